#include "Solver.h"

#include "Bezier.h"
#include "KernelData.h"
#include "NativeSolver.h"
#include "TrimClassifier.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <thread>

namespace brt
{

const char* ContactTypeName(ContactType type)
{
  switch (type)
  {
    case ContactType::SurfaceSurface: return "surface/surface";
    case ContactType::SurfaceEdge: return "surface/edge";
    case ContactType::SurfaceVertex: return "surface/vertex";
    case ContactType::OtherSolid: return "on or in another solid";
    case ContactType::Osculating: return "osculating";
    case ContactType::Failed: break;
  }
  return "failed";
}

const char* FailReasonName(FailReason reason)
{
  switch (reason)
  {
    case FailReason::None: return "none";
    case FailReason::NoOppositePoint: return "no opposite point";
    case FailReason::NotConverged: return "surface/surface Newton did not converge";
    case FailReason::EdgeNotConverged: return "surface/edge Newton did not converge";
    case FailReason::NoEdge: return "foot point left the face across a degenerated edge";
    case FailReason::Singular: return "singular Jacobian";
    case FailReason::LeftModel: return "sphere leaves the model (touches a face from outside or only at the sample, or radius not positive or larger than the model)";
    case FailReason::NotMaximal: return "sphere not maximal (contains s1 points; no restart shrank it)";
    case FailReason::OpenShell: return "the sample's solid is an open shell";
    case FailReason::NonManifold: return "the sample's solid is non-manifold";
    case FailReason::Unbounded: return "thickness not finite or beyond the solid's bounding-box diagonal";
    case FailReason::ThinWall: return "wall across thinner than 4 conversion tolerances (read the model at a finer tolerance; at a knife edge, or where the face folds over so that its normal points out of the part, no tolerance resolves it)";
    case FailReason::FileGap: return "the file's faces and edges do not agree here (a vertex or face moved off its edges, a face its edges do not enclose, or faces lying on one another)";
  }
  return "unknown";
}

namespace
{
using Vec3 = std::array<double, 3>;
inline Vec3 Sub(const Vec3& a, const Vec3& b)
{
  return { a[0] - b[0], a[1] - b[1], a[2] - b[2] };
}
inline double Dot(const Vec3& a, const Vec3& b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// --- BVH -------------------------------------------------------------------------------------
// Over several solids the first splits separate the solids (at the solid boundary nearest the
// middle), so that every subtree below them lies on one solid's faces: an inner node records
// that solid as Count = -(solid + 1), and a solve bounded by its own solid's walls (the exterior
// gap's default) skips the other solids' subtrees whole. The points come sorted by solid
// (BuildS1Tree), so every range split so is still sorted. Within one solid the split is
// spatial. The upper levels build their right subtree on a thread of its own (parallel > 0, the
// levels left to split so; subtrees of 20,000 points and more): into a vector of its own,
// appended after the left subtree with its Right indices moved, so that the tree is the one the
// serial build gives. *face: the face all the subtree's points lie on, or -1 (an inner node's
// First, from its children's).
int Build(std::vector<S1Point>& pts, std::vector<BVHNode>& nodes, int first, int count,
  const std::vector<int>& faceSolid, int parallel, bool oneSolidKnown, int* face)
{
  const int id = static_cast<int>(nodes.size());
  nodes.emplace_back();
  BVHNode node;
  node.Min = { std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
    std::numeric_limits<double>::max() };
  node.Max = { -node.Min[0], -node.Min[1], -node.Min[2] };
  auto solidOf = [&](const S1Point& p) {
    return p.Face >= 0 && p.Face < static_cast<int>(faceSolid.size()) ? faceSolid[p.Face] : -1;
  };
  for (int i = first; i < first + count; ++i)
    for (int k = 0; k < 3; ++k)
    {
      node.Min[k] = std::min(node.Min[k], pts[i].Point[k]);
      node.Max[k] = std::max(node.Max[k], pts[i].Point[k]);
    }
  // Sorted by solid: one solid where the first and the last point share it. Below a node on one
  // solid every node is.
  const int solid = count > 0 ? solidOf(pts[first]) : -1;
  const bool oneSolid = oneSolidKnown || count == 0 || solidOf(pts[first + count - 1]) == solid;
  if (oneSolid && count <= 16)
  {
    node.First = first;
    node.Count = count;
    nodes[id] = node;
    *face = count > 0 ? pts[first].Face : -1;
    for (int i = first + 1; i < first + count && *face >= 0; ++i)
      if (pts[i].Face != *face)
        *face = -1;
    return id;
  }
  int half = count / 2;
  if (!oneSolid)
  {
    // The solid boundary nearest the middle.
    int best = -1;
    for (int i = first + 1; i < first + count; ++i)
      if (solidOf(pts[i]) != solidOf(pts[i - 1]) &&
        (best < 0 || std::abs(i - first - half) < std::abs(best - first - half)))
        best = i;
    half = best - first;
  }
  else
  {
    int axis = 0;
    for (int k = 1; k < 3; ++k)
      if (node.Max[k] - node.Min[k] > node.Max[axis] - node.Min[axis])
        axis = k;
    std::nth_element(pts.begin() + first, pts.begin() + first + half, pts.begin() + first + count,
      [axis](const S1Point& a, const S1Point& b) { return a.Point[axis] < b.Point[axis]; });
  }
  node.Count = oneSolid && solid >= 0 ? -(solid + 1) : 0;
  int leftFace = -1, rightFace = -1;
  if (parallel > 0 && count >= 20000)
  {
    std::vector<BVHNode> right;
    std::thread other([&] {
      Build(pts, right, first + half, count - half, faceSolid, parallel - 1, oneSolid, &rightFace);
    });
    Build(pts, nodes, first, half, faceSolid, parallel - 1, oneSolid, &leftFace);
    other.join();
    const int base = static_cast<int>(nodes.size());
    for (BVHNode& n : right)
      if (n.Right >= 0)
        n.Right += base;
    nodes.insert(nodes.end(), right.begin(), right.end());
    node.Right = base;
  }
  else
  {
    Build(pts, nodes, first, half, faceSolid, parallel, oneSolid, &leftFace);
    node.Right =
      Build(pts, nodes, first + half, count - half, faceSolid, parallel, oneSolid, &rightFace);
  }
  // An inner node's First: the face all its points lie on, or -1.
  node.First = leftFace == rightFace ? leftFace : -1;
  *face = node.First;
  nodes[id] = node;
  return id;
}

/// Point and derivatives of an edge at edge parameter T (clamped to the edge).
/// Point and first derivative of an edge at edge parameter T (clamped to the edge).
struct EdgeEval
{
  Vec3 C, Ct, Ctt;
};
EdgeEval EvaluateEdge(const BRepModel& m, int edge, double T)
{
  const Edge& E = m.Edges[edge];
  int s = E.FirstSegment;
  while (s < E.FirstSegment + E.SegmentCount - 1 && T > m.EdgeSegments[s].T1)
    ++s;
  const EdgeSegment& seg = m.EdgeSegments[s];
  const double span = seg.T1 - seg.T0;
  const auto e = EvaluateCubic<3>(seg.ControlPoints.data(), (T - seg.T0) / span);
  const double s2 = span * span;
  return { e.P, { e.D1[0] / span, e.D1[1] / span, e.D1[2] / span },
    { e.D2[0] / s2, e.D2[1] / s2, e.D2[2] / s2 } };
}

/// The trimming segments of `face` on `edge`, in its loops' order.
std::vector<int> FaceSegmentsOnEdge(const BRepModel& m, int face, int edge)
{
  std::vector<int> list;
  const Face& F = m.Faces[face];
  for (int l = F.FirstLoop; l < F.FirstLoop + F.LoopCount; ++l)
  {
    const TrimLoop& loop = m.Loops[l];
    for (int s = loop.FirstSegment; s < loop.FirstSegment + loop.SegmentCount; ++s)
      if (m.TrimSegments[s].Edge == edge)
        list.push_back(s);
  }
  return list;
}

/// (u, v) on a face of the point at edge parameter T of an edge: on the first of that face's
/// trimming segments on the edge (`onEdge`, FaceSegmentsOnEdge's list) that covers T; false
/// where none does. The list is made once per edge (AddEdgePoints): scanned per point, a face
/// with many holes (a perforated card guide's plates, thousands of segments each) made s1's edge
/// points 28% of its preparation.
bool EdgePointOnFace(
  const BRepModel& m, const std::vector<int>& onEdge, double T, double& u, double& v)
{
  for (const int s : onEdge)
  {
    const TrimSegment& ts = m.TrimSegments[s];
    const double lo = std::min(ts.T0, ts.T1), hi = std::max(ts.T0, ts.T1);
    if (T < lo || T > hi || hi <= lo)
      continue;
    const auto e = EvaluateCubic<2>(ts.ControlPoints.data(), (T - ts.T0) / (ts.T1 - ts.T0));
    u = e.P[0];
    v = e.P[1];
    return true;
  }
  return false;
}

/// s1 along the edges, `spacing` apart (by each cubic segment's control polygon), on the first
/// face of each edge. A convex edge can cut into a sphere over a cap narrower than the spacing of
/// the patch grid, between its points (a 0.36 mm sphere on the FRAMEWORK tile 0.009 mm into the
/// corner of a wall, over 0.16 mm of the edge): the verification then passed a sphere that is
/// not maximal. Edge points are what such a corner exposes first.
void AddEdgePoints(const BRepModel& m, double spacing, std::vector<S1Point>& s1)
{
  // Each edge's points on every core, then appended in the edges' order.
  std::vector<std::vector<S1Point>> perEdge(m.Edges.size());
  ParallelFor(m.Edges.size(), 0, [&](size_t e) {
    const int edge = static_cast<int>(e);
    const Edge& E = m.Edges[e];
    const int face = E.Faces[0];
    if (face < 0 || m.Faces[face].PatchCount == 0)
      return;
    std::vector<S1Point>& out = perEdge[e];
    // The face's segments on the edge listed once (a face with many holes has thousands).
    const std::vector<int> onEdge = FaceSegmentsOnEdge(m, face, edge);
    for (int k = E.FirstSegment; k < E.FirstSegment + E.SegmentCount; ++k)
    {
      const EdgeSegment& seg = m.EdgeSegments[k];
      double length = 0.0;
      for (int i = 0; i < 3; ++i)
      {
        const Vec3 a{ seg.ControlPoints[3 * i + 3] - seg.ControlPoints[3 * i],
          seg.ControlPoints[3 * i + 4] - seg.ControlPoints[3 * i + 1],
          seg.ControlPoints[3 * i + 5] - seg.ControlPoints[3 * i + 2] };
        length += std::sqrt(Dot(a, a));
      }
      const int n = std::max(1, static_cast<int>(std::ceil(length / spacing)));
      for (int i = 0; i < n; ++i)
      {
        const double T = seg.T0 + (seg.T1 - seg.T0) * (i + 0.5) / n;
        double u = 0.0, v = 0.0;
        if (!EdgePointOnFace(m, onEdge, T, u, v))
          continue;
        out.push_back({ EvaluateEdge(m, edge, T).C, face, true, u, v });
      }
    }
  });
  size_t total = s1.size();
  for (const auto& v : perEdge)
    total += v.size();
  s1.reserve(total);
  for (const auto& v : perEdge)
    s1.insert(s1.end(), v.begin(), v.end());
}

/// Each face's trimming segments (FaceTrimCandidates), and for each block of up to 4 x 4
/// patches of each face's patch grid those that TrimCandidatesFor keeps for the block's UV box
/// with the face's `reach`. A patch's choice among its block's is the same list as among its
/// face's: every segment kept for the patch's box is kept for the block's, which holds it, the
/// segment that sets the patch's bound among them (TrimClassifier.h). Without it each patch
/// scanned its face's every segment, twice: a fifth of the preparation on the Ploopy thumb
/// trackball's body (420 faces, 32,157 segments; perf).
class BlockTrimCandidates
{
public:
  static constexpr int Size = 4;

  template <class Reach>
  BlockTrimCandidates(const BRepModel& model, Reach&& reach)
  {
    const size_t faces = model.Faces.size();
    FaceSegments.resize(faces);
    ParallelFor(faces, 0,
      [&](size_t f) { FaceTrimCandidates(model, static_cast<int>(f), FaceSegments[f]); });
    FirstBlock.assign(faces + 1, 0);
    std::vector<std::array<int, 3>> blocks; // (face, first column, first row)
    for (size_t f = 0; f < faces; ++f)
    {
      FirstBlock[f] = blocks.size();
      const Face& F = model.Faces[f];
      if (F.PatchesU > 0 && F.PatchesV > 0 && F.PatchCount == F.PatchesU * F.PatchesV)
        for (int j = 0; j < F.PatchesV; j += Size)
          for (int i = 0; i < F.PatchesU; i += Size)
            blocks.push_back({ static_cast<int>(f), i, j });
    }
    FirstBlock[faces] = blocks.size();
    BlockSegments.resize(blocks.size());
    ParallelFor(blocks.size(), 0, [&](size_t k) {
      const Face& F = model.Faces[static_cast<size_t>(blocks[k][0])];
      const int i0 = blocks[k][1], j0 = blocks[k][2];
      const int i1 = std::min(F.PatchesU, i0 + Size) - 1, j1 = std::min(F.PatchesV, j0 + Size) - 1;
      const BezierPatch& a = model.Patches[static_cast<size_t>(F.FirstPatch + i0 + j0 * F.PatchesU)];
      const BezierPatch& b = model.Patches[static_cast<size_t>(F.FirstPatch + i1 + j1 * F.PatchesU)];
      BlockSegments[k] = TrimCandidatesFor(model, FaceSegments[static_cast<size_t>(blocks[k][0])],
        { a.Domain[0], a.Domain[2], b.Domain[1], b.Domain[3] }, reach(F));
    });
  }

  /// The candidates patch p chooses among: its block's, or its face's where the face has no grid.
  const std::vector<TrimCandidate>& For(const BRepModel& model, size_t p) const
  {
    const int f = model.Patches[p].Face;
    if (f < 0 || f >= static_cast<int>(FaceSegments.size()))
      return None;
    const Face& F = model.Faces[static_cast<size_t>(f)];
    const size_t first = FirstBlock[static_cast<size_t>(f)];
    if (FirstBlock[static_cast<size_t>(f) + 1] == first)
      return FaceSegments[static_cast<size_t>(f)];
    const int k = static_cast<int>(p) - F.FirstPatch, i = k % F.PatchesU, j = k / F.PatchesU;
    const int perRow = (F.PatchesU + Size - 1) / Size;
    return BlockSegments[first + static_cast<size_t>((j / Size) * perRow + i / Size)];
  }

  /// Every segment of face f (the list a point outside the face's patch grid chooses among).
  const std::vector<TrimCandidate>& OfFace(size_t f) const { return FaceSegments[f]; }

private:
  std::vector<std::vector<TrimCandidate>> FaceSegments, BlockSegments;
  std::vector<size_t> FirstBlock;
  std::vector<TrimCandidate> None;
};

} // namespace

int FindPatchFast(const BRepModel& model, const SolverData& data, int face, double u, double v)
{
  const Face& f = model.Faces[face];
  const double* bu = &data.Breaks[data.FaceBreaks[face]];
  const double* bv = bu + f.PatchesU + 1;
  const int iu = std::clamp(
    static_cast<int>(std::upper_bound(bu + 1, bu + f.PatchesU, u) - (bu + 1)), 0, f.PatchesU - 1);
  const int iv = std::clamp(
    static_cast<int>(std::upper_bound(bv + 1, bv + f.PatchesV, v) - (bv + 1)), 0, f.PatchesV - 1);
  return f.FirstPatch + iu + iv * f.PatchesU;
}
namespace
{
double PatchBoxBand(const Face& F);
}
static void BuildPatchBoxesWith(const BRepModel& model, const CrossingIndex& crossings,
  const BlockTrimCandidates& blockSegments, SolverData& data);

SolverData PrepareSolver(const BRepModel& model, const SolverOptions& options, bool partners)
{
  SolverData data;
  Vec3 lo{ std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
    std::numeric_limits<double>::max() };
  Vec3 hi{ -lo[0], -lo[1], -lo[2] };
  for (const auto& p : model.Patches)
    for (int i = 0; i < 16; ++i)
      for (int k = 0; k < 3; ++k)
      {
        lo[k] = std::min(lo[k], p.ControlPoints[3 * i + k]);
        hi[k] = std::max(hi[k], p.ControlPoints[3 * i + k]);
      }
  data.Scale = model.Patches.empty() ? 1.0 : std::sqrt(Dot(Sub(hi, lo), Sub(hi, lo)));
  for (int k = 0; k < 3; ++k)
    data.Centre[k] = 0.5 * (lo[k] + hi[k]);
  // The faces' points only start the solve (the certification checks each sphere against the
  // patches themselves): by default 1/150 of the diagonal. The edges' points also verify, next
  // to O, where the certification counts nothing: by default a third of 1/300 of it, as before
  // the faces' went coarser (docs/Solver.md, "s1's spacing").
  const double spacing = options.S1Spacing > 0.0 ? options.S1Spacing : data.Scale / 150.0;
  const double edgeSpacing =
    (options.S1Spacing > 0.0 ? options.S1Spacing : data.Scale / 300.0) / 3.0;
  data.S1Spacing = spacing;

  // The faces whose loops cross, before s1's trim tests, which take the parity there.
  BuildLoopCrossings(model, data);

  // Patch grid breakpoints per face.
  for (size_t f = 0; f < model.Faces.size(); ++f)
  {
    const Face& F = model.Faces[f];
    data.FaceBreaks.push_back(static_cast<int>(data.Breaks.size()));
    for (int i = 0; i < F.PatchesU; ++i)
      data.Breaks.push_back(model.Patches[F.FirstPatch + i].Domain[0]);
    data.Breaks.push_back(F.PatchesU ? model.Patches[F.FirstPatch + F.PatchesU - 1].Domain[1] : 0);
    for (int j = 0; j < F.PatchesV; ++j)
      data.Breaks.push_back(model.Patches[F.FirstPatch + j * F.PatchesU].Domain[2]);
    data.Breaks.push_back(
      F.PatchesV ? model.Patches[F.FirstPatch + (F.PatchesV - 1) * F.PatchesU].Domain[3] : 0);
  }

  // s1: a grid on every patch, sized from the patch's control net, kept where inside the trim;
  // the patches on every core (the trim tests are most of the preparation), their points then
  // joined in the patches' order.
  std::vector<std::vector<S1Point>> perPatch(model.Patches.size());
  // The trim band of a face below (the segments within it of a block are tested point by point).
  auto s1Band = [](const Face& F) {
    return F.UVTolerance + 1e-9 * ((F.Domain[1] - F.Domain[0]) + (F.Domain[3] - F.Domain[2]));
  };
  // The blocks' candidates with the patch boxes' reach (BuildPatchBoxesWith, below), twice
  // s1's band or more: a list kept for a wider reach holds every segment the narrower keeps, so
  // the patches' lists here are the same (one construction of the blocks' lists, not two).
  const BlockTrimCandidates blockSegments(model, [](const Face& F) { return 2.0 * PatchBoxBand(F); });
  // The crossing parity's answers (the trim test's at cusps, ties and faces whose loops cross,
  // and the patch boxes' corners below) from each face's segments listed in bands of v
  // (CrossingIndex): every segment of the face scanned per point was a fifth of the thumb
  // trackball body's preparation.
  const CrossingIndex crossings(model);
  ParallelFor(model.Patches.size(), 0, [&](size_t pi) {
    const BezierPatch& p = model.Patches[pi];
    auto cp = [&](int i, int j) -> Vec3 {
      const double* c = &p.ControlPoints[(4 * i + j) * 3];
      return { c[0], c[1], c[2] };
    };
    double lu = 0.0, lv = 0.0;
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 3; ++i)
      {
        const Vec3 a = Sub(cp(i + 1, j), cp(i, j));
        lu = std::max(lu, std::sqrt(Dot(a, a)));
      }
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 3; ++j)
      {
        const Vec3 a = Sub(cp(i, j + 1), cp(i, j));
        lv = std::max(lv, std::sqrt(Dot(a, a)));
      }
    const int nu = std::clamp(static_cast<int>(std::ceil(3.0 * lu / spacing)), 2, options.S1MaxPerPatch);
    const int nv = std::clamp(static_cast<int>(std::ceil(3.0 * lv / spacing)), 2, options.S1MaxPerPatch);
    // A block of the patch's candidate points that no trimming segment's control box comes near
    // (within the face's UV tolerance) lies wholly inside its face or wholly outside: the trim test
    // at its middle decides for all its points. Blocks of 8 x 8 points: only those along the trim
    // are tested point by point (the trim tests were half the preparation).
    const Face& F = model.Faces[static_cast<size_t>(p.Face)];
    const double band = s1Band(F);
    // Only the segments that can be nearest to a point of the patch's domain are scanned (a face
    // with many holes has hundreds); with the trim, the ones within the band of it, which a block
    // near the trim comes near. Chosen among the patch's block's (BlockTrimCandidates).
    const std::vector<TrimCandidate> near = TrimCandidatesFor(model, blockSegments.For(model, pi),
      { p.Domain[0], p.Domain[2], p.Domain[1], p.Domain[3] }, 2.0 * band);
    const double loopsCross = data.FaceLoopsCross[static_cast<size_t>(p.Face)];
    auto wholly = [&](double ul, double uh, double vl, double vh) {
      for (const TrimCandidate& c : near)
        if (c.Box[0] - band <= uh && c.Box[2] + band >= ul && c.Box[1] - band <= vh &&
          c.Box[3] + band >= vl)
          return -1; // near the trim: each point tested
      return ClassifyPointAmong(
               model, 0.5 * (ul + uh), 0.5 * (vl + vh), near, loopsCross, &crossings)
          .Inside
        ? 1
        : 0;
    };
    auto at = [](int k, int count, double from, double to) { return from + (to - from) * (k + 0.5) / count; };
    constexpr int blockSize = 8;
    const int bu = (nu + blockSize - 1) / blockSize, bv = (nv + blockSize - 1) / blockSize;
    std::vector<int> decided(static_cast<size_t>(bu * bv));
    // A block tested point by point: the segments that can be nearest to one of its points.
    std::vector<std::vector<TrimCandidate>> blockNear(decided.size());
    for (int a = 0; a < bu; ++a)
      for (int b = 0; b < bv; ++b)
      {
        const int i0 = a * blockSize, i1 = std::min(nu, i0 + blockSize);
        const int j0 = b * blockSize, j1 = std::min(nv, j0 + blockSize);
        const std::array<double, 4> box{ at(i0, nu, p.Domain[0], p.Domain[1]),
          at(j0, nv, p.Domain[2], p.Domain[3]), at(i1 - 1, nu, p.Domain[0], p.Domain[1]),
          at(j1 - 1, nv, p.Domain[2], p.Domain[3]) };
        const size_t k = static_cast<size_t>(a * bv + b);
        decided[k] = wholly(box[0], box[2], box[1], box[3]);
        if (decided[k] < 0)
          blockNear[k] = TrimCandidatesFor(model, near, box);
      }
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j)
      {
        const size_t k = static_cast<size_t>((i / blockSize) * bv + j / blockSize);
        const double u = p.Domain[0] + (p.Domain[1] - p.Domain[0]) * (i + 0.5) / nu;
        const double v = p.Domain[2] + (p.Domain[3] - p.Domain[2]) * (j + 0.5) / nv;
        if (decided[k] == 0 ||
          (decided[k] < 0 &&
            !ClassifyPointAmong(model, u, v, blockNear[k], loopsCross, &crossings).Inside))
          continue;
        const PatchEval e = EvaluatePatch(p, u, v);
        perPatch[pi].push_back({ e.P, p.Face, false, u, v });
      }
  });
  size_t total = 0;
  for (const auto& v : perPatch)
    total += v.size();
  data.S1.reserve(total);
  for (const auto& v : perPatch)
    data.S1.insert(data.S1.end(), v.begin(), v.end());
  AddEdgePoints(model, edgeSpacing, data.S1);
  BuildS1Tree(model, data);
  BuildVertices(model, data);
  BuildPatchBoxesWith(model, crossings, blockSegments, data);
  if (partners)
    BuildWallPartners(model, data);
  else
    data.WallPartners.assign(KernelWallPartners * model.Faces.size(), -1);
  return data;
}

void BuildLoopCrossings(const BRepModel& model, SolverData& data)
{
  data.FaceLoopsCross.assign(model.Faces.size(), -1.0);
  ParallelFor(model.Faces.size(), 0, [&](size_t f) {
    data.FaceLoopsCross[f] = TrimLoopsCross(model, static_cast<int>(f));
  });
}

namespace
{
/// BuildWallPartners with the probes' query given: query(probes, wall, hit) as
/// NativeSolver::WallWithin answers at the radius S1Spacing / 8.
template <class Query>
void BuildWallPartnersBy(const BRepModel& model, SolverData& data, Query&& query)
{
  const size_t nf = model.Faces.size();
  data.WallPartners.assign(KernelWallPartners * nf, -1);
  if (data.BoxNodes.empty() || data.Breaks.empty() || !(data.S1Spacing > 0.0))
    return;
  // The probes: a 4 x 4 grid over each face's (u, v) bounds, where inside its trim (nothing of s1,
  // so that a solve file read back gives the same partners).
  // (Each face's on every core, then joined in the faces' order.)
  std::vector<std::vector<Sample>> perFace(nf);
  ParallelFor(nf, 0, [&](size_t f) {
    const Face& F = model.Faces[f];
    if (F.PatchCount == 0)
      return;
    std::vector<Sample>& probes = perFace[f];
    const int face = static_cast<int>(f);
    const double sign = F.Reversed ? 1.0 : -1.0; // inward = -outward
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
      {
        const double u = F.Domain[0] + (F.Domain[1] - F.Domain[0]) * (i + 0.5) / 4.0;
        const double v = F.Domain[2] + (F.Domain[3] - F.Domain[2]) * (j + 0.5) / 4.0;
        if (!ClassifyPoint(model, face, u, v,
              data.FaceLoopsCross.size() == nf ? data.FaceLoopsCross[f] : -1.0)
               .Inside)
          continue;
        const PatchEval e =
          EvaluatePatch(model.Patches[FindPatchFast(model, data, face, u, v)], u, v);
        const Vec3 nrm{ e.Du[1] * e.Dv[2] - e.Du[2] * e.Dv[1],
          e.Du[2] * e.Dv[0] - e.Du[0] * e.Dv[2], e.Du[0] * e.Dv[1] - e.Du[1] * e.Dv[0] };
        const double len = std::sqrt(Dot(nrm, nrm));
        if (!(len > 0.0))
          continue;
        Sample p;
        p.Face = face;
        p.U = u;
        p.V = v;
        p.Point = e.P;
        p.Direction = { sign * nrm[0] / len, sign * nrm[1] / len, sign * nrm[2] / len };
        probes.push_back(p);
      }
  });
  std::vector<Sample> probes;
  for (const auto& v : perFace)
    probes.insert(probes.end(), v.begin(), v.end());
  if (probes.empty())
    return;
  std::vector<double> wall;
  std::vector<int> hit;
  query(probes, wall, hit);
  // (face, face across) once per probe that found it, from either side.
  std::vector<std::pair<int, int>> found;
  for (size_t i = 0; i < probes.size(); ++i)
  {
    const int from = probes[i].Face, to = hit[i];
    if (to < 0 || to == from || !std::isfinite(wall[i]))
      continue;
    found.emplace_back(from, to);
    found.emplace_back(to, from);
  }
  std::sort(found.begin(), found.end());
  for (size_t a = 0; a < found.size();)
  {
    const int face = found[a].first;
    // This face's partners with their counts, most found first, ties to the lower index.
    std::vector<std::pair<int, int>> counts; // (-count, partner)
    size_t b = a;
    while (b < found.size() && found[b].first == face)
    {
      size_t c = b;
      while (c < found.size() && found[c] == found[b])
        ++c;
      counts.emplace_back(-static_cast<int>(c - b), found[b].second);
      b = c;
    }
    std::sort(counts.begin(), counts.end());
    for (size_t k = 0; k < KernelWallPartners && k < counts.size(); ++k)
      data.WallPartners[KernelWallPartners * static_cast<size_t>(face) + k] = counts[k].second;
    a = b;
  }
}
} // namespace

void BuildWallPartners(const BRepModel& model, SolverData& data)
{
  BuildWallPartnersBy(model, data,
    [&](const std::vector<Sample>& probes, std::vector<double>& wall, std::vector<int>& hit) {
      // The query needs the patches and their boxes, not s1: set aside while the solver is
      // packed (and put back however the query ends).
      struct SetAside
      {
        SolverData& D;
        std::vector<S1Point> S1;
        std::vector<BVHNode> Nodes;
        explicit SetAside(SolverData& d) : D(d)
        {
          S1.swap(D.S1);
          Nodes.swap(D.Nodes);
        }
        ~SetAside()
        {
          S1.swap(D.S1);
          Nodes.swap(D.Nodes);
        }
      } aside(data);
      PackOptions pack;
      pack.Tubes = false; // (the same answers, without fitting them)
      NativeSolver(model, data, pack).WallWithin(probes, data.S1Spacing / 8.0, wall, hit);
    });
}

void BuildWallPartners(const BRepModel& model, SolverData& data, const NativeSolver& solver)
{
  BuildWallPartnersBy(model, data,
    [&](const std::vector<Sample>& probes, std::vector<double>& wall, std::vector<int>& hit) {
      solver.WallWithin(probes, data.S1Spacing / 8.0, wall, hit);
    });
}

void BuildS1Tree(const BRepModel& model, SolverData& data)
{
  data.Nodes.clear();
  std::vector<S1Point>& pts = data.S1;
  if (pts.empty())
    return;
  std::vector<int> faceSolid(model.Faces.size());
  for (size_t f = 0; f < model.Faces.size(); ++f)
    faceSolid[f] = model.Faces[f].Solid;
  // The levels whose right subtrees are built on threads of their own: a thread per core.
  int levels = 0;
  for (unsigned t = std::max(1u, std::thread::hardware_concurrency()); t > 1; t = (t + 1) / 2)
    ++levels;
  const auto solidOf = [&](const S1Point& p) {
    return p.Face >= 0 && p.Face < static_cast<int>(faceSolid.size()) ? faceSolid[p.Face] : -1;
  };
  const auto edgeBegin = std::stable_partition(
    pts.begin(), pts.end(), [](const S1Point& p) { return !p.OnEdge; });
  // Each part sorted by solid, as Build takes them.
  const auto bySolid = [&](const S1Point& a, const S1Point& b) { return solidOf(a) < solidOf(b); };
  if (!std::is_sorted(pts.begin(), edgeBegin, bySolid))
    std::stable_sort(pts.begin(), edgeBegin, bySolid);
  if (!std::is_sorted(edgeBegin, pts.end(), bySolid))
    std::stable_sort(edgeBegin, pts.end(), bySolid);
  const int faces = static_cast<int>(edgeBegin - pts.begin());
  const int all = static_cast<int>(pts.size());
  int face;
  if (faces == 0 || faces == all)
  {
    Build(pts, data.Nodes, 0, all, faceSolid, levels, false, &face);
    return;
  }
  // The split root over the faces' points (left) and the edges' (right).
  data.Nodes.emplace_back();
  Build(pts, data.Nodes, 0, faces, faceSolid, levels, false, &face);
  const int right = Build(pts, data.Nodes, faces, all - faces, faceSolid, levels, false, &face);
  BVHNode root;
  const BVHNode& l = data.Nodes[1];
  const BVHNode& r = data.Nodes[static_cast<size_t>(right)];
  for (int k = 0; k < 3; ++k)
  {
    root.Min[k] = std::min(l.Min[k], r.Min[k]);
    root.Max[k] = std::max(l.Max[k], r.Max[k]);
  }
  // One solid below both: its marker, as Build gives an inner node over one solid.
  const int solid = solidOf(pts.front());
  const bool oneSolid = std::all_of(
    pts.begin(), pts.end(), [&](const S1Point& p) { return solidOf(p) == solid; });
  root.First = S1SplitRoot;
  root.Count = oneSolid && solid >= 0 ? -(solid + 1) : 0;
  root.Right = right;
  data.Nodes[0] = root;
}

/// The cubic Bezier curve of control points c[0], c[stride], c[2 stride], c[3 stride] (3
/// coordinates each) restricted to [a, b] of its parameter (0 <= a < b <= 1), by de Casteljau.
static void RestrictCubic(double* c, int stride, double a, double b)
{
  auto split = [&](double t, bool keepLeft) {
    for (int k = 0; k < 3; ++k)
    {
      double p[4];
      for (int i = 0; i < 4; ++i)
        p[i] = c[i * stride + k];
      const double q01 = p[0] + t * (p[1] - p[0]), q12 = p[1] + t * (p[2] - p[1]),
                   q23 = p[2] + t * (p[3] - p[2]);
      const double r0 = q01 + t * (q12 - q01), r1 = q12 + t * (q23 - q12);
      const double m = r0 + t * (r1 - r0);
      const double left[4] = { p[0], q01, r0, m }, right[4] = { m, r1, q23, p[3] };
      for (int i = 0; i < 4; ++i)
        c[i * stride + k] = keepLeft ? left[i] : right[i];
    }
  };
  if (b < 1.0)
    split(b, true);
  if (a > 0.0)
    split(a / b, false);
}

std::array<double, 48> RestrictedControlPoints(const BezierPatch& patch, const double* box)
{
  std::array<double, 48> cp = patch.ControlPoints;
  if (box[0] <= 0.0 && box[1] >= 1.0 && box[2] <= 0.0 && box[3] >= 1.0)
    return cp;
  for (int j = 0; j < 4; ++j)
    RestrictCubic(cp.data() + 3 * j, 12, box[0], box[1]);
  for (int i = 0; i < 4; ++i)
    RestrictCubic(cp.data() + 12 * i, 3, box[2], box[3]);
  return cp;
}

namespace
{
/// The UV band TrimmedPatchBox widens by: the face's UV tolerance twice and 1e-8 of its domain.
double PatchBoxBand(const Face& F)
{
  return 2.0 * F.UVTolerance + 1e-8 * ((F.Domain[1] - F.Domain[0]) + (F.Domain[3] - F.Domain[2]));
}

/// What TrimmedPatchBox's first half finds in a patch's domain (ScanPatchTrim): the UV box of
/// the trimming segments' pieces within it, and its corners' answers (inside the face or within
/// the band of its trim: 1; else 0; -1 not asked). Whole: the patch keeps its control points'
/// box (no face, no loops, an empty domain).
struct PatchTrimScan
{
  double Lo[2] = { 1e300, 1e300 }, Hi[2] = { -1e300, -1e300 };
  signed char Corner[4] = { -1, -1, -1, -1 };
  bool Whole = false;
};

/// Corners in TrimmedPatchBox's order: (u0, v0), (u0, v1), (u1, v0), (u1, v1).
inline double CornerU(const BezierPatch& p, int k) { return p.Domain[k < 2 ? 0 : 1]; }
inline double CornerV(const BezierPatch& p, int k) { return p.Domain[(k & 1) ? 3 : 2]; }

/// The first half of TrimmedPatchBox: the segments' pieces within the patch's domain, and the
/// corners k where ask[k] (the trim test at each among the segments that can be nearest to a
/// point of the domain).
PatchTrimScan ScanPatchTrim(const BRepModel& model, const BezierPatch& patch,
  const std::vector<TrimCandidate>& faceSegments, const CrossingIndex& crossings,
  const bool ask[4])
{
  PatchTrimScan scan;
  if (patch.Face < 0 || patch.Face >= static_cast<int>(model.Faces.size()))
  {
    scan.Whole = true;
    return scan;
  }
  const Face& F = model.Faces[static_cast<size_t>(patch.Face)];
  const double u0 = patch.Domain[0], u1 = patch.Domain[1], v0 = patch.Domain[2],
               v1 = patch.Domain[3];
  if (F.LoopCount <= 0 || !(u1 > u0) || !(v1 > v0))
  {
    scan.Whole = true;
    return scan;
  }
  const double band = PatchBoxBand(F);
  auto add = [&](double u, double v) {
    scan.Lo[0] = std::min(scan.Lo[0], u);
    scan.Hi[0] = std::max(scan.Hi[0], u);
    scan.Lo[1] = std::min(scan.Lo[1], v);
    scan.Hi[1] = std::max(scan.Hi[1], v);
  };
  // The segments that can be nearest to a point of the domain, with every one within the band
  // of it (TrimCandidatesFor): the others neither reach into the domain nor decide a corner.
  const std::vector<TrimCandidate> near =
    TrimCandidatesFor(model, faceSegments, { u0, v0, u1, v1 }, 2.0 * band);
  for (const TrimCandidate& c : near)
  {
    const std::array<double, 4>& sb = c.Box;
    const double cl[2] = { std::max(sb[0] - band, u0), std::max(sb[1] - band, v0) };
    const double ch[2] = { std::min(sb[2] + band, u1), std::min(sb[3] + band, v1) };
    if (cl[0] <= ch[0] && cl[1] <= ch[1])
    {
      add(cl[0], cl[1]);
      add(ch[0], ch[1]);
    }
  }
  for (int k = 0; k < 4; ++k)
    if (ask[k])
    {
      const double u = CornerU(patch, k), v = CornerV(patch, k);
      const TrimProjection tp = ClassifyPointAmong(model, u, v, near, -1.0, &crossings);
      scan.Corner[k] = tp.Inside || tp.Distance <= band || crossings.Inside(patch.Face, u, v);
    }
  return scan;
}

/// Patch p's box narrowed to the part of it inside its face's trim (b: its control points' box,
/// narrowed in place), from its scan and its corners' answers (corner[k]: 1 inside). That part
/// lies in the UV box of the trimming segments' pieces within the patch's domain (their control
/// points' boxes, clipped to it) and of the domain's corners inside the face: the boundary of
/// the face within the domain is made of those pieces and of the domain's sides between them and
/// the corners. The box is that of the control points of the patch restricted to that UV box
/// (de Casteljau). A plane's patch under a boss or across a hole is then boxed by its face
/// alone. Returns false where no part of the patch is inside the face (the certification never
/// searches it). The UV box is widened by the face's UV tolerance, the trim test's own band
/// (1e-9 of the face's domain) and rounding (PatchBoxBand).
bool TrimmedPatchBox(const BezierPatch& patch, const PatchTrimScan& scan, const signed char corner[4],
  double* b, double* local)
{
  if (scan.Whole)
    return true;
  double lo[2] = { scan.Lo[0], scan.Lo[1] }, hi[2] = { scan.Hi[0], scan.Hi[1] };
  for (int k = 0; k < 4; ++k)
    if (corner[k] == 1)
    {
      const double u = CornerU(patch, k), v = CornerV(patch, k);
      lo[0] = std::min(lo[0], u);
      hi[0] = std::max(hi[0], u);
      lo[1] = std::min(lo[1], v);
      hi[1] = std::max(hi[1], v);
    }
  const double u0 = patch.Domain[0], u1 = patch.Domain[1], v0 = patch.Domain[2],
               v1 = patch.Domain[3];
  if (!(lo[0] <= hi[0]))
    return false;
  const double a0 = std::clamp((lo[0] - u0) / (u1 - u0), 0.0, 1.0);
  const double a1 = std::clamp((hi[0] - u0) / (u1 - u0), 0.0, 1.0);
  const double c0 = std::clamp((lo[1] - v0) / (v1 - v0), 0.0, 1.0);
  const double c1 = std::clamp((hi[1] - v0) / (v1 - v0), 0.0, 1.0);
  if (a0 <= 0.0 && a1 >= 1.0 && c0 <= 0.0 && c1 >= 1.0)
    return true;
  if (!(a1 > a0) || !(c1 > c0))
    return true; // a sliver: keep the whole patch's box
  local[0] = a0;
  local[1] = a1;
  local[2] = c0;
  local[3] = c1;
  const std::array<double, 48> cp = RestrictedControlPoints(patch, local);
  double reach = 0.0;
  for (int k = 0; k < 6; ++k)
    reach = std::max(reach, std::fabs(b[k]));
  const double pad = 1e-12 * reach;
  for (int k = 0; k < 3; ++k)
  {
    double l = cp[k], h = cp[k];
    for (int i = 1; i < 16; ++i)
    {
      l = std::min(l, cp[3 * i + k]);
      h = std::max(h, cp[3 * i + k]);
    }
    b[k] = std::max(b[k], l - pad);
    b[3 + k] = std::min(b[3 + k], h + pad);
  }
  return true;
}
} // namespace

/// BuildPatchBoxes with the crossing index and the blocks' trimming candidates (for the reach
/// 2 PatchBoxBand) that PrepareSolver's s1 sampling built too.
static void BuildPatchBoxesWith(const BRepModel& model, const CrossingIndex& crossings,
  const BlockTrimCandidates& blockSegments, SolverData& data)
{
  auto box = [](const double* c, int points, double* b) {
    for (int k = 0; k < 3; ++k)
    {
      b[k] = b[3 + k] = c[k];
      for (int i = 1; i < points; ++i)
      {
        b[k] = std::min(b[k], c[3 * i + k]);
        b[3 + k] = std::max(b[3 + k], c[3 * i + k]);
      }
    }
  };
  data.PatchBoxes.assign(6 * model.Patches.size(), 0.0);
  // Patches wholly outside their face's trim take no part in the certification's tree. Each
  // face's trimming segments and their boxes once, and those of each block of its patches
  // (BlockTrimCandidates), for all of its patches.
  std::vector<char> trimmedAway(model.Patches.size(), 0);
  // A corner of a face's patch grid is shared by up to four patches: the patch whose (u0, v0)
  // corner it is answers for all of them (its trim test's candidates hold the segments nearest
  // to it, as each neighbour's do, so every neighbour's test gives the same answer). A corner's
  // answer comes from that patch where it lies in the grid with exactly this corner; else the
  // patch asks itself.
  auto provider = [&](size_t p, int k) -> size_t {
    const BezierPatch& P = model.Patches[p];
    if (k == 0 || P.Face < 0 || P.Face >= static_cast<int>(model.Faces.size()))
      return p;
    const Face& F = model.Faces[static_cast<size_t>(P.Face)];
    if (!(F.PatchesU > 0 && F.PatchesV > 0 && F.PatchCount == F.PatchesU * F.PatchesV))
      return p;
    const int at = static_cast<int>(p) - F.FirstPatch;
    const int i = at % F.PatchesU + (k >= 2 ? 1 : 0), j = at / F.PatchesU + (k & 1);
    if (i >= F.PatchesU || j >= F.PatchesV)
      return p;
    const size_t q = static_cast<size_t>(F.FirstPatch + i + j * F.PatchesU);
    const BezierPatch& Q = model.Patches[q];
    if (Q.Face != P.Face || !(Q.Domain[1] > Q.Domain[0]) || !(Q.Domain[3] > Q.Domain[2]) ||
      Q.Domain[0] != CornerU(P, k) || Q.Domain[2] != CornerV(P, k))
      return p;
    return q;
  };
  data.PatchTrimBox.assign(4 * model.Patches.size(), 0.0);
  for (size_t p = 0; p < model.Patches.size(); ++p)
  {
    data.PatchTrimBox[4 * p + 1] = 1.0;
    data.PatchTrimBox[4 * p + 3] = 1.0;
  }
  std::vector<PatchTrimScan> scans(model.Patches.size());
  ParallelFor(model.Patches.size(), 0, [&](size_t p) {
    box(model.Patches[p].ControlPoints.data(), 16, &data.PatchBoxes[6 * p]);
    bool ask[4];
    for (int k = 0; k < 4; ++k)
      ask[k] = provider(p, k) == p;
    scans[p] = ScanPatchTrim(model, model.Patches[p], blockSegments.For(model, p), crossings, ask);
  });
  ParallelFor(model.Patches.size(), 0, [&](size_t p) {
    signed char corner[4];
    for (int k = 0; k < 4; ++k)
    {
      const size_t q = provider(p, k);
      corner[k] = q == p ? scans[p].Corner[k] : scans[q].Corner[0];
    }
    trimmedAway[p] = !TrimmedPatchBox(
      model.Patches[p], scans[p], corner, &data.PatchBoxes[6 * p], &data.PatchTrimBox[4 * p]);
  });
  data.EdgeBoxes.assign(6 * model.EdgeSegments.size(), 0.0);
  for (size_t e = 0; e < model.EdgeSegments.size(); ++e)
    box(model.EdgeSegments[e].ControlPoints.data(), 4, &data.EdgeBoxes[6 * e]);
  // Each edge's distance from its faces' exact surfaces: the edges whose file tolerance lets them
  // stray from their faces (up to 34 slacks on the unseen cover, against 0.14 at most on
  // NIST_MBE_PMI_11) get a weak bound, the others a tight one.
  data.EdgeFaceDeviation.assign(2 * model.Edges.size(), -1.0);
  ParallelFor(model.Edges.size(), 0, [&](size_t e) {
    const Edge& E = model.Edges[e];
    std::vector<double> points;
    for (int s = E.FirstSegment; s < E.FirstSegment + E.SegmentCount; ++s)
      for (int i = 0; i <= 16; ++i)
      {
        const auto c = EvaluateCubic<3>(
          model.EdgeSegments[static_cast<size_t>(s)].ControlPoints.data(), i / 16.0);
        points.insert(points.end(), { c.P[0], c.P[1], c.P[2] });
      }
    for (int k = 0; k < 2; ++k)
    {
      const int f = E.Faces[static_cast<size_t>(k)];
      if (f < 0 || f >= static_cast<int>(model.Faces.size()) || points.empty())
        continue;
      const double worst = FarthestFromExactSurface(model, f, points.data(), points.size() / 3);
      if (worst >= 0.0)
        data.EdgeFaceDeviation[2 * e + static_cast<size_t>(k)] = 1.5 * worst + 1e-12 * data.Scale;
    }
  });
  // BVH: the solids apart first, then median splits of the box centres (below), leaves of up to
  // 8 boxes.
  const int np = static_cast<int>(model.Patches.size());
  const int n = np + static_cast<int>(model.EdgeSegments.size());
  auto boxOf = [&](int item) {
    return item < np ? &data.PatchBoxes[6 * static_cast<size_t>(item)]
                     : &data.EdgeBoxes[6 * static_cast<size_t>(item - np)];
  };
  // An item's solid: its face's, an edge segment's first face's (-1: none).
  auto solidOf = [&](int item) {
    int face = -1;
    if (item < np)
      face = model.Patches[static_cast<size_t>(item)].Face;
    else
    {
      const int edge = model.EdgeSegments[static_cast<size_t>(item - np)].Edge;
      if (edge >= 0 && edge < static_cast<int>(model.Edges.size()))
        face = model.Edges[static_cast<size_t>(edge)].Faces[0];
    }
    return face >= 0 && face < static_cast<int>(model.Faces.size())
      ? model.Faces[static_cast<size_t>(face)].Solid
      : -1;
  };
  // Each item's solid and its box's centre (twice: the sum of its ends) per axis, in arrays of
  // their own: read through the items' two box arrays, the splits below were most of the
  // preparation's time on free-form parts (the small headband's 11,064 patches: 25 ms of one
  // core).
  std::vector<int> itemSolid(static_cast<size_t>(n));
  std::vector<double> itemCentre(3 * static_cast<size_t>(n)), itemBox(6 * static_cast<size_t>(n));
  for (int i = 0; i < n; ++i)
  {
    itemSolid[static_cast<size_t>(i)] = solidOf(i);
    const double* b = boxOf(i);
    std::copy(b, b + 6, &itemBox[6 * static_cast<size_t>(i)]);
    for (int k = 0; k < 3; ++k)
      itemCentre[3 * static_cast<size_t>(i) + static_cast<size_t>(k)] = b[k] + b[3 + k];
  }
  data.BoxItems.clear();
  for (int i = 0; i < n; ++i)
    if (i >= np || !trimmedAway[static_cast<size_t>(i)])
      data.BoxItems.push_back(i);
  data.BoxNodes.clear();
  if (data.BoxItems.empty())
    return;
  struct Task
  {
    int First, Count, Parent;
  };
  std::vector<Task> tasks{ { 0, static_cast<int>(data.BoxItems.size()), -1 } };
  while (!tasks.empty())
  {
    const Task task = tasks.back();
    tasks.pop_back();
    const int index = static_cast<int>(data.BoxNodes.size());
    if (task.Parent >= 0)
      data.BoxNodes[static_cast<size_t>(task.Parent)].Right = index;
    BVHNode node;
    node.Min = { 1e300, 1e300, 1e300 };
    node.Max = { -1e300, -1e300, -1e300 };
    const int firstItem = data.BoxItems[static_cast<size_t>(task.First)];
    const int solid = itemSolid[static_cast<size_t>(firstItem)];
    bool oneSolid = true;
    // The face all the subtree's items are patches of (-1: edge segments among them, or several
    // faces): an inner node's First, so that the certification skips the subtree whole where
    // that face's bound clears the sphere (find_point_inside).
    int oneFace = firstItem < np ? model.Patches[static_cast<size_t>(firstItem)].Face : -1;
    for (int i = task.First; i < task.First + task.Count; ++i)
    {
      const int item = data.BoxItems[static_cast<size_t>(i)];
      const double* b = &itemBox[6 * static_cast<size_t>(item)];
      for (int k = 0; k < 3; ++k)
      {
        node.Min[k] = std::min(node.Min[k], b[k]);
        node.Max[k] = std::max(node.Max[k], b[3 + k]);
      }
      oneSolid = oneSolid && itemSolid[static_cast<size_t>(item)] == solid;
      if (item >= np || model.Patches[static_cast<size_t>(item)].Face != oneFace)
        oneFace = -1;
    }
    node.First = oneFace;
    // Leaves of up to 8 items (4 took 0-7% longer: more levels to walk; 16 no better), on one
    // solid.
    if (oneSolid && task.Count <= 8)
    {
      node.First = task.First;
      node.Count = task.Count;
      data.BoxNodes.push_back(node);
      continue;
    }
    // The median split of the box centres along the axis whose halves' boxes hold the least
    // volume (sides widened by 1e-3 of the node's diagonal, so that flat halves still compare;
    // ties to the longest axis). A thin wall's two faces then part high in the tree: a sphere
    // between them meets neither half's box (the longest axis alone kept both faces in every
    // node down to the leaves).
    int longest = 0;
    for (int k = 1; k < 3; ++k)
      if (node.Max[k] - node.Min[k] > node.Max[longest] - node.Min[longest])
        longest = k;
    int half = task.Count / 2;
    auto first = data.BoxItems.begin() + task.First;
    if (!oneSolid)
    {
      // Over several solids, the first splits separate them (at the solid boundary nearest the
      // middle), as in s1's tree: an inner node on one solid records it as Count = -(solid + 1),
      // and a query bounded by its own solid skips the others' subtrees whole.
      std::sort(first, first + task.Count, [&](int a, int b) {
        const int sa = itemSolid[static_cast<size_t>(a)], sb = itemSolid[static_cast<size_t>(b)];
        return sa < sb || (sa == sb && a < b);
      });
      int best = -1;
      for (int i = task.First + 1; i < task.First + task.Count; ++i)
        if (itemSolid[static_cast<size_t>(data.BoxItems[static_cast<size_t>(i)])] !=
            itemSolid[static_cast<size_t>(data.BoxItems[static_cast<size_t>(i - 1)])] &&
          (best < 0 || std::abs(i - task.First - half) < std::abs(best - task.First - half)))
          best = i;
      half = best - task.First;
      data.BoxNodes.push_back(node);
      tasks.push_back({ task.First + half, task.Count - half, index });
      tasks.push_back({ task.First, half, -1 });
      continue;
    }
    node.Count = solid >= 0 ? -(solid + 1) : 0;
    auto split = [&](int axis) {
      const double* c = itemCentre.data() + axis;
      std::nth_element(first, first + half, first + task.Count, [c](int a, int b) {
        const double ca = c[3 * static_cast<size_t>(a)], cb = c[3 * static_cast<size_t>(b)];
        return ca < cb || (ca == cb && a < b);
      });
    };
    double widen = 0.0;
    for (int k = 0; k < 3; ++k)
      widen += (node.Max[k] - node.Min[k]) * (node.Max[k] - node.Min[k]);
    widen = 1e-3 * std::sqrt(widen);
    auto volume = [&](int from, int to) {
      double lo[3] = { 1e300, 1e300, 1e300 }, hi[3] = { -1e300, -1e300, -1e300 };
      for (int i = from; i < to; ++i)
      {
        const double* b = &itemBox[6 * static_cast<size_t>(data.BoxItems[static_cast<size_t>(i)])];
        for (int k = 0; k < 3; ++k)
        {
          lo[k] = std::min(lo[k], b[k]);
          hi[k] = std::max(hi[k], b[3 + k]);
        }
      }
      return (hi[0] - lo[0] + widen) * (hi[1] - lo[1] + widen) * (hi[2] - lo[2] + widen);
    };
    int axis = longest;
    double bestCost = std::numeric_limits<double>::max();
    for (int j = 0; j < 3; ++j)
    {
      const int k = (longest + j) % 3;
      split(k);
      const double cost = volume(task.First, task.First + half) +
        volume(task.First + half, task.First + task.Count);
      if (cost < bestCost * (1.0 - 1e-9))
      {
        bestCost = cost;
        axis = k;
      }
    }
    split(axis);
    data.BoxNodes.push_back(node);
    // Depth first, left child next: the right child is pushed first and popped last; its index
    // is patched into this node when it is built.
    tasks.push_back({ task.First + half, task.Count - half, index });
    tasks.push_back({ task.First, half, -1 });
  }
}

void BuildPatchBoxes(const BRepModel& model, SolverData& data)
{
  const CrossingIndex crossings(model);
  const BlockTrimCandidates blockSegments(model, [](const Face& F) { return 2.0 * PatchBoxBand(F); });
  BuildPatchBoxesWith(model, crossings, blockSegments, data);
}

void BuildVertices(const BRepModel& model, SolverData& data)
{
  // Edge ends within 10x the tolerance of each other are one vertex (the edges' cubics end
  // within the tolerance of the exact vertex): union-find over a sweep along x.
  struct End
  {
    Vec3 P;
    int Id; // 2 * edge + k
  };
  std::vector<End> ends;
  for (size_t e = 0; e < model.Edges.size(); ++e)
    if (model.Edges[e].SegmentCount > 0)
      for (int k = 0; k < 2; ++k)
      {
        const Edge& E = model.Edges[e];
        const int edge = static_cast<int>(e);
        ends.push_back({ EvaluateEdge(model, edge, k ? E.T1 : E.T0).C, 2 * edge + k });
      }
  std::sort(ends.begin(), ends.end(), [](const End& a, const End& b) { return a.P[0] < b.P[0]; });
  std::vector<int> parent(ends.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](int i) {
    while (parent[i] != i)
      i = parent[i] = parent[parent[i]];
    return i;
  };
  const double eps = 10.0 * model.Tolerance;
  for (size_t i = 0; i < ends.size(); ++i)
    for (size_t j = i + 1; j < ends.size() && ends[j].P[0] - ends[i].P[0] <= eps; ++j)
    {
      const Vec3 g = Sub(ends[j].P, ends[i].P);
      if (Dot(g, g) <= eps * eps)
        parent[root(static_cast<int>(j))] = root(static_cast<int>(i));
    }
  std::vector<std::vector<int>> members(ends.size());
  for (size_t i = 0; i < ends.size(); ++i)
    members[root(static_cast<int>(i))].push_back(ends[i].Id);
  data.VertexInfo.assign(2 * model.Edges.size(), -1);
  for (auto& v : members)
  {
    if (v.empty())
      continue;
    std::sort(v.begin(), v.end());
    const int record = static_cast<int>(data.VertexInfo.size());
    data.VertexInfo.push_back(static_cast<int>(v.size()));
    for (const int id : v)
    {
      data.VertexInfo.push_back(id);
      data.VertexInfo[id] = record;
    }
  }
}

namespace
{
/// x's low 10 bits spread to every third bit.
uint32_t SpreadBits(uint32_t x)
{
  x &= 0x3ffu;
  x = (x | (x << 16)) & 0x030000ffu;
  x = (x | (x << 8)) & 0x0300f00fu;
  x = (x | (x << 4)) & 0x030c30c3u;
  x = (x | (x << 2)) & 0x09249249u;
  return x;
}

/// p's cell on a Morton curve of 1024 cells a side over box b (min, max).
uint32_t MortonCode(const std::array<double, 6>& b, const std::array<double, 3>& p)
{
  const double ext = std::max({ b[3] - b[0], b[4] - b[1], b[5] - b[2] });
  uint32_t code = 0;
  for (int k = 0; k < 3; ++k)
  {
    const double x = ext > 0.0 ? (p[k] - b[k]) / ext * 1023.0 : 0.0;
    // (A point that is not finite goes to the cell at the box's corner.)
    code |= SpreadBits(static_cast<uint32_t>(x >= 0.0 ? std::min(x, 1023.0) : 0.0)) << k;
  }
  return code;
}
} // namespace

std::vector<size_t> ChainStarts(const std::vector<Sample>& samples,
  const std::vector<size_t>& order, int chain)
{
  const size_t length = static_cast<size_t>(std::max(chain, 1));
  std::vector<size_t> starts;
  for (size_t j = 0, inRun = 0; j < order.size(); ++j, ++inRun)
  {
    if (j == 0 || samples[order[j]].Face != samples[order[j - 1]].Face)
      inRun = 0;
    if (inRun % length == 0)
      starts.push_back(j);
  }
  starts.push_back(order.size());
  return starts;
}

int ChainLength(const SolverOptions& options, bool gpu)
{
  const int chain = options.Chain > 0 ? options.Chain : (gpu ? KernelGpuChain : KernelCpuChain);
  return std::min(chain, KernelMaxChain);
}

std::vector<size_t> SpatialOrder(const std::vector<Sample>& samples, const std::vector<size_t>* which)
{
  const size_t n = which ? which->size() : samples.size();
  auto index = [&](size_t j) { return which ? (*which)[j] : j; };
  // A few samples: the same order by comparison sorts, without the tables below, which are
  // sized by the largest face index and cost more than the solve of a single sample (it took
  // 12 us instead of 5).
  if (n <= 256)
  {
    std::vector<size_t> order(n);
    for (size_t j = 0; j < n; ++j)
      order[j] = index(j);
    auto faceKey = [&](size_t i) { return std::max(samples[i].Face + 1, 0); };
    std::stable_sort(order.begin(), order.end(),
      [&](size_t a, size_t b) { return faceKey(a) < faceKey(b); });
    for (size_t a = 0; a < n;)
    {
      size_t b = a;
      std::array<double, 6> box{ std::numeric_limits<double>::infinity(),
        std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
        -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
        -std::numeric_limits<double>::infinity() };
      for (; b < n && faceKey(order[b]) == faceKey(order[a]); ++b)
        for (int k = 0; k < 3; ++k)
        {
          box[k] = std::min(box[k], samples[order[b]].Point[k]);
          box[3 + k] = std::max(box[3 + k], samples[order[b]].Point[k]);
        }
      std::vector<std::pair<uint32_t, size_t>> run;
      for (size_t j = a; j < b; ++j)
        run.emplace_back(MortonCode(box, samples[order[j]].Point), order[j]);
      std::stable_sort(run.begin(), run.end(),
        [](const auto& x, const auto& y) { return x.first < y.first; });
      for (size_t j = a; j < b; ++j)
        order[j] = run[j - a].second;
      a = b;
    }
    return order;
  }
  // Every step on every core from 65,536 samples on, each core a contiguous range of them (on
  // a GPU the order of a million samples on one core took as long as their solve; docs/Solver.md,
  // Benchmark). The order: by face (faces as their own index; -1 and others kept apart), then
  // along a Morton curve of 1024 cells a side over the face's box, in the given order within a
  // cell (stable).
  // (Positions are kept in 32 bits: four billion samples would need 300 GB of them anyway.)
  if (n > std::numeric_limits<uint32_t>::max())
    throw std::length_error("SpatialOrder: more than 2^32 samples");
  const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
  const unsigned threads = static_cast<unsigned>(std::max<size_t>(1, std::min<size_t>(hw, n / 32768)));
  auto range = [&](unsigned t) { return std::make_pair(n * t / threads, n * (t + 1) / threads); };
  auto each = [&](auto&& f) {
    if (threads == 1)
      f(0u);
    else
      ParallelFor(threads, threads, [&](size_t t) { f(static_cast<unsigned>(t)); });
  };
  auto faceOf = [&](size_t j) { return static_cast<size_t>(std::max(samples[index(j)].Face + 1, 0)); };
  // Each face's box over its samples, each core's own boxes merged.
  std::vector<size_t> largestOf(threads, 0);
  each([&](unsigned t) {
    const auto [first, last] = range(t);
    for (size_t j = first; j < last; ++j)
      largestOf[t] = std::max(largestOf[t], faceOf(j));
  });
  const size_t faces = *std::max_element(largestOf.begin(), largestOf.end()) + 1;
  const double inf = std::numeric_limits<double>::infinity();
  using Box = std::array<double, 6>;
  std::vector<std::vector<Box>> boxOf(threads, std::vector<Box>(faces, Box{ inf, inf, inf, -inf, -inf, -inf }));
  auto include = [](Box& into, const Box& b) {
    for (int k = 0; k < 3; ++k)
    {
      into[k] = std::min(into[k], b[k]);
      into[3 + k] = std::max(into[3 + k], b[3 + k]);
    }
  };
  // count[t][f]: the samples of face f in core t's range.
  std::vector<std::vector<size_t>> count(threads, std::vector<size_t>(faces, 0));
  each([&](unsigned t) {
    const auto [first, last] = range(t);
    for (size_t j = first; j < last; ++j)
    {
      const size_t f = faceOf(j);
      const auto& p = samples[index(j)].Point;
      ++count[t][f];
      include(boxOf[t][f], Box{ p[0], p[1], p[2], p[0], p[1], p[2] });
    }
  });
  std::vector<Box>& box = boxOf[0];
  for (unsigned t = 1; t < threads; ++t)
    for (size_t f = 0; f < faces; ++f)
      include(box[f], boxOf[t][f]);
  // Where each core's samples of each face go (by face, then core: stable), and each face's run.
  std::vector<size_t> start(faces + 1, 0);
  {
    size_t at = 0;
    for (size_t f = 0; f < faces; ++f)
    {
      start[f] = at;
      for (unsigned t = 0; t < threads; ++t)
      {
        const size_t c = count[t][f];
        count[t][f] = at;
        at += c;
      }
    }
    start[faces] = at;
  }
  // Keys (Morton code, position), put in their face's run. The whole order of the ExpansionCard's
  // 92,898 samples: 2.0 ms on this two-core machine, against 4.0 ms for a global radix sort of
  // (face, code) keys and 6 ms for a comparison sort; it saves about 10 ms of the solve.
  struct Key
  {
    uint32_t Code, At;
  };
  std::vector<Key> keys(n);
  each([&](unsigned t) {
    const auto [first, last] = range(t);
    std::vector<size_t>& to = count[t];
    for (size_t j = first; j < last; ++j)
    {
      const size_t f = faceOf(j);
      keys[to[f]++] = { MortonCode(box[f], samples[index(j)].Point), static_cast<uint32_t>(j) };
    }
  });
  // Each face's run sorted by its codes: a stable radix sort of three 10-bit digits in the run
  // (which the cache holds), runs of up to 32 by insertion; the faces dealt out to the cores.
  std::atomic<size_t> nextFace{ 0 };
  each([&](unsigned) {
    std::vector<Key> tmp;
    std::array<uint32_t, 1025> digits;
    for (size_t f; (f = nextFace.fetch_add(1)) < faces;)
    {
      Key* run = keys.data() + start[f];
      const size_t len = start[f + 1] - start[f];
      if (len <= 32)
      {
        for (size_t i = 1; i < len; ++i)
          for (size_t k = i; k > 0 && run[k - 1].Code > run[k].Code; --k)
            std::swap(run[k - 1], run[k]);
        continue;
      }
      tmp.resize(len);
      Key* from = run;
      Key* to = tmp.data();
      for (int shift = 0; shift < 30; shift += 10)
      {
        digits.fill(0u);
        for (size_t i = 0; i < len; ++i)
          ++digits[((from[i].Code >> shift) & 1023u) + 1];
        for (int d = 0; d < 1024; ++d)
          digits[d + 1] += digits[d];
        for (size_t i = 0; i < len; ++i)
          to[digits[(from[i].Code >> shift) & 1023u]++] = from[i];
        std::swap(from, to);
      }
      // (Three passes: the sorted run is in tmp.)
      std::copy(from, from + len, run);
    }
  });
  std::vector<size_t> order(n);
  each([&](unsigned t) {
    const auto [first, last] = range(t);
    for (size_t j = first; j < last; ++j)
      order[j] = index(keys[j].At);
  });
  return order;
}

std::vector<Sample> SamplesFromMesh(const BRepModel& model, const SolverData& data)
{
  const DisplayMesh& M = model.Mesh;
  const size_t nPoints = M.NumberOfPoints();
  std::vector<Sample> out(nPoints);
  for (size_t i = 0; i < out.size(); ++i)
  {
    out[i].Face = M.FaceIds[i];
    out[i].U = M.UV[2 * i];
    out[i].V = M.UV[2 * i + 1];
    out[i].Point = { M.Points[3 * i], M.Points[3 * i + 1], M.Points[3 * i + 2] };
    out[i].Direction = { -M.Normals[3 * i], -M.Normals[3 * i + 1], -M.Normals[3 * i + 2] };
    if (M.Curvatures.size() == 2 * nPoints)
      out[i].Curvature = { M.Curvatures[2 * i], M.Curvatures[2 * i + 1] };
  }
  // Vertices on a face's boundary: at a convex edge the sphere tangent there has radius 0 and
  // Newton would chase t -> 0. Move them 1e-2 of the way to an adjacent triangle's centroid
  // (in UV, on the patches), where the sphere is small but well defined, also in float.
  // The triangles' edges, each under its lower vertex (counting sort): an edge used once lies
  // on the boundary.
  const size_t nt = M.TriangleFace.size();
  const size_t nv = out.size();
  std::vector<int> start(nv + 1, 0);
  auto edge = [&](size_t t, int k) {
    const int a = M.Triangles[3 * t + k], b = M.Triangles[3 * t + (k + 1) % 3];
    return std::make_pair(std::min(a, b), std::max(a, b));
  };
  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k)
      ++start[static_cast<size_t>(edge(t, k).first) + 1];
  for (size_t v = 0; v < nv; ++v)
    start[v + 1] += start[v];
  std::vector<int> other(static_cast<size_t>(start[nv]));
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (size_t t = 0; t < nt; ++t)
      for (int k = 0; k < 3; ++k)
      {
        const auto e = edge(t, k);
        other[static_cast<size_t>(fill[static_cast<size_t>(e.first)]++)] = e.second;
      }
  }
  auto uses = [&](int lo, int hi) {
    return std::count(other.begin() + start[static_cast<size_t>(lo)],
      other.begin() + start[static_cast<size_t>(lo) + 1], hi);
  };
  std::vector<int> adjacent(nv, -1);
  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k)
    {
      const auto e = edge(t, k);
      if (uses(e.first, e.second) == 1)
        adjacent[static_cast<size_t>(e.first)] = adjacent[static_cast<size_t>(e.second)] =
          static_cast<int>(t);
    }
  // Each face's exact surface as the packing gives it to the kernels (none where its description
  // misses the face's own patches), for the projection below.
  std::vector<CheckedExactSurface> exact(model.Faces.size());
  ParallelFor(model.Faces.size(), 0,
    [&](size_t f) { exact[f] = CheckExactSurface(model, static_cast<int>(f)); });
  // The trim test below among the segments its patch's block keeps (BlockTrimCandidates; every
  // segment of the face where the point lies outside the face's patch grid), with the crossing
  // parity from a CrossingIndex: ClassifyPoint's answers, without scanning the face's every
  // segment per point (a third of the time of this function on the Ploopy thumb trackball's
  // body, whose faces have up to thousands of segments).
  const BlockTrimCandidates blocks(model, [](const Face&) { return 0.0; });
  const CrossingIndex crossings(model);
  // A face with many segments and many samples on its boundary (a plate of hundreds of holes,
  // one patch and so one block, whose list is the face's every segment) also gets them by the
  // cells of a Cells x Cells grid over its UV bounds, each cell's list the candidates that can
  // hold the nearest trimming point of some point of the cell (TrimCandidatesFor: the same
  // answers): a sample whose tries all lie in one cell searches that cell's. Scanning the
  // block's thousands at every sample was 1 s of a perforated card guide's 100,645 samples.
  // The grid costs Cells^2 scans of the face's segments, each sample's search a scan of its
  // block's list: it is made where those lists add up to more than twice the grid's cost.
  constexpr int Cells = 16;
  constexpr size_t ManySegments = 256;
  // What the samples would scan without it: their blocks' lists (the face's where its patches
  // have no grid).
  std::vector<double> scans(model.Faces.size(), 0.0);
  for (size_t i = 0; i < nv; ++i)
  {
    const size_t f = static_cast<size_t>(out[i].Face);
    if (adjacent[i] < 0 || model.Faces[f].PatchCount == 0 ||
      blocks.OfFace(f).size() < ManySegments)
      continue;
    const std::vector<TrimCandidate>& list = data.FaceBreaks.empty()
      ? blocks.OfFace(f)
      : blocks.For(model,
          static_cast<size_t>(FindPatchFast(model, data, out[i].Face, out[i].U, out[i].V)));
    scans[f] += static_cast<double>(list.size());
  }
  std::vector<std::vector<std::vector<TrimCandidate>>> cellCandidates(model.Faces.size());
  ParallelFor(model.Faces.size(), 0, [&](size_t f) {
    const Face& F = model.Faces[f];
    if (blocks.OfFace(f).size() < ManySegments ||
      !(scans[f] > 2.0 * Cells * Cells * static_cast<double>(blocks.OfFace(f).size())) ||
      !(F.Domain[1] > F.Domain[0]) || !(F.Domain[3] > F.Domain[2]))
      return;
    auto& cells = cellCandidates[f];
    cells.resize(static_cast<size_t>(Cells * Cells));
    const double du = (F.Domain[1] - F.Domain[0]) / Cells, dv = (F.Domain[3] - F.Domain[2]) / Cells;
    for (int i = 0; i < Cells; ++i)
      for (int j = 0; j < Cells; ++j)
        cells[static_cast<size_t>(i * Cells + j)] = TrimCandidatesFor(model, blocks.OfFace(f),
          { F.Domain[0] + du * i, F.Domain[2] + dv * j, F.Domain[0] + du * (i + 1),
            F.Domain[2] + dv * (j + 1) });
  });
  // The cell of face f that holds the UV box (u0, v0, u1, v1), or null.
  auto cellFor = [&](size_t f, double u0, double v0, double u1, double v1)
    -> const std::vector<TrimCandidate>* {
    if (cellCandidates[f].empty())
      return nullptr;
    const Face& F = model.Faces[f];
    const double du = (F.Domain[1] - F.Domain[0]) / Cells, dv = (F.Domain[3] - F.Domain[2]) / Cells;
    const double x = (u0 - F.Domain[0]) / du, y = (v0 - F.Domain[2]) / dv;
    if (!(x >= 0.0 && y >= 0.0 && x < Cells && y < Cells))
      return nullptr;
    const int i = static_cast<int>(x), j = static_cast<int>(y);
    // The cell's own bounds, as TrimCandidatesFor took them.
    if (!(u0 >= F.Domain[0] + du * i && u1 <= F.Domain[0] + du * (i + 1) &&
          v0 >= F.Domain[2] + dv * j && v1 <= F.Domain[2] + dv * (j + 1)))
      return nullptr;
    return &cellCandidates[f][static_cast<size_t>(i * Cells + j)];
  };
  auto insideTrim = [&](int face, double u, double v, const std::vector<TrimCandidate>* cell) {
    const size_t f = static_cast<size_t>(face);
    const Face& F = model.Faces[f];
    const std::vector<TrimCandidate>* among = &blocks.OfFace(f);
    if (cell)
      among = cell;
    else if (F.PatchCount > 0 && !data.FaceBreaks.empty())
    {
      const int p = FindPatchFast(model, data, face, u, v);
      const BezierPatch& P = model.Patches[static_cast<size_t>(p)];
      if (u >= P.Domain[0] && u <= P.Domain[1] && v >= P.Domain[2] && v <= P.Domain[3])
        among = &blocks.For(model, static_cast<size_t>(p));
    }
    return ClassifyPointAmong(model, u, v, *among,
      data.FaceLoopsCross.size() == model.Faces.size() ? data.FaceLoopsCross[f] : -1.0, &crossings)
      .Inside;
  };
  // Every core: each sample on its own.
  ParallelFor(nv, 0, [&](size_t i) {
    const int t = adjacent[i];
    Sample& s = out[i];
    const Face& F = model.Faces[s.Face];
    if (t < 0 || F.PatchCount == 0)
      return;
    double cu = 0.0, cv = 0.0;
    for (int k = 0; k < 3; ++k)
    {
      cu += M.UV[2 * M.Triangles[3 * t + k]] / 3.0;
      cv += M.UV[2 * M.Triangles[3 * t + k] + 1] / 3.0;
    }
    // The centroid lies inside the mesh's polygon, which leaves a face where its boundary curves
    // away from a long chord: the Original Prusa i3's extruder body had a nudged sample 1.3e-3 mm
    // off its face, its sphere (2t = 0.0016) centred outside the part. A point outside the
    // face's trim (ClassifyPoint, 0.7-3.2 us) is nudged half as far, up to six times; where
    // none lies inside, the vertex itself, on the face's boundary, is the sample (a nudged
    // sample of the Original Prusa i3's IR sensor holder stayed 1.6e-6 outside in UV, 7e-4 mm
    // off its B-spline face).
    const double u0 = s.U, v0 = s.V;
    const double u1 = u0 + 1e-2 * (cu - u0), v1 = v0 + 1e-2 * (cv - v0);
    const std::vector<TrimCandidate>* cell = cellFor(static_cast<size_t>(s.Face),
      std::min(u0, u1), std::min(v0, v1), std::max(u0, u1), std::max(v0, v1));
    double step = 1e-2;
    bool inside = false;
    for (int tries = 0; tries < 7 && !inside; ++tries, step *= 0.5)
    {
      s.U = u0 + step * (cu - u0);
      s.V = v0 + step * (cv - v0);
      inside = insideTrim(s.Face, s.U, s.V, cell);
    }
    if (!inside)
    {
      s.U = u0;
      s.V = v0;
    }
    // (The sample keeps its vertex's curvatures: on a face's boundary the reader takes them
    // where such a sample moves, just inside the face, the smallest largest of them.)
    const PatchEval e =
      EvaluatePatch(model.Patches[FindPatchFast(model, data, s.Face, s.U, s.V)], s.U, s.V);
    Vec3 n{ e.Du[1] * e.Dv[2] - e.Du[2] * e.Dv[1], e.Du[2] * e.Dv[0] - e.Du[0] * e.Dv[2],
      e.Du[0] * e.Dv[1] - e.Du[1] * e.Dv[0] };
    const double len = std::sqrt(Dot(n, n));
    if (!(len > 0.0))
      return; // singular point of the patch: keep the exact sample
    const double sign = F.Reversed ? 1.0 : -1.0; // inward = -outward
    s.Point = e.P;
    s.Direction = { sign * n[0] / len, sign * n[1] / len, sign * n[2] / len };
    // On an analytic face, back onto the exact surface (the patches lie up to the tolerance off).
    ProjectOnExactSurface(exact[static_cast<size_t>(s.Face)], s.Point, s.Direction,
      2.0 * model.Tolerance);
  });
  return out;
}

} // namespace brt
