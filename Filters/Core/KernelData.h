// BRepThickness: the solver's model, samples and results in the flat arrays of the kernel source
// (Kernels/thickness.cl), in the kernel's precision T (float or double). One packing for every
// device: the OpenCL kernels (Kernels/OpenCLSolver) upload these arrays, the native device
// (NativeSolver) points its Model at them. Coordinates are relative to the model's centre
// (SolverData::Centre); anchors and sample points are split into hi + lo parts of T.
#pragma once

#include "Solver.h"

#include <array>
#include <vector>

namespace brt
{

/// Reals per sample (SAMPLE_REALS in thickness.cl): O as hi + lo parts, the inward normal, (u, v),
/// and the largest curvature of the face at O towards the normal (Sample::Curvature[0]).
constexpr size_t KernelSampleReals = 12;
/// Reals per result (OUT_REALS): t, foot - O (3), residual, the foot's parameters.
constexpr size_t KernelOutReals = 7;
/// Ints per result (OUT_INTS): type, reason, face, patch, edge, iterations, exact pass.
constexpr size_t KernelOutInts = 7;
/// Ints per face (FACE_INTS): its grid, loops, orientation, solid, exact kind, trim tree root,
/// whether its patches are its surface (PatchesAreTheSurface), and for a plane whose patches
/// are its isometric parametrisation the sign of its frame (PlaneFrame in KernelData.cxx; 0: none),
/// then the faces across its thin walls (KernelWallPartners of them, SolverData::WallPartners).
constexpr size_t KernelFaceInts = 20;
/// Faces across a face's thin walls, in its FaceInfo record (SolverData::WallPartners).
constexpr size_t KernelWallPartners = 8;
/// Reals per face (FACE_REALS): its (u, v) domain, periods and UV tolerance, its exact surface,
/// the patches' measured deviation, and last (KernelFaceTrimEdgeGap) on a plane whose patches are
/// its isometric parametrisation the measured distance between its edges and their trimming
/// segments' images at the same edge parameter (PlaneTrimEdgeGap in KernelData.cxx; 0 elsewhere),
/// then (KernelFaceLoopsCross) SolverData::FaceLoopsCross (-1 where the loops do not cross).
constexpr size_t KernelFaceReals = 22, KernelFaceTrimEdgeGap = 20, KernelFaceLoopsCross = 21;
/// Reals per trimming segment (TRIM_REALS): four (u, v) control points, then their box.
constexpr size_t KernelTrimReals = 12;
/// Reals per patch of the cylinder sectors (PATCH_SECTOR_REALS; PackKernelModel): the control
/// points' height range along the face's cylinder axis from a point of the axis next to the
/// patch, the middle direction around the axis (3), the cosine and sine of the half-angle that
/// holds them all, 1 where that sector is narrower than a half-turn (else 0, the heights alone
/// count), then that point of the axis relative to the patch's anchor (3), and one unused.
/// On a torus: the patch's arc of the tube (PackTorusArc: its ends' unit vectors, its middle,
/// the cosine of its half-span) and 1 in the same flag; the arc its domain spans on a torus
/// written as one, the arc that holds its control hull on one read from a B-spline
/// (TorusArcOfPatch); then the wedge around the axis that holds its
/// control points (PackDirectionCone: its middle direction (3) and the cosine of its half-angle,
/// 0 where none). On a sphere: zeros but for the last four, the cone from the centre that holds
/// its control points, the same way. On a face with no exact surface: the tube that holds the
/// patch (PackPatchTube: its spine's centre relative to the patch's anchor (3), axis (3), circle
/// radius, the tube's radius, the allowance, the spine's kind 1-3; zeros where none). On a cone,
/// and on a face with no exact surface and no tube whose patch turns round the axis of a
/// neighbouring cylinder, cone or torus: the piece of space around that axis that holds the
/// patch's part inside its face's trim (PackPatchAxisBox: the axis's point next to the patch's
/// anchor, relative to it (3), the axis (3), 0, the middle of the part's distances from the axis
/// and their half-spread, kind 4, its heights along the axis from that point (2)). Rounded
/// outwards to T; zeros on faces of other kinds.
constexpr size_t KernelPatchSectorReals = 12;
/// Reals per patch of its control net's constants (PATCH_HULL_REALS; the certification's
/// patch_gap): the control points' mean relative to the patch's anchor (3) and the unit normal of
/// the net's diagonals (3; zeros where they are parallel), both by the kernel source's own
/// operations in T on the control points as packed (PackPatchHull); then the least and the
/// greatest offset of the control points along that normal, rounded outwards to T, and the offset
/// of the four corners' mean; the diagonal of the box of the patch's 5 x 5 grid of points
/// (certify_patch's extent).
constexpr size_t KernelPatchHullReals = 10;
/// Segments per leaf of a face's trim tree at most (TRIM_LEAF), and the faces that get a tree:
/// those with more than KernelLinearTrims segments.
constexpr int KernelTrimLeaf = 4, KernelLinearTrims = 8;

template <class T>
struct KernelModel
{
  std::vector<T> Patches, PatchAnchor, PatchDomain, FaceDomain, Breaks, Trim, TrimRange, EdgeRange,
    EdgeSeg, EdgeAnchor, EdgeSegRange, S1Point, S1UV, NodeBox, PatchBoxes, EdgeBoxes, BoxNodeBox,
    PatchSector, PatchHull;
  std::vector<int> FaceInfo, Loops, TrimEdge, EdgeInfo, S1Face, NodeInfo, VertexInfo, PatchFace,
    EdgeSegEdge, BoxNodeInfo, BoxItems;
  /// The faces' trimming-segment trees (PackTrimTrees in KernelData.cxx): node boxes (4 per
  /// node), (First, Count, Right) per node, (segment, loop) per leaf item.
  std::vector<T> TrimNodeBox;
  std::vector<int> TrimNodeInfo, TrimItems;
  /// Whether the boxes for the certification are there (BuildPatchBoxes ran).
  bool HasBoxes() const { return !BoxNodeInfo.empty(); }
};

/// The longest chain (SolverOptions::Chain; longer ones are cut) the native device packs on its
/// stack.
constexpr int KernelMaxChain = 64;
/// SolverOptions::Chain 0, the device's own chains (ChainLength): 32 samples on a CPU (the native
/// device, an OpenCL CPU device), where a core solves chain after chain and each chain's start
/// from s1 is work saved by a longer chain (2-7% fewer instructions than chains of 8 on 19 of
/// 20 parts, NIST_MBE_PMI_11 and the hinge 5-9% less time), and 8 on a GPU, which needs the
/// work-items (docs/Solver.md, item 20).
constexpr int KernelCpuChain = 32, KernelGpuChain = 8;

/// The scalars every launch gets, from the model, its data and the options.
struct KernelScalars
{
  double Scale = 1.0;     ///< bounding-box diagonal
  double StepTol = 0.0;   ///< Newton step tolerance (model units, by precision)
  double NewtonTol = 0.0; ///< SolverOptions::NewtonTolerance
  double Slack = 0.0;     ///< the patches' accuracy: 2x the conversion tolerance
  double Clearance = 0.0; ///< SolverOptions::Clearance resolved (negative: 2x the tolerance)
  double S1Spacing = 0.0;
  int MaxIterations = 50, MaxEdgeIterations = 50;
  int Certify = 1;
  int Exterior = 0;  ///< SolverOptions::Exterior
  int AllSolids = 0; ///< SolverOptions::AllSolids
  /// The kernels' mode argument (MODE_* in Kernels/thickness.cl); hasBoxes: the certification's
  /// boxes are packed (the certification needs them).
  int Mode(bool hasBoxes) const
  {
    return (Certify && hasBoxes ? 1 : 0) | (Exterior ? 2 : 0) | (AllSolids ? 4 : 0);
  }
};

/// The exact surface of face f for the kernel's exact finish (EXACT_* in Kernels/thickness.cl;
/// returns 0 where there is none: a face that is not analytic, a model without FaceExact): its
/// origin relative to c (3; the packing splits it into hi + lo parts), 3 unused, the unit axis (3)
/// and three sizes. The origin is moved to the foot of the face's first patch anchor on the plane
/// or on the axis, so that float keeps its accuracy on a surface whose origin lies far away.
int PackExactSurface(const BRepModel& m, int f, const std::array<double, 3>& c,
  std::array<double, 12>& out);

/// What PackKernelModel leaves out. Tubes: the tubes that hold the patches of faces with no exact
/// surface (PackPatchTube) and the pieces of space around an axis that hold cones' and free-form
/// patches (PackPatchAxisBox), bounds that only spare the certification searches, so that a query
/// answers the same without them: the wall partners' probes (BuildWallPartners) pack without,
/// where fitting them was most of their packing (the small headband: 23.5 of 33.5 ms).
struct PackOptions
{
  bool Tubes = true;
};

template <class T>
KernelModel<T> PackKernelModel(const BRepModel& m, const SolverData& data,
  const PackOptions& options = PackOptions());

/// Writes data.WallPartners into k's faces (their FACE_INTS slots after the first 12), as
/// PackKernelModel does: for a model packed before BuildWallPartners ran with its solver
/// (NativeSolver::SetWallPartners). Leaves k as it is where the partners are not there.
template <class T>
void PackWallPartners(const SolverData& data, KernelModel<T>& k);

template <class T>
KernelScalars GetKernelScalars(const BRepModel& m, const SolverData& data, const SolverOptions& options);

/// Writes KernelSampleReals values of s at out.
template <class T>
void PackSample(const SolverData& data, const Sample& s, T* out);

/// Reads one kernel result into r (r reset first); returns the exact-pass flag.
template <class T>
bool UnpackResult(const Sample& s, const T* outReal, const int* outInt, SampleResult& r);

} // namespace brt
