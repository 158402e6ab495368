// BRepThickness: point-in-face test on the cubic trimming segments alone (paper eq. 6 and the
// corner rule). Free of VTK and OpenCASCADE; the OpenCL kernels implement the same steps.
#pragma once

#include "BRepModel.h"

#include <memory>
#include <mutex>
#include <vector>

namespace brt
{

struct TrimProjection
{
  bool Inside = false;
  double Distance = 0.0; ///< UV distance from the query point to the nearest trimming point
  int Segment = -1;      ///< index into BRepModel::TrimSegments of the nearest segment
  double Parameter = 0.0; ///< local parameter on that segment, in [0,1]
  bool Corner = false;   ///< the nearest point is a C0 junction decided by the corner rule
};

/// The box of a segment's four control points (u0, v0, u1, v1): it holds the segment (convex
/// hull property).
std::array<double, 4> SegmentBox(const std::array<double, 8>& cp);

/// Nearest point on one cubic 2D segment: Newton on eq. 6 started from the projection on the
/// polyline through c(0), c(1/3), c(2/3), c(1). Returns the local parameter in [0,1].
double ProjectOnSegment(const std::array<double, 8>& cp, double u, double v, double* distance);

/// Classifies (u,v) against all loops of `face`. Inside iff the cross product
/// (c'(t_p) x (P - c(t_p)))_w > 0 with loops oriented material-on-the-left; when the nearest
/// point is the junction of two segments that are not tangent-continuous, the corner rule
/// applies (a left turn is convex: outside; a right turn is concave: inside), but where the two
/// tangents lie within 1e-3 rad of each other or of opposite (a cusp), InsideByCrossings decides.
///
/// loopsCross: the face's TrimLoopsCross where known; where it is not negative (the face's loops
/// cross), a point farther from the trim than four times it (and 1e-9 of the domain) takes
/// InsideByCrossings' answer, as in the kernel's classify.
TrimProjection ClassifyPoint(
  const BRepModel& model, int face, double u, double v, double loopsCross = -1.0);

/// A trimming segment of a face with its control box (SegmentBox), for ClassifyPoint over a
/// part of the face's segments.
struct TrimCandidate
{
  int Loop = -1, Segment = -1;
  std::array<double, 4> Box{};
  /// The control polygon has a length (ClassifyPoint passes over the segments that have none).
  bool HasLength = false;
};

/// Every trimming segment of `face` with its box, loop by loop in the face's order, into `out`
/// (cleared first).
void FaceTrimCandidates(const BRepModel& model, int face, std::vector<TrimCandidate>& out);

/// The segments of `face` that can hold the nearest trimming point of some point of the UV box
/// (u0, v0, u1, v1): every segment whose control box lies within U of the box, U the largest
/// distance from the box to the nearest end of a segment (no point of the box is farther than U
/// from its nearest trimming point), with a margin for rounding, and every segment whose box
/// lies within `reach` of it. In the face's order.
std::vector<TrimCandidate> TrimCandidatesFor(
  const BRepModel& model, int face, const std::array<double, 4>& uvBox, double reach = 0.0);

/// The same choice among `from` (candidates for a box that holds uvBox).
std::vector<TrimCandidate> TrimCandidatesFor(const BRepModel& model,
  const std::vector<TrimCandidate>& from, const std::array<double, 4>& uvBox, double reach = 0.0);

/// Independent point-in-face test by the parity of the crossings of a ray from (u,v) towards +u
/// with the loops, each cubic segment flattened to 16 chords. Meant for points farther from the
/// loops than the chords' error, as a second opinion beside ClassifyPoint.
bool InsideByCrossings(const BRepModel& model, int face, double u, double v);

/// InsideByCrossings' answers for many points of a model: each face's segments listed once in
/// bands of v (each in every band its control box spans, widened as InsideByCrossings widens it),
/// so that a point tests only the segments of its band, each by InsideByCrossings' own steps, not
/// every segment of its face. The same answer bit for bit: a segment whose box misses v has no
/// chord across v, and every segment whose box holds v is listed in v's band (the bands are
/// monotone in v). A face's bands are built on its first query, from any thread.
class CrossingIndex
{
public:
  explicit CrossingIndex(const BRepModel& model);
  ~CrossingIndex();
  CrossingIndex(const CrossingIndex&) = delete;
  CrossingIndex& operator=(const CrossingIndex&) = delete;

  bool Inside(int face, double u, double v) const;

private:
  struct FaceBands;
  const FaceBands& For(int face) const;
  const BRepModel& Model;
  std::unique_ptr<FaceBands[]> Faces;
  std::unique_ptr<std::once_flag[]> Built;
};

/// ClassifyPoint over the candidates TrimCandidatesFor gave for a UV box that holds (u, v): the
/// same answer, without scanning the face's other segments. With `crossings`, the parity tests
/// it takes (above) are that index's.
TrimProjection ClassifyPointAmong(const BRepModel& model, double u, double v,
  const std::vector<TrimCandidate>& candidates, double loopsCross = -1.0,
  const CrossingIndex* crossings = nullptr);

/// Whether the trimming loops of `face` cross themselves or each other, the segments taken as
/// InsideByCrossings' 16 chords each (a proper crossing of two chords, neither at the two
/// segments' shared end): -1 where none cross, else a bound on the chords' distance from their
/// segments, over the face's segments (6 / 8 / 16^2 times the largest second difference of a
/// segment's control points). A loop that crosses itself (a lobe that runs the wrong way round, a
/// hook at a corner) puts points beside the lobe on the wrong side of its nearer curve at any
/// distance: the kernel's classify takes the crossing parity on such a face farther than a few
/// of these bounds from the trim (docs/Solver.md, item 5, "Loops that cross themselves").
double TrimLoopsCross(const BRepModel& model, int face);

} // namespace brt
