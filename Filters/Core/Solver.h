// BRepThickness: the maximal-sphere solver (Lemasson et al. 2014, sections 2.1-2.3): its types,
// options, and the host-only preparation (s1, the BVHs, the samples). VTK-free and OpenCL-free.
// The solve itself is written once, in Kernels/thickness.cl, and runs as OpenCL kernels
// (Kernels/OpenCLSolver) or compiled as C++ on the CPU (NativeSolver, the reference).
#pragma once

#include "BRepModel.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

namespace brt
{

/// One thickness sample O (set s0): a point on a face with the inward unit normal d.
struct Sample
{
  int Face = -1;
  double U = 0.0, V = 0.0;
  std::array<double, 3> Point{};
  std::array<double, 3> Direction{}; ///< inward unit normal (into the material)
  /// The principal curvatures of the face's exact surface at O, the largest first, positive
  /// where the face bends towards Direction (towards the sphere's centre); zeros where not known.
  /// No sphere tangent at O is inside the material beyond radius 1 / Curvature[0]: the solver
  /// bounds it there (the osculating sphere, docs/Solver.md).
  std::array<double, 2> Curvature{};
};

/// The sample seen from the other side of its face: Direction and Curvature reversed (the
/// exterior gap's samples).
inline void ReverseSample(Sample& s)
{
  for (double& c : s.Direction)
    c = -c;
  const double largest = s.Curvature[0];
  s.Curvature[0] = -s.Curvature[1];
  s.Curvature[1] = -largest;
}

enum class ContactType : int
{
  Failed = 0,
  SurfaceSurface = 1, ///< tangent to O's face and to an opposite face inside its trim
  SurfaceEdge = 2,    ///< tangent to O's face and touching an edge (eq. 7)
  SurfaceVertex = 3,  ///< the edge Newton ran into an end of the edge: touches that vertex
  /// The gap with all solids (SolverOptions::Exterior and AllSolids) only: O lies on or inside
  /// another solid, which touches or overlaps its own there. The gap is 0 (radius 0, the centre
  /// and the foot at O); OppositeFace is the other solid's face that the test's rays left it by.
  OtherSolid = 4,
  /// The sphere osculates O's own face at O: the face's largest curvature there towards the
  /// material (Sample::Curvature) bounds it, radius 1 / curvature, and nothing else does (the
  /// tip of a rounded wall end more curved than the wall is thick: a medial-axis end). The foot
  /// is O itself; OppositeFace is O's face.
  Osculating = 5
};
const char* ContactTypeName(ContactType type);

enum class FailReason : int
{
  None = 0,
  NoOppositePoint = 1,  ///< no s1 point lies in front of O (open shell, or sampling too coarse)
  NotConverged = 2,     ///< surface/surface Newton did not reach the tolerance
  EdgeNotConverged = 3, ///< surface/edge Newton did not reach the tolerance
  NoEdge = 4,           ///< the foot point left the face across a degenerated edge (pole)
  Singular = 5,         ///< singular Jacobian
  LeftModel = 6,        ///< the sphere touches a face from outside or only at the sample
                        ///< itself, or its radius is not positive or larger than the model
  NotMaximal = 7,       ///< the sphere found contains s1 points and no restart shrank it
  // Set after the solve by CheckResults (ResultCheck.h), never by the kernels:
  OpenShell = 8,        ///< the sample's solid is an open shell: it has no inside
  NonManifold = 9,      ///< the sample's solid is non-manifold (a fin, bodies touching at an edge)
  Unbounded = 10,       ///< thickness not finite or beyond its solid's bounding-box diagonal
  // Set by the kernels again:
  ThinWall = 11,        ///< the wall across the sample (along its normal) is thinner than 4
                        ///< conversion tolerances, below what the patches resolve
  // Set after the solve by CheckResults again:
  FileGap = 12          ///< the sample or its contact lies where the file's faces and edges miss
                        ///< each other (BRepModel::LooseVertices, LooseFaces): the geometry
                        ///< there is not the part's
};
const char* FailReasonName(FailReason reason);

struct SampleResult
{
  double Thickness = 0.0; ///< 2t
  double Radius = 0.0;    ///< t
  std::array<double, 3> Center{}; ///< M = O + t d, a medial-axis sample
  std::array<double, 3> Foot{};   ///< the contact point P on the opposite face or edge
  int OppositeFace = -1;
  int OppositePatch = -1; ///< surface/surface contacts
  int OppositeEdge = -1;  ///< surface/edge and surface/vertex contacts
  /// Where the foot point lies: (u, v) on OppositeFace for surface/surface contacts, (T, 0) on
  /// OppositeEdge for surface/edge and surface/vertex contacts. (An edge contact typed
  /// surface/surface at a tangent edge gets the trimming curve's point at T, a few 1e-3 mm along
  /// the edge from Foot at most.)
  std::array<double, 2> FootParameter{};
  ContactType Type = ContactType::Failed;
  FailReason Reason = FailReason::None;
  /// |R| of the last Newton system (eq. 4 or eq. 7) in model units: the tangential equations
  /// are divided by the tangent lengths, S_u.(S-M)/|S_u|, so every component is a distance.
  double Residual = 0.0;
  int Iterations = 0;    ///< Newton iterations, surface and edge together
};

struct SolverOptions
{
  /// Spacing of the coarse sample set s1 on every patch (model units), and a third of it along
  /// the edges; <= 0 picks 1/150 of the bounding-box diagonal on the patches and a third of 1/300
  /// of it along the edges. Each patch gets between 2x2 and S1MaxPerPatch^2 candidates.
  double S1Spacing = 0.0;
  int S1MaxPerPatch = 64;
  /// A Newton result is accepted when |R| (SampleResult::Residual) is at most this (model units).
  double NewtonTolerance = 1e-4;
  int MaxIterations = 50;     ///< surface/surface Newton (eq. 4)
  int MaxEdgeIterations = 50; ///< surface/edge Newton (eq. 7)
  /// Boundary points less than this deep inside a sphere do not limit it (model units): the
  /// solver finds the largest sphere tangent at O that nothing enters deeper than the clearance
  /// (docs/Solver.md). Negative: 2x the model's conversion tolerance. 0: eq. 1 exactly. A sample
  /// that fails with a clearance is solved again without one.
  double Clearance = -1.0;
  /// Check every sphere against the patches themselves, not only s1: the centre is projected on
  /// every patch of the sample's solid that reaches into the sphere, and a point of the trimmed
  /// faces deeper inside than the clearance restarts the solve from it (docs/Solver.md,
  /// "Certified emptiness"). Off only to measure what it costs and buys.
  bool Certify = true;
  /// The exterior gap instead of the thickness (issue 16, docs/Solver.md "Exterior gap"): the
  /// samples' Direction is the outward normal, and the sphere grows into the air, touching
  /// faces from their outer side. A sample that no wall faces (nothing in front of it) fails with
  /// NoOppositePoint: its gap is infinite.
  bool Exterior = false;
  /// Walls of every solid bound the sphere (the clearance between the solids of an assembly),
  /// not only those of the sample's own solid.
  bool AllSolids = false;
  /// Samples solved in a row by one thread or work-item (1 to 64): each face's samples, in
  /// SpatialOrder, fall into chains of this many (ChainStarts), and each sample of a chain after
  /// its first starts from its predecessor's contact across instead of eq. 1's walk over s1
  /// (docs/Solver.md, item 20, "Chains"). Every thread count, and every device of a kind, solves
  /// a sample from the same start. 1: every sample from s1; 0: the device's (ChainLength: 32 on
  /// a CPU, 8 on a GPU).
  int Chain = 0;
};

/// s1 point: a point of a trimmed face with its patch and face parameters.
struct S1Point
{
  std::array<double, 3> Point{};
  int Face = -1;
  /// Sampled along an edge (verification only: an edge point never starts a solve, it only
  /// shows a sphere cut by a corner narrower than the patch grid's spacing).
  bool OnEdge = false;
  double U = 0.0, V = 0.0;
};

/// Node of the AABB BVH over s1, flattened depth first: an inner node's left child follows it,
/// its right child is at Right. A leaf holds the s1 points [First, First + Count), all on one
/// solid's faces. The first splits separate the solids; an inner node whose subtree lies on one
/// solid has Count = -(solid + 1), one over several solids Count = 0. An inner node's First is
/// the face all its points lie on (-1: several), so that a walk that leaves a face out skips
/// its subtrees whole. Where s1 has points on
/// faces and along edges, the root splits them first: its First is S1SplitRoot, its left subtree
/// holds the faces' points (all eq. 1 starts from) and its right one the edges' (the verification
/// next to the certification checks only those; thickness.cl, verify_s1).
constexpr int S1SplitRoot = -2;
struct BVHNode
{
  std::array<double, 3> Min{}, Max{};
  int First = 0, Count = 0; ///< Count > 0: leaf; <= 0: inner (-(solid + 1) or 0, see above)
  int Right = -1;
};

/// Everything the solver needs besides the model, built once on the host.
struct SolverData
{
  std::vector<S1Point> S1;
  std::vector<BVHNode> Nodes;
  double Scale = 1.0; ///< bounding-box diagonal of the model
  double S1Spacing = 0.0; ///< the spacing s1's face points were sampled at (SolverOptions::S1Spacing or its default)
  std::array<double, 3> Centre{};
  /// Per face: the patch grid breakpoints (NU+1 u values then NV+1 v values), at FaceBreaks[f].
  std::vector<double> Breaks;
  std::vector<int> FaceBreaks;
  /// Vertices: edge ends that meet (within 10x the conversion tolerance), not stored in solve
  /// files (BuildVertices derives them from the model). VertexInfo[2 e + k] is the record of the
  /// vertex at edge e's end k (0: T0, 1: T1), -1 where the edge has no segments; a record at
  /// offset r holds its end count n at VertexInfo[r], then n ends, each 2 * edge + k. The OpenCL
  /// kernels get the same array.
  std::vector<int> VertexInfo;
  /// Per patch: the box of its control points (min x, y, z, max x, y, z), which holds the patch.
  /// Derived like VertexInfo (BuildPatchBoxes), not stored in solve files.
  std::vector<double> PatchBoxes;
  /// Per patch: the part of its (local, [0, 1]^2) parameters that holds its part inside its
  /// face's trim, as s0, s1, r0, r1 (TrimmedPatchBox's UV box; 0, 1, 0, 1 where that is the whole
  /// patch). Derived like PatchBoxes.
  std::vector<double> PatchTrimBox;
  /// The same per edge segment (its 4 control points).
  std::vector<double> EdgeBoxes;
  /// Per edge, for each of its two faces: how far its segments lie from that face's exact surface
  /// (plane, cylinder, cone, sphere, torus), half as much again as measured at 17 points of each
  /// segment, for the certification's bound on the edge (thickness.cl, find_point_inside); -1
  /// where the face has no exact surface or there is no face. Derived like PatchBoxes.
  std::vector<double> EdgeFaceDeviation;
  /// BVH over those boxes (same node layout as Nodes); BoxItems[First .. First + Count) of a
  /// leaf are patch indices, or edge segment indices offset by the number of patches. An inner
  /// node's First is the face whose patches are all its subtree's items (-1: none such).
  std::vector<BVHNode> BoxNodes;
  std::vector<int> BoxItems;
  /// Per face, KernelWallPartners (8) faces across its thin walls, the most found first (-1:
  /// none): the starts of wall_partner_start where s1 is much coarser than the wall
  /// (BuildWallPartners; derived like PatchBoxes).
  std::vector<int> WallPartners;
  /// Per face, TrimLoopsCross: -1 where its trimming loops do not cross, else a bound on the
  /// crossing test's chords' error; the kernel's trim test takes the crossing parity on such a
  /// face (BuildLoopCrossings; derived like PatchBoxes).
  std::vector<double> FaceLoopsCross;
};

/// Fills data.FaceLoopsCross (TrimLoopsCross of every face; PrepareSolver and ReadSolve call it).
void BuildLoopCrossings(const BRepModel& model, SolverData& data);

/// Fills data.WallPartners: a 4 x 4 grid of points over each face's (u, v) bounds, where inside
/// its trim, probe the wall across by the certification's query for the deepest point of the
/// faces inside the sphere of diameter S1Spacing / 4 tangent there (NativeSolver::WallWithin). A
/// face's partners are the other faces its probes find, or whose probes find it, the most found
/// first (ties to the lower index), eight at most. Needs the patches' boxes (PrepareSolver and
/// ReadSolve call it).
void BuildWallPartners(const BRepModel& model, SolverData& data);

class NativeSolver;
/// BuildWallPartners with the probes run on `solver`, made from model and data before (their
/// partners then -1; the same answers as the probes' own packing, which leaves out s1 and the
/// tubes: neither changes the query's answers). NativeSolver::SetWallPartners then copies them
/// into its packed model: one packing of the model for the probes and the solve.
void BuildWallPartners(const BRepModel& model, SolverData& data, const NativeSolver& solver);

/// Fills data.PatchBoxes, data.EdgeBoxes, their BVH and data.EdgeFaceDeviation (PrepareSolver
/// and ReadSolve call it).
void BuildPatchBoxes(const BRepModel& model, SolverData& data);

/// The control points of the patch restricted to the local parameter box (s0, s1, r0, r1 in
/// [0, 1], as SolverData::PatchTrimBox), by de Casteljau.
std::array<double, 48> RestrictedControlPoints(const BezierPatch& patch, const double* box);

/// Fills data.VertexInfo from the model's edges (PrepareSolver and ReadSolve call it).
void BuildVertices(const BRepModel& model, SolverData& data);

/// The solver's data (s1, the trees, the boxes, the wall partners...). partners false: the wall
/// partners are left at -1, for BuildWallPartners(model, data, solver) with the solver that will
/// solve (the filter's native device).
SolverData PrepareSolver(
  const BRepModel& model, const SolverOptions& options, bool partners = true);

/// s0 = the display mesh vertices, with the inward normal (minus the outward normal). Vertices on
/// a face's boundary are moved a tiny step into the face (see the implementation).
std::vector<Sample> SamplesFromMesh(const BRepModel& model, const SolverData& data);

/// The indices of the samples to solve (which, or 0..n-1 where null) in the order the solvers
/// take them: by face, and within a face along a Morton curve over the face's samples' bounding
/// box (10 bits per axis), the given order kept within a cell.
/// Neighbouring samples walk the same nodes of the trees; in the mesh's order they took 6-13%
/// longer on the native device, shuffled 1.3-1.8 times as long (docs/Solver.md, Host layer,
/// "Sample order").
std::vector<size_t> SpatialOrder(const std::vector<Sample>& samples, const std::vector<size_t>* which);

/// The chains (SolverOptions::Chain) in `order` (SpatialOrder's): the positions where they start,
/// then order.size(). Each face's run is cut every `chain` samples from its first, so a face's
/// chains depend on its own samples alone (not on the other faces solved with them, as in a
/// process's piece of the faces under MPI).
std::vector<size_t> ChainStarts(const std::vector<Sample>& samples,
  const std::vector<size_t>& order, int chain);

/// The chains' length a device solves `options` with: SolverOptions::Chain, or where that is 0
/// KernelGpuChain on a GPU and KernelCpuChain elsewhere; within 1..KernelMaxChain.
int ChainLength(const SolverOptions& options, bool gpu);

/// The solver's reference: steps 3-8 (docs/Solver.md) for every sample, by the native device
/// (NativeSolver: the kernel source compiled as C++ in double) on `threads` threads (0: one per
/// core); results[i] is samples[i]'s. Packs the model on every call: a caller solving in several
/// calls keeps a NativeSolver instead.
void SolveReference(const BRepModel& model, const SolverData& data, const SolverOptions& options,
  const std::vector<Sample>& samples, std::vector<SampleResult>& results, unsigned threads = 0);

/// Calls f(i) for i in [0, n) on `threads` threads (0: one per core), the indices dealt out in
/// turn.
template <class F>
void ParallelFor(size_t n, unsigned threads, F&& f)
{
  if (threads == 0)
    threads = std::max(1u, std::thread::hardware_concurrency());
  threads = static_cast<unsigned>(std::min<size_t>(threads, n));
  std::vector<std::thread> pool;
  for (unsigned k = 0; k < threads; ++k)
    pool.emplace_back([&, k] {
      for (size_t i = k; i < n; i += threads)
        f(i);
    });
  for (auto& t : pool)
    t.join();
}

/// Calls f(i) for i in [0, n) on `threads` threads (0: one per core), the calling thread one of
/// them: each takes the next `block` indices in turn, so that no thread waits while another has
/// work left. Between its blocks the calling thread calls progress(done), done the indices
/// finished so far; progress returning false stops the loop (the indices not yet taken are left
/// undone). The calling thread runs the first block before the others start, so progress is
/// called at least once (where n > 0) however the threads are scheduled. Returns false where
/// stopped.
template <class F, class P>
bool ParallelForWithProgress(size_t n, unsigned threads, size_t block, F&& f, P&& progress)
{
  if (threads == 0)
    threads = std::max(1u, std::thread::hardware_concurrency());
  block = std::max<size_t>(1, block);
  threads = static_cast<unsigned>(std::max<size_t>(1, std::min<size_t>(threads, (n + block - 1) / block)));
  std::atomic<size_t> next{ 0 }, done{ 0 };
  std::atomic<bool> stop{ false };
  // The next block; false where none is left, else the indices finished so far in `finished`.
  auto one = [&](size_t& finished) {
    const size_t first = next.fetch_add(block);
    if (first >= n)
      return false;
    const size_t last = std::min(n, first + block);
    for (size_t i = first; i < last; ++i)
      f(i);
    finished = done.fetch_add(last - first) + (last - first);
    return true;
  };
  auto work = [&](bool caller) {
    size_t finished = 0;
    while (!stop.load(std::memory_order_relaxed) && one(finished))
      if (caller && !progress(finished))
      {
        stop = true;
        return;
      }
  };
  // Under load a worker could otherwise take every block before the caller gets one: no
  // progress at all, and no stop (Parallel.BlocksEveryIndexOnceAndStops failed so once).
  size_t first = 0;
  if (one(first) && !progress(first))
    return false;
  std::vector<std::thread> pool;
  for (unsigned k = 1; k < threads; ++k)
    pool.emplace_back(work, false);
  work(true);
  for (auto& t : pool)
    t.join();
  return !stop;
}

/// Builds the BVH over s1 (data.Nodes, reordering data.S1; see BVHNode): PrepareSolver and
/// ReadSolve call it.
void BuildS1Tree(const BRepModel& model, SolverData& data);

/// Patch of `face` containing (u,v), by binary search on the face's grid breakpoints.
int FindPatchFast(const BRepModel& model, const SolverData& data, int face, double u, double v);

} // namespace brt
