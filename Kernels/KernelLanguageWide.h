// BRepThickness: the kernel language's vector types as vectors, for the native device's x86-64-v3
// build (Filters/Core/NativeKernelWide.cxx). KernelLanguage.h gives real2 and real3 as plain
// structs of doubles, which every build of C++ compiles well; here they are what OpenCL's double2
// and double3 are, vectors of two and four lanes (a double3 has four, the fourth unused), so that
// their arithmetic is one AVX instruction instead of three scalar ones. The same operations in
// the same order, lane by lane (dot sums x, y, z in that order, as KernelLanguage.h does; no FMA):
// the results are those of the plain build bit for bit (docs/Solver.md, "The native device's
// instruction sets"). The fourth lane is kept 0 and read by nothing.
//
// Only for a translation unit compiled for AVX: in a baseline (SSE2) build 32-byte vectors are
// split in two and passed through memory, and the solve ran at half the speed of the plain structs
// (measured, thirty-second session). GCC's and clang's vector extensions; the names live in
// brt::kernel_wide, and the kernel source compiled with them takes that namespace instead of
// brt::kernel.
#pragma once

#include "KernelLanguage.h"

#if !defined(__OPENCL_VERSION__) && (defined(__GNUC__) || defined(__clang__))

namespace brt
{
namespace kernel_wide
{
typedef double real;
typedef double real2v __attribute__((vector_size(16)));
typedef double real4v __attribute__((vector_size(32)));

// .x .y .z name the lanes through an anonymous struct in the union (an extension of both
// compilers; the kernel source only reads them).
#if defined(__clang__)
#pragma clang diagnostic push
#pragma clang diagnostic ignored "-Wnested-anon-types"
#pragma clang diagnostic ignored "-Wgnu-anonymous-struct"
#endif
struct real2
{
  union
  {
    real2v v;
    __extension__ struct
    {
      double x, y;
    };
  };
  real2()
    : v{ 0.0, 0.0 }
  {
  }
  real2(double a, double b)
    : v{ a, b }
  {
  }
  explicit real2(real2v w)
    : v(w)
  {
  }
};

struct real3
{
  union
  {
    real4v v;
    __extension__ struct
    {
      double x, y, z, unused;
    };
  };
  real3()
    : v{ 0.0, 0.0, 0.0, 0.0 }
  {
  }
  real3(double a, double b, double c)
    : v{ a, b, c, 0.0 }
  {
  }
  explicit real3(real4v w)
    : v(w)
  {
  }
};
#if defined(__clang__)
#pragma clang diagnostic pop
#endif

// Lane by lane; the fourth lane of a real3: 0 + 0, 0 * s, 0 / s (s is never 0 where the kernel
// divides a vector).
#define BRT_LANE_OPERATORS(T)                                                                    \
  inline T operator+(T a, T b) { return T(a.v + b.v); }                                         \
  inline T operator-(T a, T b) { return T(a.v - b.v); }                                         \
  inline T operator-(T a) { return T(-a.v); }                                                   \
  inline T operator*(double s, T a) { return T(s * a.v); }                                      \
  inline T operator*(T a, double s) { return T(a.v * s); }                                      \
  inline T operator/(T a, double s) { return T(a.v / s); }
BRT_LANE_OPERATORS(real2)
BRT_LANE_OPERATORS(real3)
#undef BRT_LANE_OPERATORS

inline double dot(real2 a, real2 b)
{
  const real2v p = a.v * b.v;
  return p[0] + p[1];
}
inline double dot(real3 a, real3 b)
{
  const real4v p = a.v * b.v;
  return p[0] + p[1] + p[2];
}
#include "KernelLanguageVectorOps.inc"

using std::fabs;
using std::floor;
using std::sqrt;
using ::brt::kernel::clamp;
using ::brt::kernel::fmax;
using ::brt::kernel::fmin;
using ::brt::kernel::max;
using ::brt::kernel::min;
// Lane by lane as KernelLanguage.h's: fmax/fmin give the other argument for a NaN, max/min are
// OpenCL's (y where x < y, resp. y < x).
inline real3 fmax(real3 a, real3 b) { return real3(((b.v > a.v) | (a.v != a.v)) ? b.v : a.v); }
inline real3 fmin(real3 a, real3 b) { return real3(((b.v < a.v) | (a.v != a.v)) ? b.v : a.v); }
inline real3 max(real3 a, real3 b) { return real3(a.v < b.v ? b.v : a.v); }
inline real3 min(real3 a, real3 b) { return real3(b.v < a.v ? b.v : a.v); }
} // namespace kernel_wide
} // namespace brt

#endif
