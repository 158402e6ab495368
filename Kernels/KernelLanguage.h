// BRepThickness: the common subset of OpenCL C and C++ the solver's kernel source is written in
// (Kernels/thickness.cl). Compiled as OpenCL C, the source gets OpenCL's own vector types and
// built-ins and this header is never read (thickness.cl includes it only outside OpenCL). Compiled
// as C++ (Filters/Core/NativeSolver.cxx: the native device and the double reference), this header
// supplies the same names in double precision: real, real2, real3 with OpenCL's arithmetic, dot,
// cross, length, normalize, clamp, the component-wise fmin/fmax, and the address-space qualifiers
// as nothing.
//
// Rules for the kernel source (docs/Solver.md, "One source"): vector values are written with
// make_real2(x, y), make_real3(x, y, z) and splat_real3(s) (never OpenCL's (real3)(x, y, z),
// which C++ would read as a cast of a comma expression); no swizzles beyond .x .y .z; no vector
// comparisons; no recursion; fixed-size arrays only; every function a plain function of plain
// structs and __global pointers.
#pragma once

#ifndef __OPENCL_VERSION__

#include <algorithm>
#include <cfloat>
#include <cmath>

// The C++ build is the double one.
#define BRT_DOUBLE 1
#define __global
#define __kernel
#define __constant const

namespace brt
{
namespace kernel
{
typedef double real;

struct real2
{
  double x, y;
};
struct real3
{
  double x, y, z;
};

inline real2 operator+(real2 a, real2 b) { return { a.x + b.x, a.y + b.y }; }
inline real2 operator-(real2 a, real2 b) { return { a.x - b.x, a.y - b.y }; }
inline real2 operator-(real2 a) { return { -a.x, -a.y }; }
inline real2 operator*(double s, real2 a) { return { s * a.x, s * a.y }; }
inline real2 operator*(real2 a, double s) { return { a.x * s, a.y * s }; }
inline real2 operator/(real2 a, double s) { return { a.x / s, a.y / s }; }

inline real3 operator+(real3 a, real3 b) { return { a.x + b.x, a.y + b.y, a.z + b.z }; }
inline real3 operator-(real3 a, real3 b) { return { a.x - b.x, a.y - b.y, a.z - b.z }; }
inline real3 operator-(real3 a) { return { -a.x, -a.y, -a.z }; }
inline real3 operator*(double s, real3 a) { return { s * a.x, s * a.y, s * a.z }; }
inline real3 operator*(real3 a, double s) { return { a.x * s, a.y * s, a.z * s }; }
inline real3 operator/(real3 a, double s) { return { a.x / s, a.y / s, a.z / s }; }

inline double dot(real2 a, real2 b) { return a.x * b.x + a.y * b.y; }
inline double dot(real3 a, real3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
#include "KernelLanguageVectorOps.inc"

using std::fabs;
using std::floor;
using std::sqrt;
// OpenCL's fmin/fmax (a NaN argument gives the other), inline: the C library's are calls.
inline double fmax(double a, double b) { return (b > a || a != a) ? b : a; }
inline double fmin(double a, double b) { return (b < a || a != a) ? b : a; }
inline real3 fmax(real3 a, real3 b) { return { fmax(a.x, b.x), fmax(a.y, b.y), fmax(a.z, b.z) }; }
inline real3 fmin(real3 a, real3 b) { return { fmin(a.x, b.x), fmin(a.y, b.y), fmin(a.z, b.z) }; }
// OpenCL's max/min for reals (y where x < y, resp. y < x; undefined for a NaN): one instruction,
// where fmax/fmin need a NaN test. The kernel uses them in bounds only (boxes, hulls).
inline double max(double x, double y) { return x < y ? y : x; }
inline double min(double x, double y) { return y < x ? y : x; }
inline real3 max(real3 a, real3 b) { return { max(a.x, b.x), max(a.y, b.y), max(a.z, b.z) }; }
inline real3 min(real3 a, real3 b) { return { min(a.x, b.x), min(a.y, b.y), min(a.z, b.z) }; }
inline double clamp(double x, double lo, double hi) { return fmin(fmax(x, lo), hi); }
inline int clamp(int x, int lo, int hi) { return std::min(std::max(x, lo), hi); }
} // namespace kernel
} // namespace brt

// Unqualified: the kernel source's namespace says which real2 and real3 (brt::kernel's, or
// KernelLanguageWide.h's brt::kernel_wide for the x86-64-v3 build).
#define make_real2(a, b) (real2{ (double)(a), (double)(b) })
#define make_real3(a, b, c) (real3{ (double)(a), (double)(b), (double)(c) })
#define splat_real3(s) make_real3((s), (s), (s))
#define splat_real2(s) make_real2((s), (s))
#define REAL_MAX DBL_MAX
#define REAL_MIN DBL_MIN
#define REAL_EPS DBL_EPSILON

#endif
