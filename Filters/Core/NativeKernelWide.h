// BRepThickness: the native device's kernel source compiled twice, for the x86-64 baseline
// (NativeSolver.cxx) and for the AVX2 level of x86-64-v3 (AVX, AVX2, BMI, BMI2, POPCNT; no FMA:
// NativeKernelWide.cxx), the second used where the CPU has those instructions. Both give the same results bit for bit (no FMA contraction);
// the wider one is faster (docs/Solver.md, "The native device's instruction sets"). Internal to
// the native device.
#pragma once

#include "KernelData.h"

namespace brt
{
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define BRT_NATIVE_WIDE 1
#else
#define BRT_NATIVE_WIDE 0
#endif

/// The kernel source's Model (Kernels/thickness.cl) over a packed model, for either build of the
/// source (their Models are the same struct in two namespaces).
template <class Model>
Model KernelView(const KernelModel<double>& K, const KernelScalars& s, int patchCount)
{
  return Model{ K.Patches.data(), K.PatchAnchor.data(), K.PatchDomain.data(), K.FaceInfo.data(),
    K.FaceDomain.data(), K.Breaks.data(), K.Loops.data(), K.Trim.data(), K.TrimEdge.data(),
    K.TrimRange.data(), K.TrimNodeBox.data(), K.TrimNodeInfo.data(), K.TrimItems.data(),
    K.EdgeInfo.data(), K.EdgeRange.data(), K.EdgeSeg.data(), K.EdgeAnchor.data(),
    K.EdgeSegRange.data(), K.VertexInfo.data(), s.Slack, s.Clearance, s.S1Spacing,
    K.PatchFace.data(), K.EdgeSegEdge.data(), K.PatchBoxes.data(), K.PatchSector.data(),
    K.PatchHull.data(), K.EdgeBoxes.data(), K.BoxNodeBox.data(), K.BoxNodeInfo.data(), K.BoxItems.data(), patchCount,
    s.Mode(K.HasBoxes()), nullptr };
}

/// True where the native device runs the wide build: this CPU has AVX, AVX2, BMI, BMI2 and POPCNT
/// and the environment variable BRT_NATIVE_BASELINE is unset or empty. Decided once per process.
bool NativeKernelWide();
/// That build's name: "x86-64-v3" (the wide one) or "baseline".
const char* NativeKernelBuild();

#if BRT_NATIVE_WIDE
/// solve_chain of the x86-64-v3 build (call only where NativeKernelWide()): n packed samples and
/// their faces, results in KernelOutReals and KernelOutInts per sample.
void SolveChainWide(const KernelModel<double>& K, const KernelScalars& s, int patchCount,
  const double* samples, const int* faces, int n, double* outR, int* outI);
/// ray_thickness of the x86-64-v3 build; Ohi, Olo, d as the kernel takes them.
double RayThicknessWide(const KernelModel<double>& K, const KernelScalars& s, int patchCount,
  const double Ohi[3], const double Olo[3], const double d[3], int ownFace, int* hitFace);
#endif
} // namespace brt
