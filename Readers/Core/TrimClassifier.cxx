#include "TrimClassifier.h"

#include "Bezier.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace brt
{

namespace
{
inline double Cross(double ax, double ay, double bx, double by)
{
  return ax * by - ay * bx;
}

inline double Length2(const std::array<double, 8>& cp)
{
  double l = 0.0;
  for (int i = 0; i < 3; ++i)
  {
    const double du = cp[2 * i + 2] - cp[2 * i], dv = cp[2 * i + 3] - cp[2 * i + 1];
    l += std::sqrt(du * du + dv * dv);
  }
  return l;
}

/// Tangent direction at local t, robust to vanishing derivatives at the ends.
std::array<double, 2> Tangent(const std::array<double, 8>& cp, double t)
{
  const auto e = EvaluateCubic<2>(cp.data(), t);
  const double scale = Length2(cp);
  if (std::hypot(e.D1[0], e.D1[1]) > 1e-12 * scale)
  {
    return { e.D1[0], e.D1[1] };
  }
  // Coincident control points: use the first non-zero chord from (or to) that end.
  if (t < 0.5)
  {
    for (int i = 1; i < 4; ++i)
    {
      const double du = cp[2 * i] - cp[0], dv = cp[2 * i + 1] - cp[1];
      if (std::hypot(du, dv) > 1e-12 * scale)
        return { du, dv };
    }
  }
  else
  {
    for (int i = 2; i >= 0; --i)
    {
      const double du = cp[6] - cp[2 * i], dv = cp[7] - cp[2 * i + 1];
      if (std::hypot(du, dv) > 1e-12 * scale)
        return { du, dv };
    }
  }
  return { cp[6] - cp[0], cp[7] - cp[1] };
}
} // namespace

std::array<double, 4> SegmentBox(const std::array<double, 8>& cp)
{
  std::array<double, 4> b{ cp[0], cp[1], cp[0], cp[1] };
  for (int i = 2; i < 8; i += 2)
  {
    b[0] = cp[i] < b[0] ? cp[i] : b[0];
    b[1] = cp[i + 1] < b[1] ? cp[i + 1] : b[1];
    b[2] = cp[i] > b[2] ? cp[i] : b[2];
    b[3] = cp[i + 1] > b[3] ? cp[i + 1] : b[3];
  }
  return b;
}

double ProjectOnSegment(const std::array<double, 8>& cp, double u, double v, double* distance)
{
  // Start: projection on the polyline c(0), c(1/3), c(2/3), c(1).
  std::array<std::array<double, 2>, 4> poly;
  for (int i = 0; i < 4; ++i)
  {
    const auto e = EvaluateCubic<2>(cp.data(), i / 3.0);
    poly[i] = { e.P[0], e.P[1] };
  }
  double bestT = 0.0, bestD2 = std::numeric_limits<double>::max();
  for (int i = 0; i < 3; ++i)
  {
    const double ax = poly[i + 1][0] - poly[i][0], ay = poly[i + 1][1] - poly[i][1];
    const double len2 = ax * ax + ay * ay;
    double tau = len2 > 0.0 ? ((u - poly[i][0]) * ax + (v - poly[i][1]) * ay) / len2 : 0.0;
    tau = std::clamp(tau, 0.0, 1.0);
    const double px = poly[i][0] + tau * ax - u, py = poly[i][1] + tau * ay - v;
    const double d2 = px * px + py * py;
    if (d2 < bestD2)
    {
      bestD2 = d2;
      bestT = (i + tau) / 3.0;
    }
  }
  // Newton on f(t) = (c(t) - P) . c'(t) = 0 (eq. 6), clamped to the segment.
  double t = bestT;
  for (int it = 0; it < 12; ++it)
  {
    const auto e = EvaluateCubic<2>(cp.data(), t);
    const double rx = e.P[0] - u, ry = e.P[1] - v;
    const double f = rx * e.D1[0] + ry * e.D1[1];
    const double df = e.D1[0] * e.D1[0] + e.D1[1] * e.D1[1] + rx * e.D2[0] + ry * e.D2[1];
    if (df <= 0.0)
    {
      break; // not a minimum locally: keep the best so far
    }
    const double next = std::clamp(t - f / df, 0.0, 1.0);
    const double step = std::fabs(next - t);
    t = next;
    if (step < 1e-15)
    {
      break;
    }
  }
  // Keep the best of the Newton result and both ends.
  double best = std::numeric_limits<double>::max();
  double bestParam = t;
  for (double cand : { t, 0.0, 1.0 })
  {
    const auto e = EvaluateCubic<2>(cp.data(), cand);
    const double du = e.P[0] - u, dv = e.P[1] - v;
    const double d = std::sqrt(du * du + dv * dv);
    if (d < best)
    {
      best = d;
      bestParam = cand;
    }
  }
  if (distance)
  {
    *distance = best;
  }
  return bestParam;
}

std::vector<TrimCandidate> TrimCandidatesFor(const BRepModel& model,
  const std::vector<TrimCandidate>& from, const std::array<double, 4>& uvBox, double reach)
{
  // U: the smallest over the segments (of non-zero length: ClassifyPoint skips the others) of
  // the farthest distance from the box to one of the segment's ends. ClassifyPoint's distance
  // is at most a point's distance to such an end (it keeps the better of its Newton and the
  // ends), so no segment whose box lies farther than U is ever kept.
  double u2 = std::numeric_limits<double>::infinity();
  auto farthest2 = [&](double x, double y) {
    const double dx = std::max(std::fabs(x - uvBox[0]), std::fabs(x - uvBox[2]));
    const double dy = std::max(std::fabs(y - uvBox[1]), std::fabs(y - uvBox[3]));
    return dx * dx + dy * dy;
  };
  for (const TrimCandidate& c : from)
  {
    if (!c.HasLength)
      continue;
    const auto& cp = model.TrimSegments[c.Segment].ControlPoints;
    u2 = std::min(u2, std::min(farthest2(cp[0], cp[1]), farthest2(cp[6], cp[7])));
  }
  // The margin: rounding in the distances compared (relative 1e-6, far above it).
  const double limit2 = std::max(u2 * (1.0 + 1e-6), reach * reach);
  auto keep = [&](const TrimCandidate& c) {
    const double du = std::max({ c.Box[0] - uvBox[2], uvBox[0] - c.Box[2], 0.0 });
    const double dv = std::max({ c.Box[1] - uvBox[3], uvBox[1] - c.Box[3], 0.0 });
    return !(du * du + dv * dv > limit2);
  };
  // Counted first: the lists are kept (a block's for all its patches), at their size.
  size_t kept = 0;
  for (const TrimCandidate& c : from)
    kept += keep(c);
  std::vector<TrimCandidate> near;
  near.reserve(kept);
  for (const TrimCandidate& c : from)
    if (keep(c))
      near.push_back(c);
  return near;
}

void FaceTrimCandidates(const BRepModel& model, int face, std::vector<TrimCandidate>& out)
{
  out.clear();
  const Face& f = model.Faces[face];
  for (int l = f.FirstLoop; l < f.FirstLoop + f.LoopCount; ++l)
  {
    const TrimLoop& loop = model.Loops[l];
    for (int s = loop.FirstSegment; s < loop.FirstSegment + loop.SegmentCount; ++s)
      out.push_back({ l, s, SegmentBox(model.TrimSegments[s].ControlPoints),
        Length2(model.TrimSegments[s].ControlPoints) > 0.0 });
  }
}

std::vector<TrimCandidate> TrimCandidatesFor(
  const BRepModel& model, int face, const std::array<double, 4>& uvBox, double reach)
{
  std::vector<TrimCandidate> all;
  FaceTrimCandidates(model, face, all);
  return TrimCandidatesFor(model, all, uvBox, reach);
}

namespace
{
// ClassifyPoint over `candidates` (every segment of the face, or those TrimCandidatesFor kept).
TrimProjection Classify(const BRepModel& model, double u, double v,
  const TrimCandidate* candidates, size_t count, double loopsCross,
  const CrossingIndex* crossings = nullptr)
{
  auto insideByCrossings = [&](int face) {
    return crossings ? crossings->Inside(face, u, v) : InsideByCrossings(model, face, u, v);
  };
  TrimProjection res;
  res.Distance = std::numeric_limits<double>::max();
  int bestLoop = -1;
  // The segment after the nearest: a tie within rounding that puts the point on the other side
  // hands the decision to the crossings (below).
  double secondDistance = std::numeric_limits<double>::max(), secondParameter = 0.0;
  int secondSegment = -1;
  // Two distances within this (relative) of each other are a tie (the kernel's TRIM_TIE in
  // double); the search keeps every segment whose box lies within it of the best distance.
  const double tie = 1e-6;
  // The nearest segment, ties to the lowest index. A cubic lies in the box of its control
  // points, so a segment whose box is farther than the best distance so far cannot be nearer
  // and is not projected: first the segment with the nearest box, then the others in order.
  auto consider = [&](const TrimCandidate& c) {
    if (!c.HasLength)
      return;
    const int l = c.Loop, s = c.Segment;
    const auto& cp = model.TrimSegments[s].ControlPoints;
    double d = 0.0;
    const double t = ProjectOnSegment(cp, u, v, &d);
    if (d < res.Distance || (d == res.Distance && s < res.Segment))
    {
      secondDistance = res.Distance;
      secondParameter = res.Parameter;
      secondSegment = res.Segment;
      res.Distance = d;
      res.Segment = s;
      res.Parameter = t;
      bestLoop = l;
    }
    else if (d < secondDistance || (d == secondDistance && s < secondSegment))
    {
      secondDistance = d;
      secondParameter = t;
      secondSegment = s;
    }
  };
  // Each segment's box distance once (the s1 sampling classifies every candidate point of every
  // patch: this scan was a sixth of a filter's preparation on NIST_MBE_PMI_11), on the stack for
  // the short lists of TrimCandidatesFor. (A thread_local vector cost the plugin, a shared
  // library, a call of __tls_get_addr each time: the filter's preparation took 5-17% longer on
  // four free-form parts, docs/Solver.md, "Host layer".)
  constexpr size_t stackGaps = 256;
  double gapsOnStack[stackGaps];
  std::vector<double> gapsOnHeap;
  if (count > stackGaps)
    gapsOnHeap.resize(count);
  double* boxGap = count > stackGaps ? gapsOnHeap.data() : gapsOnStack;
  size_t first = count;
  double firstBound = std::numeric_limits<double>::max();
  for (size_t k = 0; k < count; ++k)
  {
    const std::array<double, 4>& bx = candidates[k].Box;
    const double du = u < bx[0] ? bx[0] - u : (u > bx[2] ? u - bx[2] : 0.0);
    const double dv = v < bx[1] ? bx[1] - v : (v > bx[3] ? v - bx[3] : 0.0);
    const double b = du * du + dv * dv;
    boxGap[k] = b;
    if (b < firstBound)
    {
      firstBound = b;
      first = k;
    }
  }
  if (first < count)
    consider(candidates[first]);
  for (size_t k = 0; k < count; ++k)
  {
    // The margin keeps rounding in the projection from dropping a segment that ties.
    const double bound = res.Distance * (1.0 + tie);
    if (k != first && !(boxGap[k] > bound * bound))
      consider(candidates[k]);
  }
  if (res.Segment < 0)
  {
    return res; // no trimming curve: nothing is inside
  }
  // A face whose loops cross (TrimLoopsCross): the parity farther than four chords' errors from
  // the trim (the kernel's classify, the same rule).
  if (loopsCross >= 0.0)
  {
    const int face = model.TrimSegments[static_cast<size_t>(res.Segment)].Face;
    const std::array<double, 4>& d = model.Faces[static_cast<size_t>(face)].Domain;
    if (res.Distance > 4.0 * loopsCross + 1e-9 * (d[1] - d[0] + d[3] - d[2]))
    {
      res.Inside = insideByCrossings(face);
      return res;
    }
  }
  const TrimLoop& loop = model.Loops[bestLoop];
  const auto& cp = model.TrimSegments[res.Segment].ControlPoints;
  const auto e = EvaluateCubic<2>(cp.data(), res.Parameter);
  const double px = u - e.P[0], py = v - e.P[1];

  // A sliver, a segment a thousandth of the point's distance long, says nothing of the side a
  // point so far off lies on, and a loop's gap or a pcurve's tail can leave one that turns back
  // (a bridge 3.7e-4 long pointing backwards on the Framework logo cover's face 11). The nearest
  // point on a sliver is taken as a corner, and a corner's sides are the segments next to it that
  // are not slivers (the kernel's classify, the same steps).
  const double sliver = 1e-3 * std::sqrt(px * px + py * py);
  const bool onSliver = !(Length2(cp) > sliver);
  // The nearest segment that is not a sliver from s along the loop in dir (s itself left out);
  // any with a length where all are slivers, s where none has one.
  auto neighbour = [&](int s, int dir) {
    int idx = s - loop.FirstSegment, any = -1;
    for (int k = 0; k + 1 < loop.SegmentCount; ++k)
    {
      idx = (idx + dir + loop.SegmentCount) % loop.SegmentCount;
      const double len = Length2(model.TrimSegments[loop.FirstSegment + idx].ControlPoints);
      if (len > 0.0 && any < 0)
        any = loop.FirstSegment + idx;
      if (len > sliver)
        return loop.FirstSegment + idx;
    }
    return any >= 0 ? any : s;
  };

  const double endEps = 1e-9;
  if (res.Parameter > endEps && res.Parameter < 1.0 - endEps && !onSliver)
  {
    const auto tg = Tangent(cp, res.Parameter);
    res.Inside = Cross(tg[0], tg[1], px, py) > 0.0;
    // A second segment as near (within the tie) that puts the point on the other side: the
    // point lies beside a part of the face (or of a hole) far thinner than its distance, whose
    // two sides' curves run together and may cross (a sliver face's tip); the crossings decide
    // (the kernel's classify, the same steps).
    if (secondSegment >= 0 && secondDistance <= res.Distance * (1.0 + tie) &&
      secondParameter > endEps && secondParameter < 1.0 - endEps)
    {
      const auto& cp2 = model.TrimSegments[secondSegment].ControlPoints;
      const auto e2 = EvaluateCubic<2>(cp2.data(), secondParameter);
      const auto tg2 = Tangent(cp2, secondParameter);
      if (Length2(cp2) > sliver &&
        (Cross(tg2[0], tg2[1], u - e2.P[0], v - e2.P[1]) > 0.0) != res.Inside)
        res.Inside = insideByCrossings(model.TrimSegments[res.Segment].Face);
    }
    return res;
  }
  // At a corner: incoming segment a (ending there) and outgoing segment b (starting there).
  const int incoming = (onSliver || res.Parameter <= endEps) ? neighbour(res.Segment, -1) : res.Segment;
  const int outgoing = (onSliver || res.Parameter > endEps) ? neighbour(res.Segment, +1) : res.Segment;
  const std::array<double, 2> ta = Tangent(model.TrimSegments[incoming].ControlPoints, 1.0);
  const std::array<double, 2> tb = Tangent(model.TrimSegments[outgoing].ControlPoints, 0.0);
  const double sa = Cross(ta[0], ta[1], px, py);
  const double sb = Cross(tb[0], tb[1], px, py);
  if ((sa > 0.0) == (sb > 0.0))
  {
    res.Inside = sa > 0.0;
    return res;
  }
  // Corner rule: a left turn (convex corner) keeps the region near the vertex outside,
  // a right turn (concave corner) inside. Where the tangents lie within a thousandth of a radian
  // of each other or of opposite (a loop that turns back on itself at a cusp, or a corner all
  // but smooth), the turn's sign is rounding, and the crossing parity decides, as in the
  // kernel's classify (docs/Solver.md, Open items, "The corner rule at a cusp").
  // Likewise where slivers lie between the corner's two sides: they turn the loop too, and the
  // turn from one side to the other alone may take the wrong way round (a spike's tip whose
  // fillet ends a little short of the way back, then a sliver: the kernel's classify).
  res.Corner = true;
  const double turn = Cross(ta[0], ta[1], tb[0], tb[1]);
  const bool adjacent =
    loop.FirstSegment + (incoming - loop.FirstSegment + 1) % loop.SegmentCount == outgoing;
  if (!adjacent || std::fabs(turn) < 1e-3 * std::hypot(ta[0], ta[1]) * std::hypot(tb[0], tb[1]))
    res.Inside = insideByCrossings(model.TrimSegments[res.Segment].Face);
  else
    res.Inside = turn < 0.0;
  return res;
}
} // namespace

TrimProjection ClassifyPoint(
  const BRepModel& model, int face, double u, double v, double loopsCross)
{
  thread_local std::vector<TrimCandidate> all;
  FaceTrimCandidates(model, face, all);
  return Classify(model, u, v, all.data(), all.size(), loopsCross);
}

TrimProjection ClassifyPointAmong(const BRepModel& model, double u, double v,
  const std::vector<TrimCandidate>& candidates, double loopsCross, const CrossingIndex* crossings)
{
  return Classify(model, u, v, candidates.data(), candidates.size(), loopsCross, crossings);
}

double TrimLoopsCross(const BRepModel& model, int face)
{
  const Face& F = model.Faces[static_cast<size_t>(face)];
  struct Piece
  {
    int Loop, Index, Count; // the segment's loop, its place in it, the loop's length
    std::array<double, 34> P; // 17 points: the 16 chords' ends
    std::array<double, 4> Box;
  };
  std::vector<Piece> pieces;
  double chordError = 0.0;
  for (int l = F.FirstLoop; l < F.FirstLoop + F.LoopCount; ++l)
  {
    const TrimLoop& L = model.Loops[static_cast<size_t>(l)];
    for (int k = 0; k < L.SegmentCount; ++k)
    {
      const auto& cp = model.TrimSegments[static_cast<size_t>(L.FirstSegment + k)].ControlPoints;
      if (!(Length2(cp) > 0.0))
        continue;
      Piece pc;
      pc.Loop = l;
      pc.Index = k;
      pc.Count = L.SegmentCount;
      pc.Box = { std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
        -std::numeric_limits<double>::max(), -std::numeric_limits<double>::max() };
      for (int j = 0; j <= 16; ++j)
      {
        const auto e = EvaluateCubic<2>(cp.data(), j / 16.0);
        pc.P[2 * j] = e.P[0];
        pc.P[2 * j + 1] = e.P[1];
        pc.Box[0] = std::min(pc.Box[0], e.P[0]);
        pc.Box[1] = std::min(pc.Box[1], e.P[1]);
        pc.Box[2] = std::max(pc.Box[2], e.P[0]);
        pc.Box[3] = std::max(pc.Box[3], e.P[1]);
      }
      for (int i = 0; i < 2; ++i)
        chordError = std::max(chordError,
          6.0 / 8.0 / 256.0 *
            std::hypot(cp[2 * i + 4] - 2.0 * cp[2 * i + 2] + cp[2 * i],
              cp[2 * i + 5] - 2.0 * cp[2 * i + 3] + cp[2 * i + 1]));
      pieces.push_back(pc);
    }
  }
  auto orient = [](const double* a, const double* b, const double* c) {
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  };
  // Chords ab and cd cross properly: each one's ends strictly on either side of the other.
  auto cross = [&](const double* a, const double* b, const double* c, const double* d) {
    const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a),
                 o4 = orient(c, d, b);
    return ((o1 > 0.0 && o2 < 0.0) || (o1 < 0.0 && o2 > 0.0)) &&
      ((o3 > 0.0 && o4 < 0.0) || (o3 < 0.0 && o4 > 0.0));
  };
  auto overlap = [](const std::array<double, 4>& a, const std::array<double, 4>& b) {
    return a[0] <= b[2] && b[0] <= a[2] && a[1] <= b[3] && b[1] <= a[3];
  };
  std::vector<size_t> order(pieces.size());
  for (size_t i = 0; i < order.size(); ++i)
    order[i] = i;
  std::sort(order.begin(), order.end(),
    [&](size_t a, size_t b) { return pieces[a].Box[0] < pieces[b].Box[0]; });
  for (size_t x = 0; x < order.size(); ++x)
  {
    const Piece& A = pieces[order[x]];
    for (size_t y = x + 1; y < order.size() && pieces[order[y]].Box[0] <= A.Box[2]; ++y)
    {
      const Piece& B = pieces[order[y]];
      if (!overlap(A.Box, B.Box))
        continue;
      // Next to each other on a loop: their shared end's two chords are not compared.
      const bool aThenB = A.Loop == B.Loop && (A.Index + 1) % A.Count == B.Index;
      const bool bThenA = A.Loop == B.Loop && (B.Index + 1) % B.Count == A.Index;
      for (int i = 0; i < 16; ++i)
      {
        const double* a = &A.P[2 * i];
        const std::array<double, 4> ab = { std::min(a[0], a[2]), std::min(a[1], a[3]),
          std::max(a[0], a[2]), std::max(a[1], a[3]) };
        if (!overlap(ab, B.Box))
          continue;
        for (int j = 0; j < 16; ++j)
        {
          if ((aThenB && i == 15 && j == 0) || (bThenA && i == 0 && j == 15))
            continue;
          const double* c = &B.P[2 * j];
          if (cross(a, a + 2, c, c + 2))
            return chordError;
        }
      }
    }
  }
  return -1.0;
}

namespace
{
/// A segment's control box in v widened by the rounding InsideByCrossings allows for, and the
/// box's right end likewise: (v0, v1, u1).
std::array<double, 3> CrossingBox(const double* cp)
{
  double vlo = cp[1], vhi = cp[1], uhi = cp[0], mag = 0.0;
  for (int i = 0; i < 4; ++i)
  {
    vlo = std::min(vlo, cp[2 * i + 1]);
    vhi = std::max(vhi, cp[2 * i + 1]);
    uhi = std::max(uhi, cp[2 * i]);
    mag = std::max({ mag, std::fabs(cp[2 * i]), std::fabs(cp[2 * i + 1]) });
  }
  const double pad = 1e-12 * mag;
  return { vlo - pad, vhi + pad, uhi + pad };
}

/// Whether the ray from (u, v) towards +u crosses the segment's 16 chords an odd number of times.
bool OddCrossings(const double* cp, double u, double v)
{
  // A segment whose control points all lie on one side of the ray's line in v, or all
  // before its start in u, has no chord the ray crosses: its points lie in their box (the
  // box widened by far more than the rounding of the points evaluated below). Most
  // segments of a face are such: the patch boxes' corner tests spent a fifth of the
  // preparation of a part of rational B-spline faces here.
  const std::array<double, 3> box = CrossingBox(cp);
  if (box[1] < v || box[0] > v || box[2] < u)
    return false;
  auto at = [&](int k) { return EvaluateCubic<2>(cp, k / 16.0).P; };
  bool odd = false;
  std::array<double, 2> a = at(0);
  for (int k = 1; k <= 16; ++k)
  {
    const std::array<double, 2> b = at(k);
    // Half-open in v, so that a vertex on the ray counts once.
    if ((a[1] > v) != (b[1] > v))
    {
      const double x = a[0] + (v - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
      if (x > u)
        odd = !odd;
    }
    a = b;
  }
  return odd;
}
} // namespace

bool InsideByCrossings(const BRepModel& model, int face, double u, double v)
{
  const Face& f = model.Faces[face];
  bool inside = false;
  for (int l = f.FirstLoop; l < f.FirstLoop + f.LoopCount; ++l)
  {
    const TrimLoop& loop = model.Loops[l];
    for (int s = loop.FirstSegment; s < loop.FirstSegment + loop.SegmentCount; ++s)
      inside ^= OddCrossings(model.TrimSegments[s].ControlPoints.data(), u, v);
  }
  return inside;
}

struct CrossingIndex::FaceBands
{
  double V0 = 0.0, Step = 1.0;
  int Bands = 0;
  std::vector<int> First;    // band b's segments: [First[b], First[b + 1])
  std::vector<int> Segments; // band by band

  int Band(double v) const
  {
    const double x = std::floor((v - V0) / Step);
    return !(x > 0.0) ? 0 : (x >= Bands - 1 ? Bands - 1 : static_cast<int>(x)); // NaN: band 0
  }
};

CrossingIndex::CrossingIndex(const BRepModel& model)
  : Model(model)
  , Faces(new FaceBands[model.Faces.size()])
  , Built(new std::once_flag[model.Faces.size()])
{
}

CrossingIndex::~CrossingIndex() = default;

const CrossingIndex::FaceBands& CrossingIndex::For(int face) const
{
  const size_t f = static_cast<size_t>(face);
  std::call_once(Built[f], [&]() {
    FaceBands& fc = Faces[f];
    const Face& F = Model.Faces[f];
    std::vector<std::pair<int, std::array<double, 3>>> segments;
    for (int l = F.FirstLoop; l < F.FirstLoop + F.LoopCount; ++l)
    {
      const TrimLoop& loop = Model.Loops[static_cast<size_t>(l)];
      for (int s = loop.FirstSegment; s < loop.FirstSegment + loop.SegmentCount; ++s)
        segments.emplace_back(
          s, CrossingBox(Model.TrimSegments[static_cast<size_t>(s)].ControlPoints.data()));
    }
    if (segments.empty())
      return;
    double lo = segments[0].second[0], hi = segments[0].second[1];
    for (const auto& sb : segments)
    {
      lo = std::min(lo, sb.second[0]);
      hi = std::max(hi, sb.second[1]);
    }
    // About two segments a band; a segment is listed in every band from its box's lower end's
    // to its upper end's. The bands are monotone in v (rounding included), so every segment
    // whose box holds v is listed in v's band, and OddCrossings passes over the others.
    fc.Bands = static_cast<int>(std::clamp<size_t>(segments.size() / 2, 1, 1 << 16));
    fc.V0 = lo;
    fc.Step = hi > lo ? (hi - lo) / fc.Bands : 1.0;
    std::vector<int> count(static_cast<size_t>(fc.Bands) + 1, 0);
    for (const auto& sb : segments)
      for (int b = fc.Band(sb.second[0]); b <= fc.Band(sb.second[1]); ++b)
        ++count[static_cast<size_t>(b) + 1];
    fc.First.assign(count.size(), 0);
    for (size_t b = 1; b < count.size(); ++b)
      fc.First[b] = fc.First[b - 1] + count[b];
    fc.Segments.resize(static_cast<size_t>(fc.First.back()));
    std::vector<int> at(fc.First.begin(), fc.First.end() - 1);
    for (const auto& sb : segments)
      for (int b = fc.Band(sb.second[0]); b <= fc.Band(sb.second[1]); ++b)
        fc.Segments[static_cast<size_t>(at[static_cast<size_t>(b)]++)] = sb.first;
  });
  return Faces[f];
}

bool CrossingIndex::Inside(int face, double u, double v) const
{
  const FaceBands& fc = For(face);
  if (fc.Bands == 0)
    return false;
  const int b = fc.Band(v);
  bool inside = false;
  for (int i = fc.First[static_cast<size_t>(b)]; i < fc.First[static_cast<size_t>(b) + 1]; ++i)
    inside ^= OddCrossings(
      Model.TrimSegments[static_cast<size_t>(fc.Segments[static_cast<size_t>(i)])].ControlPoints.data(), u, v);
  return inside;
}

int FindPatch(const BRepModel& model, int face, double u, double v)
{
  const Face& f = model.Faces[face];
  int iu = 0, iv = 0;
  for (int i = 0; i < f.PatchesU - 1; ++i)
  {
    if (u >= model.Patches[f.FirstPatch + i].Domain[1])
      iu = i + 1;
  }
  for (int j = 0; j < f.PatchesV - 1; ++j)
  {
    if (v >= model.Patches[f.FirstPatch + j * f.PatchesU].Domain[3])
      iv = j + 1;
  }
  return f.FirstPatch + iu + iv * f.PatchesU;
}

} // namespace brt
