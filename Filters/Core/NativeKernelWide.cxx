// BRepThickness: the native device's hot entry points (the solve and the ray, per sample) compiled
// a second time for the AVX2 level of x86-64-v3 (AVX, AVX2, BMI, BMI2, POPCNT: the instructions the
// run-time check asks the CPU for, and no others; no FMA), chosen at run time where the CPU has
// them (NativeKernelWide.h). The same kernel source, the same operations in the
// same order: the results are bit for bit those of the baseline build (docs/Solver.md, "The
// native device's instruction sets"); only the encoding is wider (three-operand AVX, BMI).
//
// The kernel source goes into its own namespace, kernel_v3, so that none of its functions shares
// a name with the baseline build's: an inline function compiled here with AVX2 must never be the
// copy the linker keeps for the baseline. The helpers of KernelLanguage.h and the standard headers
// are included before the target pragma, so their out-of-line copies are baseline ones too; the
// functions after it may inline them. The kernel source here takes its vector types from
// KernelLanguageWide.h (brt::kernel_wide: real2 and real3 as two- and four-lane vectors, one AVX
// instruction per operation; 9-14% faster on the Data/ parts than KernelLanguage.h's plain
// structs, which the baseline build keeps, thirty-second session). That header is included after
// the pragma: compiled for the baseline, its 32-byte operations were split into SSE halves before
// they were inlined here (the solve 16% slower than with the plain structs). Its names are this
// file's alone, so no other object holds a copy of them. FMA is left out of the target, and the
// file is compiled with -ffp-contract=off as well (Filters/Core/CMakeLists.txt): a fused
// a * b + c would round differently.
#include "NativeKernelWide.h"

#include "KernelLanguage.h"

#include <cstdlib>

#if BRT_NATIVE_WIDE

#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx,avx2,bmi,bmi2,popcnt"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx,avx2,bmi,bmi2,popcnt")
#endif

#include "KernelLanguageWide.h"

namespace brt
{
namespace kernel_v3
{
using namespace ::brt::kernel_wide;
#include "thickness.cl"

// ray_thickness from plain arrays: its real3 arguments (32-byte vectors) are made here, inside
// the target pragma, rather than passed by value from the baseline code below.
double ray_thickness_from(const Model* m, int ownFace, const double* Ohi, const double* Olo,
  const double* d, real stepTol, int* hitFace)
{
  return ray_thickness(m, ownFace, make_real3(Ohi[0], Ohi[1], Ohi[2]),
    make_real3(Olo[0], Olo[1], Olo[2]), make_real3(d[0], d[1], d[2]), stepTol, hitFace);
}
} // namespace kernel_v3
} // namespace brt

#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif

namespace brt
{
namespace
{
// Exactly the instructions of the target pragma above.
bool WideChosen()
{
  __builtin_cpu_init();
  const char* force = std::getenv("BRT_NATIVE_BASELINE");
  return !(force && *force) && __builtin_cpu_supports("avx") && __builtin_cpu_supports("avx2") &&
    __builtin_cpu_supports("bmi") && __builtin_cpu_supports("bmi2") &&
    __builtin_cpu_supports("popcnt");
}
} // namespace

bool NativeKernelWide()
{
  static const bool wide = WideChosen();
  return wide;
}

void SolveChainWide(const KernelModel<double>& K, const KernelScalars& s, int patchCount,
  const double* samples, const int* faces, int n, double* outR, int* outI)
{
  kernel_v3::solve_chain(KernelView<kernel_v3::Model>(K, s, patchCount), K.S1Point.data(),
    K.S1Face.data(), K.S1UV.data(), K.NodeBox.data(), K.NodeInfo.data(), samples, faces, n,
    s.Scale, s.StepTol, s.NewtonTol, s.MaxIterations, s.MaxEdgeIterations, outR, outI);
}

double RayThicknessWide(const KernelModel<double>& K, const KernelScalars& s, int patchCount,
  const double Ohi[3], const double Olo[3], const double d[3], int ownFace, int* hitFace)
{
  const kernel_v3::Model m = KernelView<kernel_v3::Model>(K, s, patchCount);
  return kernel_v3::ray_thickness_from(&m, ownFace, Ohi, Olo, d, s.StepTol, hitFace);
}
} // namespace brt

#else

namespace brt
{
bool NativeKernelWide()
{
  return false;
}
} // namespace brt

#endif

namespace brt
{
const char* NativeKernelBuild()
{
  return NativeKernelWide() ? "x86-64-v3" : "baseline";
}
} // namespace brt
