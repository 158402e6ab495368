#include "KernelData.h"

#include "Bezier.h"
#include "NativeSolver.h"

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <limits>

namespace brt
{
namespace
{
/// Appends a as hi (3) and lo (3) parts of T.
template <class T>
void PushSplit(std::vector<T>& out, const std::array<double, 3>& a)
{
  for (int k = 0; k < 3; ++k)
    out.push_back(static_cast<T>(a[k]));
  for (int k = 0; k < 3; ++k)
    out.push_back(static_cast<T>(a[k] - static_cast<double>(static_cast<T>(a[k]))));
}

/// A BVH's nodes as boxes (6 per node, relative to c) and (First, Count, Right) triples.
template <class T>
void PushNodes(const std::vector<BVHNode>& nodes, const std::array<double, 3>& c,
  std::vector<T>& box, std::vector<int>& info)
{
  box.reserve(box.size() + 6 * nodes.size());
  info.reserve(info.size() + 3 * nodes.size());
  for (const auto& n : nodes)
  {
    for (int k = 0; k < 3; ++k)
      box.push_back(static_cast<T>(n.Min[k] - c[k]));
    for (int k = 0; k < 3; ++k)
      box.push_back(static_cast<T>(n.Max[k] - c[k]));
    info.insert(info.end(), { n.First, n.Count, n.Right });
  }
}

/// Per face with more than KernelLinearTrims trimming segments, a BVH over its segments' control
/// boxes in (u, v), for the kernel's nearest-segment search (classify): nodes as boxes (u0, v0,
/// u1, v1: the union of their segments' boxes as packed, so in T they still hold them) and
/// (First, Count, Right) triples, left child next to its parent, leaves of up to KernelTrimLeaf
/// segments given as (segment, loop) pairs from First; its root in the face's FACE_INTS record (slot 9;
/// -1: the face's segments are scanned in turn). Median split of the box centres along the
/// longer side.
template <class T>
void PackTrimTrees(const BRepModel& m, KernelModel<T>& k)
{
  for (size_t f = 0; f < m.Faces.size(); ++f)
  {
    const Face& F = m.Faces[f];
    std::vector<std::pair<int, int>> items; // segment, loop
    for (int l = F.FirstLoop; l < F.FirstLoop + F.LoopCount; ++l)
      for (int s = m.Loops[l].FirstSegment;
           s < m.Loops[l].FirstSegment + m.Loops[l].SegmentCount; ++s)
        items.emplace_back(s, l);
    if (static_cast<int>(items.size()) <= KernelLinearTrims)
      continue; // its FaceInfo slot 9 stays -1
    k.FaceInfo[KernelFaceInts * f + 9] = static_cast<int>(k.TrimNodeInfo.size() / 3);
    const int itemBase = static_cast<int>(k.TrimItems.size() / 2);
    const T* box = k.Trim.data() + 8; // segment s's box at box + KernelTrimReals * s
    auto centre = [&](const std::pair<int, int>& it, int axis) {
      const T* b = box + KernelTrimReals * static_cast<size_t>(it.first);
      return static_cast<double>(b[axis]) + static_cast<double>(b[2 + axis]);
    };
    // Depth-first, so that a node's left child is the next node.
    struct Task
    {
      int First, Count, Parent;
    };
    std::vector<Task> tasks{ { 0, static_cast<int>(items.size()), -1 } };
    while (!tasks.empty())
    {
      const Task t = tasks.back();
      tasks.pop_back();
      const int node = static_cast<int>(k.TrimNodeInfo.size() / 3);
      if (t.Parent >= 0)
        k.TrimNodeInfo[3 * static_cast<size_t>(t.Parent) + 2] = node;
      T lo[2], hi[2];
      for (int a = 0; a < 2; ++a)
      {
        lo[a] = box[KernelTrimReals * static_cast<size_t>(items[t.First].first) + a];
        hi[a] = box[KernelTrimReals * static_cast<size_t>(items[t.First].first) + 2 + a];
      }
      for (int i = t.First + 1; i < t.First + t.Count; ++i)
        for (int a = 0; a < 2; ++a)
        {
          lo[a] = std::min(lo[a], box[KernelTrimReals * static_cast<size_t>(items[i].first) + a]);
          hi[a] = std::max(hi[a], box[KernelTrimReals * static_cast<size_t>(items[i].first) + 2 + a]);
        }
      k.TrimNodeBox.insert(k.TrimNodeBox.end(), { lo[0], lo[1], hi[0], hi[1] });
      if (t.Count <= KernelTrimLeaf)
      {
        k.TrimNodeInfo.insert(k.TrimNodeInfo.end(), { itemBase + t.First, t.Count, -1 });
        continue;
      }
      k.TrimNodeInfo.insert(k.TrimNodeInfo.end(), { 0, 0, -1 });
      const int axis = hi[1] - lo[1] > hi[0] - lo[0] ? 1 : 0;
      const int half = t.Count / 2;
      auto first = items.begin() + t.First;
      std::nth_element(first, first + half, first + t.Count,
        [&](const std::pair<int, int>& a, const std::pair<int, int>& b) {
          const double ca = centre(a, axis), cb = centre(b, axis);
          return ca < cb || (ca == cb && a.first < b.first);
        });
      tasks.push_back({ t.First + half, t.Count - half, node }); // right, after the left subtree
      tasks.push_back({ t.First, half, -1 });                   // left: the next node
    }
    for (const auto& it : items)
      k.TrimItems.insert(k.TrimItems.end(), { it.first, it.second });
  }
}

/// Boxes stored as (min x, y, z, max x, y, z) in absolute coordinates, relative to c.
template <class T>
std::vector<T> RelativeBoxes(const std::vector<double>& boxes, const std::array<double, 3>& c)
{
  std::vector<T> out(boxes.size());
  for (size_t i = 0; i < boxes.size(); ++i)
    out[i] = static_cast<T>(boxes[i] - c[i % 3]);
  return out;
}

/// x rounded to T towards -infinity (down) or +infinity (up).
template <class T>
T Rounded(double x, bool up)
{
  T y = static_cast<T>(x);
  if (up ? static_cast<double>(y) < x : static_cast<double>(y) > x)
    y = std::nextafter(y, up ? std::numeric_limits<T>::infinity() : -std::numeric_limits<T>::infinity());
  return y;
}

/// A patch's control-net constants (KernelPatchHullReals) from its 16 control points c as packed
/// (relative to its anchor): the mean and the normal by the operations patch_gap did on them in
/// the kernel source, in T and in its order (so that its bound kept its value where neither build
/// contracts them into FMAs). The bound holds for any mean and unit normal: the offsets are taken
/// along the normal as stored.
template <class T>
void PackPatchHull(const T* c, T* out)
{
  T mean[3] = { T(0), T(0), T(0) };
  for (int i = 0; i < 16; ++i)
    for (int k = 0; k < 3; ++k)
      mean[k] = mean[k] + c[3 * i + k];
  for (int k = 0; k < 3; ++k)
    out[k] = mean[k] / T(16);
  // cross(c33 - c00, c03 - c30), then divided by its length (zeros where that is 0).
  T x[3], y[3];
  for (int k = 0; k < 3; ++k)
  {
    x[k] = c[45 + k] - c[k];
    y[k] = c[9 + k] - c[36 + k];
  }
  const T n[3] = { x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2],
    x[0] * y[1] - x[1] * y[0] };
  const T ln = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int k = 0; k < 3; ++k)
    out[3 + k] = ln > T(0) ? n[k] / ln : T(0);
  // The control points' offsets along that normal (as stored in T), in double: the least and the
  // greatest rounded outwards, so that the hull lies between them in T too; the corners' mean's.
  double lo = std::numeric_limits<double>::infinity(), hi = -lo, corners = 0.0;
  for (int i = 0; i < 16; ++i)
  {
    double o = 0.0;
    for (int k = 0; k < 3; ++k)
      o += static_cast<double>(c[3 * i + k]) * static_cast<double>(out[3 + k]);
    lo = std::min(lo, o);
    hi = std::max(hi, o);
    if (i == 0 || i == 3 || i == 12 || i == 15)
      corners += 0.25 * o;
  }
  out[6] = Rounded<T>(lo, false);
  out[7] = Rounded<T>(hi, true);
  out[8] = static_cast<T>(corners);
  // The diagonal of the box of the patch's 5 x 5 grid (certify_patch's extent), in double.
  double B[5][4];
  for (int k = 0; k <= 4; ++k)
  {
    const double at = 0.25 * k, rest = 1.0 - at;
    B[k][0] = rest * rest * rest;
    B[k][1] = 3.0 * rest * rest * at;
    B[k][2] = 3.0 * rest * at * at;
    B[k][3] = at * at * at;
  }
  const double inf = std::numeric_limits<double>::infinity();
  double box[6] = { inf, inf, inf, -inf, -inf, -inf };
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; j <= 4; ++j)
      for (int k = 0; k < 3; ++k)
      {
        double q = 0.0;
        for (int a = 0; a < 4; ++a)
          for (int b = 0; b < 4; ++b)
            q += B[i][a] * B[j][b] * static_cast<double>(c[3 * (4 * a + b) + k]);
        box[k] = std::min(box[k], q);
        box[3 + k] = std::max(box[3 + k], q);
      }
  double e2 = 0.0;
  for (int k = 0; k < 3; ++k)
    e2 += (box[3 + k] - box[k]) * (box[3 + k] - box[k]);
  out[9] = static_cast<T>(std::sqrt(e2));
}

/// The sector of a cylinder (origin o and unit axis a, absolute) that holds the control points
/// cp of one of its face's patches, as KernelPatchSectorReals: the point of the axis at the
/// middle of their heights, relative to the patch's anchor (the first control point) and stored
/// as T, so that the kernels form M's position from it with float's rounding of the patch's size
/// rather than of the model's; their heights from that stored point, rounded outwards; the
/// middle direction around the axis, as T; the cosine (rounded down) and sine (rounded up) of
/// the half-angle that holds every control point around that stored direction; 1 where the
/// sector is narrower than a half-turn.
template <class T>
void PackCylinderSector(const double* cp, const double* o, const double* a, T* out)
{
  std::fill(out, out + KernelPatchSectorReals, T(0));
  double z0 = std::numeric_limits<double>::infinity(), z1 = -z0;
  for (int i = 0; i < 16; ++i)
  {
    const double z = (cp[3 * i] - o[0]) * a[0] + (cp[3 * i + 1] - o[1]) * a[1] +
      (cp[3 * i + 2] - o[2]) * a[2];
    z0 = std::min(z0, z);
    z1 = std::max(z1, z);
  }
  // The patch's own point of the axis, as the kernels will read it. Through a volatile: GCC 12
  // at -O3 vectorised cp + double(T(x)) into cp + x here, dropping the rounding to T that the
  // kernels see (caught by KernelData.CylinderSectorsHoldTheirControlPoints).
  double po[3];
  for (int j = 0; j < 3; ++j)
  {
    const volatile T stored = static_cast<T>(o[j] + 0.5 * (z0 + z1) * a[j] - cp[j]);
    out[8 + j] = stored;
    po[j] = cp[j] + static_cast<double>(stored);
  }
  z0 = std::numeric_limits<double>::infinity();
  z1 = -z0;
  double r[16][3], mean[3] = { 0.0, 0.0, 0.0 };
  for (int i = 0; i < 16; ++i)
  {
    double q[3];
    for (int j = 0; j < 3; ++j)
      q[j] = cp[3 * i + j] - po[j];
    const double z = q[0] * a[0] + q[1] * a[1] + q[2] * a[2];
    z0 = std::min(z0, z);
    z1 = std::max(z1, z);
    for (int j = 0; j < 3; ++j)
    {
      r[i][j] = q[j] - z * a[j];
      mean[j] += r[i][j];
    }
  }
  out[0] = Rounded<T>(z0, false);
  out[1] = Rounded<T>(z1, true);
  const double lm = std::sqrt(mean[0] * mean[0] + mean[1] * mean[1] + mean[2] * mean[2]);
  if (!(lm > 0.0))
    return;
  // The angles around the direction as the kernel will read it (rounded to T).
  double mid[3];
  for (int j = 0; j < 3; ++j)
  {
    const volatile T stored = static_cast<T>(mean[j] / lm); // as above
    out[2 + j] = stored;
    mid[j] = static_cast<double>(stored);
  }
  const double lmid = std::sqrt(mid[0] * mid[0] + mid[1] * mid[1] + mid[2] * mid[2]);
  double cosA = 1.0;
  for (const auto& ri : r)
  {
    const double lr = std::sqrt(ri[0] * ri[0] + ri[1] * ri[1] + ri[2] * ri[2]);
    if (!(lr > 0.0))
      return;
    cosA = std::min(cosA, (ri[0] * mid[0] + ri[1] * mid[1] + ri[2] * mid[2]) / (lr * lmid));
  }
  const T c = Rounded<T>(cosA, false);
  if (!(c > T(0)))
    return;
  const double cd = static_cast<double>(c);
  out[5] = c;
  out[6] = Rounded<T>(std::sqrt(std::max(0.0, 1.0 - cd * cd)), true);
  out[7] = T(1);
}

/// Calls visit(i, j, q) with the point q of the bicubic patch (control points cp, (4 i + j) * 3)
/// at (i / (G - 1), j / (G - 1)) of its local parameters, for every step-th i and j, by the tensor
/// product: the control net's rows first.
template <class F>
void ForEachGridPoint(const double* cp, int G, int step, F&& visit)
{
  auto basis = [](double x, double* b) {
    b[0] = (1 - x) * (1 - x) * (1 - x);
    b[1] = 3 * x * (1 - x) * (1 - x);
    b[2] = 3 * x * x * (1 - x);
    b[3] = x * x * x;
  };
  for (int i = 0; i < G; i += step)
  {
    double bs[4], row[4][3];
    basis(i / (G - 1.0), bs);
    for (int b = 0; b < 4; ++b)
      for (int k = 0; k < 3; ++k)
        row[b][k] = bs[0] * cp[3 * b + k] + bs[1] * cp[3 * (4 + b) + k] +
          bs[2] * cp[3 * (8 + b) + k] + bs[3] * cp[3 * (12 + b) + k];
    for (int j = 0; j < G; j += step)
    {
      double br[4], q[3];
      basis(j / (G - 1.0), br);
      for (int k = 0; k < 3; ++k)
        q[k] = br[0] * row[0][k] + br[1] * row[1][k] + br[2] * row[2][k] + br[3] * row[3][k];
      visit(i, j, q);
    }
  }
}

/// The tube that holds a patch of a face with no exact surface (tube_patch_gap, docs/Solver.md
/// item 22): a free-form round (a rolling ball's blend, a pipe) is swept by circular arcs of one
/// radius about a spine, and over one patch the spine is nearly a point (a ball's corner), a line
/// or a circle. Each way across the patch, the circles through the patch's points at the start,
/// middle and end of three of its parameter lines (at 0, 1/2 and 1 of the other parameter) give
/// three centres on the spine (where the three arcs' radii agree within 2%, as a round's do;
/// elsewhere no tube, at the cost of 9 points); the spine is the point where they meet, the line
/// where the middle one lies on the line through the others (within a hundredth of the slack),
/// else the circle through all three; of the two ways, the one the patch follows more closely on
/// a 5 x 5 grid. Then the patch's distances from that spine at a 9 x 9 grid: r their middle,
/// the allowance 1.5 times their half-spread (as the faces' deviation takes its measure) and the
/// rounding. (Centres of curvature instead moved with the patches' second derivatives, several
/// per cent off a converted rational round's, and the spines through them missed the ball's
/// centre by 0.006 on a round of radius 0.8.) As KernelPatchSectorReals: the spine's centre (the
/// point; a point of the line; the circle's centre) relative to the patch's anchor, stored as T;
/// its unit axis (the line's direction, the circle's normal); the circle's radius; r; the
/// allowance; the kind (1 point, 2 line, 3 circle; 0 none: no allowance below the slack, where
/// the bound would not help). The kernel reads these where the face has no exact surface.
template <class T>
void PackPatchTube(const double* cp, double slack, T* out)
{
  std::fill(out, out + KernelPatchSectorReals, T(0));
  // The patch's points on a 9 x 9 grid (i along u, j along v), by the tensor product: the
  // control net's rows first. Only the 3 x 3 at 0, 1/2 and 1 until the screen below passes.
  constexpr int G = 9;
  double pts[G * G][3];
  auto fill = [&](int step) {
    ForEachGridPoint(cp, G, step, [&](int i, int j, const double* q) {
      for (int k = 0; k < 3; ++k)
        pts[G * i + j][k] = q[k];
    });
  };
  fill(4);
  auto sub = [](const double* a, const double* b, double* o) {
    for (int c = 0; c < 3; ++c)
      o[c] = a[c] - b[c];
  };
  auto cross = [](const double* a, const double* b, double* o) {
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
  };
  auto dot = [](const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  // The circle through a, b, c: its centre and unit normal; false where they are (nearly) on a
  // line.
  auto circle = [&](const double* a, const double* b, const double* c, double* centre,
                  double* normal) {
    double ab[3], ac[3], n[3], nab[3], acn[3];
    sub(b, a, ab);
    sub(c, a, ac);
    cross(ab, ac, n);
    const double l2 = dot(n, n), a2 = dot(ab, ab), c2 = dot(ac, ac);
    if (!(l2 > 1e-16 * a2 * c2))
      return false;
    cross(n, ab, nab);
    cross(ac, n, acn);
    for (int k = 0; k < 3; ++k)
    {
      centre[k] = a[k] + (c2 * nab[k] + a2 * acn[k]) / (2.0 * l2);
      normal[k] = n[k] / std::sqrt(l2);
    }
    return true;
  };
  struct Spine
  {
    int kind;
    double c[3], a[3], R;
  };
  Spine cand[2];
  int nc = 0;
  for (int dir = 0; dir < 2; ++dir)
  {
    // Three parameter lines across (u varying at v = 0, 1/2, 1; then the other way).
    double C[3][3], nrm[3], radius[3];
    bool ok = true;
    for (int k = 0; k < 3 && ok; ++k)
    {
      const int fixed = 4 * k;
      auto at = [&](int run) { return dir == 0 ? pts[G * run + fixed] : pts[G * fixed + run]; };
      ok = circle(at(0), at(4), at(8), C[k], nrm);
      if (ok)
      {
        double w[3];
        sub(at(0), C[k], w);
        radius[k] = std::sqrt(dot(w, w));
      }
    }
    // The screen: a round's arcs across have one radius (within 2% here); elsewhere no tube is
    // fitted (most free-form patches, at the cost of 9 points).
    if (!ok ||
      std::max({ radius[0], radius[1], radius[2] }) >
        1.02 * std::min({ radius[0], radius[1], radius[2] }))
      continue;
    // One spine per way: the point where the three centres meet (within a hundredth of the
    // slack), the line where the middle one lies that near the line through the others, else the
    // circle through all three.
    double ab[3], am[3], x[3];
    sub(C[2], C[0], ab);
    sub(C[1], C[0], am);
    const double lab = std::sqrt(dot(ab, ab)), near = 1e-2 * slack;
    cross(am, ab, x);
    Spine sp{ 1, { 0, 0, 0 }, { 0, 0, 0 }, 0.0 };
    if (lab < near && std::sqrt(dot(am, am)) < near)
    {
      for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 3; ++c)
          sp.c[c] += C[k][c] / 3.0;
    }
    else if (lab > 0.0 && std::sqrt(dot(x, x)) / lab < near)
      sp = Spine{ 2, { C[0][0], C[0][1], C[0][2] }, { ab[0] / lab, ab[1] / lab, ab[2] / lab }, 0.0 };
    else
    {
      sp.kind = 3;
      if (!circle(C[0], C[1], C[2], sp.c, sp.a))
        continue;
      double w[3];
      sub(C[0], sp.c, w);
      sp.R = std::sqrt(dot(w, w));
    }
    cand[nc++] = sp;
  }
  if (nc == 0)
    return;
  fill(1);
  // Each candidate as the kernel reads it (rounded to T): measured on the 5 x 5 grid (every
  // other point), the better then on the whole 9 x 9.
  auto measure = [&](const Spine& sp, int step, T* stored, double& allow) {
    double c[3], a[3];
    for (int j = 0; j < 3; ++j)
    {
      const volatile T sc = static_cast<T>(sp.c[j] - cp[j]); // as in PackCylinderSector
      stored[j] = sc;
      c[j] = cp[j] + static_cast<double>(sc);
      const volatile T sa = static_cast<T>(sp.a[j]);
      stored[3 + j] = sa;
      a[j] = static_cast<double>(sa);
    }
    const volatile T sR = static_cast<T>(sp.R);
    stored[6] = sR;
    const double R = static_cast<double>(sR);
    double dmin = std::numeric_limits<double>::infinity(), dmax = -dmin, size = 0.0;
    for (int i = 0; i < G; i += step)
      for (int j = 0; j < G; j += step)
      {
        double x[3];
        sub(pts[G * i + j], c, x);
        const double z = dot(x, a), xx = dot(x, x);
        const double rho = std::sqrt(std::max(0.0, xx - z * z));
        const double dist = sp.kind == 1 ? std::sqrt(xx)
          : sp.kind == 2               ? rho
                                       : std::sqrt((rho - R) * (rho - R) + z * z);
        dmin = std::min(dmin, dist);
        dmax = std::max(dmax, dist);
        size = std::max(size, std::sqrt(xx));
      }
    const T r = static_cast<T>(0.5 * (dmin + dmax));
    stored[7] = r;
    const double spread = std::max(static_cast<double>(r) - dmin, dmax - static_cast<double>(r));
    allow = 1.5 * spread +
      64.0 * std::numeric_limits<T>::epsilon() * (size + R + static_cast<double>(r));
  };
  int best = -1;
  double bestAllow = std::numeric_limits<double>::infinity();
  T stored[8];
  for (int k = 0; k < nc; ++k)
  {
    double allow;
    measure(cand[k], 2, stored, allow);
    if (allow < bestAllow)
    {
      bestAllow = allow;
      best = k;
    }
  }
  if (best < 0 || !(bestAllow < slack))
    return;
  double allow;
  measure(cand[best], 1, stored, allow);
  if (!(allow < slack))
    return;
  std::copy(stored, stored + 8, out);
  out[8] = Rounded<T>(allow, true);
  out[9] = static_cast<T>(cand[best].kind);
}

/// The angle that the control points cp (which hold the patch) span around the line through the
/// absolute point o along the unit axis a, in radians (from the first one's direction; pi or more
/// where they go round it, 0 where the first lies on the line).
double AngleAroundAxis(const double* cp, const double* o, const double* a)
{
  double ref[3] = { 0, 0, 0 }, side[3];
  double lo = 0.0, hi = 0.0;
  for (int i = 0; i < 16; ++i)
  {
    double x[3] = { cp[3 * i] - o[0], cp[3 * i + 1] - o[1], cp[3 * i + 2] - o[2] };
    const double z = x[0] * a[0] + x[1] * a[1] + x[2] * a[2];
    for (int k = 0; k < 3; ++k)
      x[k] -= z * a[k];
    if (i == 0)
    {
      const double l = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
      if (!(l > 0.0))
        return 0.0;
      for (int k = 0; k < 3; ++k)
        ref[k] = x[k] / l;
      side[0] = a[1] * ref[2] - a[2] * ref[1];
      side[1] = a[2] * ref[0] - a[0] * ref[2];
      side[2] = a[0] * ref[1] - a[1] * ref[0];
      continue;
    }
    const double ang = std::atan2(x[0] * side[0] + x[1] * side[1] + x[2] * side[2],
      x[0] * ref[0] + x[1] * ref[1] + x[2] * ref[2]);
    lo = std::min(lo, ang);
    hi = std::max(hi, ang);
  }
  return hi - lo;
}

/// The piece of space around a line that holds a patch (tube_patch_gap's kind 4), for the
/// certification's bound where the patch turns round the line: a cone's patch, a thread's flank
/// or a helical face beside a shaft, whose control net's hull comes nearer to the axis than the
/// patch by the sag of its chords. cp: the control points of the patch's part inside its face's
/// trim (SolverData::PatchTrimBox; the certification counts no point outside it); anchor: the
/// whole patch's (the kernels' patch anchor); the line through the absolute point o along the
/// unit axis a. The heights along the line come from the control points (which hold the part),
/// the greatest distance from the line too (that distance is convex: its greatest over their
/// hull lies at one of them), the least from a 17 x 17 grid of the part's points, less three
/// times what the 9 x 9 grid within it missed of it (the grid's shortfall, extrapolated) and the
/// rounding. As KernelPatchSectorReals: the line's point nearest the anchor, relative to it,
/// stored as T; the axis as T; 0; the middle of the distances; their half-spread; kind 4; the
/// heights from the stored point, rounded outwards.
template <class T>
void PackPatchAxisBox(const double* anchor, const double* cp, const double* o, const double* axis,
  T* out)
{
  // The bound holds for a unit axis: the file's, made one to rounding.
  const double la = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  const double a[3] = { axis[0] / la, axis[1] / la, axis[2] / la };
  double c[3], sa[3];
  const double s0 =
    (anchor[0] - o[0]) * a[0] + (anchor[1] - o[1]) * a[1] + (anchor[2] - o[2]) * a[2];
  T stored[KernelPatchSectorReals] = {};
  for (int j = 0; j < 3; ++j)
  {
    const volatile T sc = static_cast<T>(o[j] + s0 * a[j] - anchor[j]); // as in PackCylinderSector
    stored[j] = sc;
    c[j] = anchor[j] + static_cast<double>(sc);
    const volatile T ax = static_cast<T>(a[j]);
    stored[3 + j] = ax;
    sa[j] = static_cast<double>(ax);
  }
  // As the kernel reads them: M's height is its offset along the stored axis, its distance
  // from the line the rest.
  auto cyl = [&](const double* q, double& z, double& rho, double& size) {
    const double x[3] = { q[0] - c[0], q[1] - c[1], q[2] - c[2] };
    z = x[0] * sa[0] + x[1] * sa[1] + x[2] * sa[2];
    const double xx = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
    rho = std::sqrt(std::max(0.0, xx - z * z));
    size = std::sqrt(xx);
  };
  double z0 = std::numeric_limits<double>::infinity(), z1 = -z0, rhoMax = -z0, size = 0.0;
  for (int i = 0; i < 16; ++i)
  {
    double z, rho, sz;
    cyl(cp + 3 * i, z, rho, sz);
    z0 = std::min(z0, z);
    z1 = std::max(z1, z);
    rhoMax = std::max(rhoMax, rho);
    size = std::max(size, sz);
  }
  constexpr int G = 17;
  double minFine = std::numeric_limits<double>::infinity(), minCoarse = minFine;
  ForEachGridPoint(cp, G, 1, [&](int i, int j, const double* q) {
    double z, rho, sz;
    cyl(q, z, rho, sz);
    minFine = std::min(minFine, rho);
    if (i % 2 == 0 && j % 2 == 0)
      minCoarse = std::min(minCoarse, rho);
  });
  const double eps = (64.0 * std::numeric_limits<T>::epsilon() + 1e-12) * (size + rhoMax);
  const double lo = std::max(0.0, minFine - 3.0 * (minCoarse - minFine) - eps);
  const double hi = rhoMax + eps;
  const T r = static_cast<T>(0.5 * (lo + hi));
  stored[7] = r;
  stored[8] = Rounded<T>(std::max(static_cast<double>(r) - lo, hi - static_cast<double>(r)), true);
  stored[9] = T(4);
  stored[10] = Rounded<T>(z0 - eps, false);
  stored[11] = Rounded<T>(z1 + eps, true);
  std::copy(stored, stored + KernelPatchSectorReals, out);
}

/// A torus patch's arc of the tube (torus_patch_gap), as KernelPatchSectorReals: the unit
/// vectors of its ends in the meridian half-plane (cos, sin of v0 and of v1: radial, axial), its
/// middle direction as T, the cosine of the half-span around that stored direction (rounded
/// down), and 1; 0 in the flag where the arc spans half the tube or more.
template <class T>
void PackTorusArc(double v0, double v1, T* out)
{
  std::fill(out, out + KernelPatchSectorReals, T(0));
  const double span = v1 - v0;
  if (!(span > 0.0 && span < 3.14159))
    return;
  const double ends[2] = { v0, v1 };
  for (int k = 0; k < 2; ++k)
  {
    out[2 * k] = static_cast<T>(std::cos(ends[k]));
    out[2 * k + 1] = static_cast<T>(std::sin(ends[k]));
  }
  const double mid = 0.5 * (v0 + v1);
  const volatile T mc = static_cast<T>(std::cos(mid)), ms = static_cast<T>(std::sin(mid)); // as in PackCylinderSector
  out[4] = mc;
  out[5] = ms;
  const double c = static_cast<double>(mc), sn = static_cast<double>(ms), l = std::hypot(c, sn);
  // Every angle of the arc is within the farther end's angle of the stored middle.
  const double cosHalf = std::min(std::cos(v0) * c + std::sin(v0) * sn,
    std::cos(v1) * c + std::sin(v1) * sn) / l;
  out[6] = Rounded<T>(cosHalf, false);
  out[7] = T(1);
}

/// The cone of directions from a point o that holds the control points cp of a sphere's patch
/// (a null axis a), or the wedge of directions around the axis (o, a) that holds those of a
/// torus's, as the last four of KernelPatchSectorReals: the middle direction (the mean of the
/// points' directions, across the axis on a torus) stored as T, and the cosine of the half-angle
/// about that stored direction that holds every point, widened by `widen` (radians) and rounded
/// down; zeros where that half-angle is a quarter-turn or more (the cone or wedge would not be
/// convex, and the patch's hull would not lie in it) or a point lies on o or the axis.
template <class T>
void PackDirectionCone(const double* cp, const double* o, const double* a, double widen, T* out)
{
  std::fill(out, out + 4, T(0));
  double r[16][3], mean[3] = { 0.0, 0.0, 0.0 };
  for (int i = 0; i < 16; ++i)
  {
    double q[3] = { cp[3 * i] - o[0], cp[3 * i + 1] - o[1], cp[3 * i + 2] - o[2] };
    if (a)
    {
      const double z = q[0] * a[0] + q[1] * a[1] + q[2] * a[2];
      for (int j = 0; j < 3; ++j)
        q[j] -= z * a[j];
    }
    const double l = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    if (!(l > 0.0))
      return;
    for (int j = 0; j < 3; ++j)
    {
      r[i][j] = q[j] / l;
      mean[j] += r[i][j];
    }
  }
  const double lm = std::sqrt(mean[0] * mean[0] + mean[1] * mean[1] + mean[2] * mean[2]);
  if (!(lm > 0.0))
    return;
  double mid[3];
  for (int j = 0; j < 3; ++j)
  {
    const volatile T stored = static_cast<T>(mean[j] / lm); // as in PackCylinderSector
    mid[j] = static_cast<double>(stored);
  }
  const double lmid = std::sqrt(mid[0] * mid[0] + mid[1] * mid[1] + mid[2] * mid[2]);
  double cosA = 1.0;
  for (const auto& ri : r)
    cosA = std::min(cosA, (ri[0] * mid[0] + ri[1] * mid[1] + ri[2] * mid[2]) / lmid);
  // With the rounding of the sums above, well beyond it.
  const double half = std::acos(std::clamp(cosA, -1.0, 1.0)) + widen + 1e-12;
  if (!(half < 0.5 * M_PI - 1e-6))
    return;
  const T c = Rounded<T>(std::cos(half), false);
  if (!(c > T(0)))
    return;
  for (int j = 0; j < 3; ++j)
    out[j] = static_cast<T>(mid[j]);
  out[3] = c;
}

/// The angles around the tube (as a native torus's v: from the torus's plane towards its axis)
/// that hold a patch lying near a torus of centre o, unit axis a and radius R (absolute), for a
/// torus read from a B-spline, whose patch parameters are not its angles. The patch lies in the
/// hull of its control points c_i. A point P = sum l_i c_i of it has the height sum l_i z_i and
/// the distance from the axis |sum l_i r_i| (r_i: c_i's part across the axis), which is at most
/// sum l_i |r_i| and, the r_i lying within an angle A of their mean direction, at least that
/// less e = max |r_i| (1 - cos A). So P's meridian position (distance from the axis less R,
/// height) lies in the hull of the c_i's and of the same moved by -e along the first, and the
/// angles of a hull that leaves out the tube's centre are those of its points. False where the
/// points' angles span half a turn or more, or a point lies on that centre.
bool TorusArcOfPatch(const double* cp, const double* o, const double* a, double R, double& v0,
  double& v1)
{
  double q[16], z[16], r[16][3], n[3] = { 0.0, 0.0, 0.0 }, maxRho = 0.0;
  for (int i = 0; i < 16; ++i)
  {
    const double w[3] = { cp[3 * i] - o[0], cp[3 * i + 1] - o[1], cp[3 * i + 2] - o[2] };
    z[i] = w[0] * a[0] + w[1] * a[1] + w[2] * a[2];
    for (int j = 0; j < 3; ++j)
    {
      r[i][j] = w[j] - z[i] * a[j];
      n[j] += r[i][j];
    }
    const double rho = std::sqrt(r[i][0] * r[i][0] + r[i][1] * r[i][1] + r[i][2] * r[i][2]);
    q[i] = rho - R;
    maxRho = std::max(maxRho, rho);
  }
  const double ln = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (!(ln > 0.0))
    return false;
  double cosA = 1.0;
  for (int i = 0; i < 16; ++i)
  {
    const double rho = q[i] + R;
    if (!(rho > 0.0))
      return false;
    cosA = std::min(cosA, (r[i][0] * n[0] + r[i][1] * n[1] + r[i][2] * n[2]) / (rho * ln));
  }
  if (!(cosA > 0.0))
    return false;
  // With the rounding of the sums above, well beyond it.
  const double e = maxRho * ((1.0 - cosA) + 1e-12);
  double mq = 0.0, mz = 0.0;
  for (int i = 0; i < 16; ++i)
  {
    mq += q[i] - 0.5 * e;
    mz += z[i];
  }
  const double lm = std::hypot(mq, mz);
  if (!(lm > 0.0))
    return false;
  const double cr = mq / lm, sr = mz / lm, minLength = 1e-9 * (R + maxRho);
  // The points in the frame of their mean direction; the two whose angles are extreme, found by
  // a pseudo-angle that grows with the angle over the whole turn, then their angles.
  auto pseudo = [](double x, double y) {
    const double s = y / (std::fabs(x) + std::fabs(y));
    return x >= 0.0 ? s : (y >= 0.0 ? 2.0 - s : -2.0 - s);
  };
  double loP = std::numeric_limits<double>::infinity(), hiP = -loP, lo[2] = {}, hi[2] = {};
  for (int k = 0; k < 32; ++k)
  {
    const double x = q[k % 16] - (k < 16 ? 0.0 : e), y = z[k % 16];
    if (!(x * x + y * y > minLength * minLength))
      return false;
    const double xr = x * cr + y * sr, yr = y * cr - x * sr, pa = pseudo(xr, yr);
    if (pa < loP)
    {
      loP = pa;
      lo[0] = xr;
      lo[1] = yr;
    }
    if (pa > hiP)
    {
      hiP = pa;
      hi[0] = xr;
      hi[1] = yr;
    }
  }
  const double first = std::atan2(lo[1], lo[0]), last = std::atan2(hi[1], hi[0]);
  const double ref = std::atan2(sr, cr);
  if (!(last - first < 3.14))
    return false;
  v0 = ref + first - 1e-9;
  v1 = ref + last + 1e-9;
  return true;
}

} // namespace

int PackExactSurface(const BRepModel& m, int f, const std::array<double, 3>& c,
  std::array<double, 12>& out)
{
  const Face& F = m.Faces[f];
  if (m.FaceExact.size() != m.Faces.size() || F.PatchCount <= 0)
    return 0;
  const auto& e = m.FaceExact[f];
  double a[3] = { e[3], e[4], e[5] };
  const double la = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  if (!(std::fabs(la - 1.0) < 1e-6))
    return 0; // not a unit axis: not a description this solver trusts
  for (double& x : a)
    x /= la;
  const auto& p = m.Patches[F.FirstPatch].ControlPoints;
  double o[3] = { e[0], e[1], e[2] };
  const double s = (p[0] - o[0]) * a[0] + (p[1] - o[1]) * a[1] + (p[2] - o[2]) * a[2];
  double sizes[3] = { 0.0, 0.0, 0.0 };
  int kind = 0;
  switch (F.Kind)
  {
    case SurfaceKind::Plane:
      kind = 1;
      for (int i = 0; i < 3; ++i)
        o[i] = p[i] - s * a[i];
      break;
    case SurfaceKind::Cylinder:
      kind = 2;
      for (int i = 0; i < 3; ++i)
        o[i] += s * a[i];
      sizes[0] = e[6];
      break;
    case SurfaceKind::Cone:
    {
      kind = 3;
      for (int i = 0; i < 3; ++i)
        o[i] += s * a[i];
      sizes[0] = e[6] + s * std::tan(e[7]); // the radius at the first control point's height
      sizes[1] = std::cos(e[7]);
      sizes[2] = std::sin(e[7]);
      // OpenCASCADE's cone goes on past its apex (v below -RefRadius / sin(angle)) as the other
      // nappe, where the radius R + v sin(angle) is negative: a face may lie there (screw.step's
      // countersink). Its control point farthest from the apex (the patches' largest |radius|)
      // tells the nappe; on the other one the description is turned (R and the angle negated:
      // the same double cone, its generator now the face's), so that the kernels' distance to
      // the generator is the face's own surface (exact_distance).
      double radius = 0.0;
      const double slope = std::tan(e[7]);
      for (int pi = F.FirstPatch; pi < F.FirstPatch + F.PatchCount; ++pi)
        for (int i = 0; i < 16; ++i)
        {
          const double* q = &m.Patches[static_cast<size_t>(pi)].ControlPoints[3 * i];
          const double z = (q[0] - o[0]) * a[0] + (q[1] - o[1]) * a[1] + (q[2] - o[2]) * a[2];
          const double r = sizes[0] + z * slope;
          if (std::fabs(r) > std::fabs(radius))
            radius = r;
        }
      if (radius < 0.0)
      {
        sizes[0] = -sizes[0];
        sizes[2] = -sizes[2];
      }
      break;
    }
    case SurfaceKind::Sphere:
      kind = 4;
      sizes[0] = e[6];
      break;
    case SurfaceKind::Torus:
    {
      kind = 5;
      sizes[0] = e[6];
      sizes[1] = e[7];
      // A spindle torus (major radius below the minor: a lemon-shaped dome, screw.step's head)
      // passes through its axis: in a meridian half-plane its points with R + r cos(v) < 0 lie
      // on the tube circle mirrored across the axis, around rho = -R. A face there (the lemon)
      // gets the description turned (R negated: the same surface), so that the kernels' distance
      // to the tube circle is to the face's own (exact_distance); its patches' corners, which
      // lie on the surface, tell the circle.
      if (e[6] < e[7])
      {
        int mirrored = 0, corners = 0;
        for (int pi = F.FirstPatch; pi < F.FirstPatch + F.PatchCount; ++pi)
          for (int i : { 0, 3, 12, 15 })
          {
            const double* q = &m.Patches[static_cast<size_t>(pi)].ControlPoints[3 * i];
            const double w[3] = { q[0] - o[0], q[1] - o[1], q[2] - o[2] };
            const double z = w[0] * a[0] + w[1] * a[1] + w[2] * a[2];
            const double rho = std::sqrt(std::max(0.0,
              w[0] * w[0] + w[1] * w[1] + w[2] * w[2] - z * z));
            const double own = std::fabs(std::hypot(rho - e[6], z) - e[7]);
            const double other = std::fabs(std::hypot(rho + e[6], z) - e[7]);
            mirrored += other < own ? 1 : 0;
            ++corners;
          }
        if (2 * mirrored > corners)
          sizes[0] = -e[6];
      }
      break;
    }
    default:
      return 0;
  }
  out = { o[0] - c[0], o[1] - c[1], o[2] - c[2], 0.0, 0.0, 0.0, a[0], a[1], a[2], sizes[0],
    sizes[1], sizes[2] };
  return kind;
}

namespace
{
/// A plane face whose patches are the plane's own parametrisation, an isometry: every control point
/// at Q0 + u X + v Y with X, Y orthonormal and in the plane (OpenCASCADE's planes; a B-spline read
/// as a plane only where its parameters happen to be such a map). Then a point's (u, v) distance from the trim is its distance in the plane
/// (the certification's plane_trim_gap). Returns 0 where not, else the sign s of Y = s (a x X),
/// a the plane's unit normal; X out.
int PlaneFrame(const BRepModel& m, int f, const double* a, double* X)
{
  const Face& F = m.Faces[static_cast<size_t>(f)];
  if (F.PatchCount <= 0)
    return 0;
  const BezierPatch& P0 = m.Patches[static_cast<size_t>(F.FirstPatch)];
  const double du = P0.Domain[1] - P0.Domain[0], dv = P0.Domain[3] - P0.Domain[2];
  if (!(du > 0.0) || !(dv > 0.0))
    return 0;
  const double* c = P0.ControlPoints.data();
  double Y[3];
  for (int k = 0; k < 3; ++k)
  {
    X[k] = (c[36 + k] - c[k]) / du; // P30: u at its end
    Y[k] = (c[9 + k] - c[k]) / dv;  // P03: v at its end
  }
  const auto dot = [](const double* p, const double* q) { return p[0] * q[0] + p[1] * q[1] + p[2] * q[2]; };
  const double eps = 1e-12;
  if (std::fabs(dot(X, X) - 1.0) > eps || std::fabs(dot(Y, Y) - 1.0) > eps ||
    std::fabs(dot(X, Y)) > eps || std::fabs(dot(X, a)) > eps || std::fabs(dot(Y, a)) > eps)
    return 0;
  const double axX[3] = { a[1] * X[2] - a[2] * X[1], a[2] * X[0] - a[0] * X[2],
    a[0] * X[1] - a[1] * X[0] };
  const int sign = dot(axX, Y) > 0.0 ? 1 : -1;
  // Every control point where the map puts it, to rounding of the face's size.
  double size = std::fabs(F.Domain[1] - F.Domain[0]) + std::fabs(F.Domain[3] - F.Domain[2]);
  for (int k = 0; k < 3; ++k)
    size += std::fabs(c[k]);
  const double tol = 1e-12 * size;
  for (int p = F.FirstPatch; p < F.FirstPatch + F.PatchCount; ++p)
  {
    const BezierPatch& B = m.Patches[static_cast<size_t>(p)];
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
      {
        const double u = B.Domain[0] + (B.Domain[1] - B.Domain[0]) * i / 3.0 - P0.Domain[0];
        const double v = B.Domain[2] + (B.Domain[3] - B.Domain[2]) * j / 3.0 - P0.Domain[2];
        const double* q = &B.ControlPoints[3 * (4 * i + j)];
        for (int k = 0; k < 3; ++k)
          if (std::fabs(c[k] + u * X[k] + v * Y[k] - q[k]) > tol)
            return 0;
      }
  }
  return sign;
}

/// On a plane face whose patches are its isometric parametrisation (PlaneFrame), the largest
/// distance between an edge's point at T and the plane's point at its trimming segment's (u, v)
/// for the same T (the segment's local parameter mapped linearly onto [T0, T1], as the kernel's
/// second look maps it), over 17 points of every segment, 1.5 times that for what lies between
/// (the margin BuildPatchBoxes gives the edges' deviation from their faces). The chain's memo
/// asks for that much room beyond the second look's radius (memo_inside). 0 where no segment
/// has an edge.
double PlaneTrimEdgeGap(const BRepModel& m, int f)
{
  const Face& F = m.Faces[static_cast<size_t>(f)];
  const BezierPatch& P0 = m.Patches[static_cast<size_t>(F.FirstPatch)];
  const double du = P0.Domain[1] - P0.Domain[0], dv = P0.Domain[3] - P0.Domain[2];
  const double* c = P0.ControlPoints.data();
  double worst = 0.0;
  for (int l = F.FirstLoop; l < F.FirstLoop + F.LoopCount; ++l)
  {
    const TrimLoop& L = m.Loops[static_cast<size_t>(l)];
    for (int s = L.FirstSegment; s < L.FirstSegment + L.SegmentCount; ++s)
    {
      const TrimSegment& S = m.TrimSegments[static_cast<size_t>(s)];
      if (S.Edge < 0 || S.Edge >= static_cast<int>(m.Edges.size()))
        continue;
      const Edge& E = m.Edges[static_cast<size_t>(S.Edge)];
      if (E.SegmentCount <= 0)
        continue;
      for (int i = 0; i <= 16; ++i)
      {
        const double q = i / 16.0, T = S.T0 + q * (S.T1 - S.T0);
        const auto uv = EvaluateCubic<2>(S.ControlPoints.data(), q);
        // The edge segment the kernel's eval_edge takes: the first whose range ends at or
        // after T, else the last (by bisection, as there: the ends rise along the edge).
        int e = E.FirstSegment, last = E.FirstSegment + E.SegmentCount - 1;
        while (e < last)
        {
          const int mid = (e + last) / 2;
          if (T > m.EdgeSegments[static_cast<size_t>(mid)].T1)
            e = mid + 1;
          else
            last = mid;
        }
        const EdgeSegment& G = m.EdgeSegments[static_cast<size_t>(e)];
        const auto C = EvaluateCubic<3>(G.ControlPoints.data(), (T - G.T0) / (G.T1 - G.T0));
        const double a = (uv.P[0] - P0.Domain[0]) / du, b = (uv.P[1] - P0.Domain[2]) / dv;
        double d2 = 0.0;
        for (int k = 0; k < 3; ++k)
        {
          // The patch's bilinear corner map: exact on an isometric plane (PlaneFrame).
          const double p = c[k] + a * (c[36 + k] - c[k]) + b * (c[9 + k] - c[k]);
          d2 += (C.P[k] - p) * (C.P[k] - p);
        }
        worst = std::max(worst, std::sqrt(d2));
      }
    }
  }
  return 1.5 * worst;
}
} // namespace

template <class T>
KernelModel<T> PackKernelModel(
  const BRepModel& m, const SolverData& data, const PackOptions& options)
{
  KernelModel<T> k;
  const auto& c = data.Centre;
  k.Breaks.assign(data.Breaks.begin(), data.Breaks.end());
  // Every array at its final size up front: grown by doubling, the copies and the fresh pages
  // were most of the packing (s1 alone is 286k points on the ExpansionCard).
  const size_t np = m.Patches.size(), nf = m.Faces.size(), nt = m.TrimSegments.size();
  const size_t ne = m.Edges.size(), nes = m.EdgeSegments.size(), ns = data.S1.size();
  k.PatchAnchor.reserve(6 * np);
  k.Patches.reserve(48 * np);
  k.PatchDomain.reserve(4 * np);
  k.PatchFace.reserve(np);
  k.PatchSector.assign(KernelPatchSectorReals * np, T(0));
  std::vector<int> tubePatches; // of faces with no exact surface (PackPatchTube)
  k.PatchHull.resize(KernelPatchHullReals * np);
  k.FaceInfo.reserve(KernelFaceInts * nf);
  k.FaceDomain.reserve(KernelFaceReals * nf);
  k.Loops.reserve(2 * m.Loops.size());
  k.Trim.reserve(12 * nt);
  k.TrimEdge.reserve(nt);
  k.TrimRange.reserve(2 * nt);
  k.EdgeInfo.reserve(4 * ne);
  k.EdgeRange.reserve(4 * ne);
  k.EdgeAnchor.reserve(6 * nes);
  k.EdgeSeg.reserve(12 * nes);
  k.EdgeSegRange.reserve(2 * nes);
  k.EdgeSegEdge.reserve(nes);
  k.S1Point.reserve(3 * ns);
  k.S1Face.reserve(ns);
  k.S1UV.reserve(2 * ns);
  for (const auto& p : m.Patches)
  {
    // Anchor: the first control point, relative to the centre.
    const std::array<double, 3> a{ p.ControlPoints[0] - c[0], p.ControlPoints[1] - c[1],
      p.ControlPoints[2] - c[2] };
    PushSplit(k.PatchAnchor, a);
    for (int i = 0; i < 48; ++i)
      k.Patches.push_back(static_cast<T>(p.ControlPoints[i] - c[i % 3] - a[i % 3]));
    k.PatchDomain.insert(k.PatchDomain.end(), p.Domain.begin(), p.Domain.end());
    k.PatchFace.push_back(p.Face);
  }
  // The control nets' constants (PackPatchHull), on every core.
  ParallelFor(np, 0, [&](size_t p) {
    PackPatchHull(&k.Patches[48 * p], &k.PatchHull[KernelPatchHullReals * p]);
  });
  for (size_t f = 0; f < m.Faces.size(); ++f)
  {
    const Face& F = m.Faces[f];
    std::array<double, 12> exact{};
    int kind = PackExactSurface(m, static_cast<int>(f), c, exact);
    if (kind != 0 && !ExactSurfaceFitsPatches(m, static_cast<int>(f), kind, exact, c))
    {
      // A description the kernels would misread: the patches alone (ExactSurfaceFitsPatches).
      kind = 0;
      exact = {};
    }
    // A plane's frame (PlaneFrame): X in the sizes, which a plane leaves unused, the sign in
    // the face's slot 11.
    int frame = 0;
    if (kind == 1)
    {
      double X[3];
      frame = PlaneFrame(m, static_cast<int>(f), &exact[6], X);
      if (frame != 0)
        for (int i = 0; i < 3; ++i)
          exact[9 + i] = X[i];
    }
    k.FaceInfo.insert(k.FaceInfo.end(),
      { F.FirstPatch, F.PatchesU, F.PatchesV, data.FaceBreaks[f], F.FirstLoop, F.LoopCount,
        F.Reversed ? 1 : 0, F.Solid, kind, -1,
        PatchesAreTheSurface(m, static_cast<int>(f)) ? 1 : 0, frame });
    k.FaceInfo.insert(k.FaceInfo.end(), KernelWallPartners, -1); // PackWallPartners, below
    k.FaceDomain.insert(k.FaceDomain.end(), F.Domain.begin(), F.Domain.end());
    k.FaceDomain.insert(k.FaceDomain.end(), { static_cast<T>(F.Period[0]),
      static_cast<T>(F.Period[1]), static_cast<T>(F.UVTolerance) });
    PushSplit(k.FaceDomain, { exact[0], exact[1], exact[2] });
    for (int i = 6; i < 12; ++i)
      k.FaceDomain.push_back(static_cast<T>(exact[i]));
    k.FaceDomain.push_back(static_cast<T>(F.MaxDeviation));
    // The memo's room on a framed plane (KernelFaceTrimEdgeGap).
    k.FaceDomain.push_back(
      static_cast<T>(frame != 0 ? PlaneTrimEdgeGap(m, static_cast<int>(f)) : 0.0));
    // Whether the face's loops cross (KernelFaceLoopsCross; a solve data without it: none).
    k.FaceDomain.push_back(static_cast<T>(
      data.FaceLoopsCross.size() == nf ? data.FaceLoopsCross[f] : -1.0));
    // Per patch of a cylinder (EXACT_CYLINDER) its sector, of a torus (EXACT_TORUS) whose tube
    // is clear of the axis its arc of the tube (cylinder_patch_gap, torus_patch_gap): on a torus
    // written as one the arc its (u, v) domain spans (its parameters are the torus's angles), on
    // one read from a B-spline the arc that holds its control hull.
    const double o[3] = { exact[0] + c[0], exact[1] + c[1], exact[2] + c[2] };
    // Per patch of a sphere or a torus, also the cone of directions from the centre, resp. the
    // wedge around the axis, that holds its control points (sphere_patch_gap, torus_patch_gap).
    // On a torus written as one the arc is its parameters', whose points lie within the
    // deviation of the patch's: the wedge is widened by the angle that deviation spans from
    // the axis (twice the measure; none where the face has no measure).
    const bool torus = kind == 5 && exact[9] > exact[10];
    const bool native = F.DegreeU == 0 && F.DegreeV == 0;
    // Per patch of a face with no exact surface, the tube that holds it (tube_patch_gap; fitted
    // on every core below).
    if (kind == 0 && options.Tubes)
      for (int p = F.FirstPatch; p < F.FirstPatch + F.PatchCount; ++p)
        tubePatches.push_back(p);
    if (kind == 2 || torus || kind == 4)
      for (int p = F.FirstPatch; p < F.FirstPatch + F.PatchCount; ++p)
      {
        T* sector = &k.PatchSector[KernelPatchSectorReals * static_cast<size_t>(p)];
        const double* cp = m.Patches[p].ControlPoints.data();
        double v0 = m.Patches[p].Domain[2], v1 = m.Patches[p].Domain[3];
        if (kind == 2)
          PackCylinderSector<T>(cp, o, &exact[6], sector);
        else if (kind == 4)
          PackDirectionCone<T>(cp, o, nullptr, 0.0, sector + 8);
        else
        {
          if (native || TorusArcOfPatch(cp, o, &exact[6], exact[9], v0, v1))
            PackTorusArc<T>(v0, v1, sector);
          const double spread = 2.0 * F.MaxDeviation / (exact[9] - exact[10]);
          if (F.MaxDeviation >= 0.0 && spread < 0.5)
            PackDirectionCone<T>(cp, o, &exact[6], std::asin(spread), sector + 8);
        }
      }
  }
  ParallelFor(tubePatches.size(), 0, [&](size_t i) {
    const int p = tubePatches[i];
    PackPatchTube<T>(m.Patches[static_cast<size_t>(p)].ControlPoints.data(), 2.0 * m.Tolerance,
      &k.PatchSector[KernelPatchSectorReals * static_cast<size_t>(p)]);
  });
  if (options.Tubes && m.FaceExact.size() == m.Faces.size())
  {
    // Each face's neighbours' distinct axes (cylinders, cones, tori; one line within the
    // conversion tolerance), as the index of the first neighbour on each line.
    std::vector<std::vector<int>> axisFaces(nf);
    auto hasAxis = [&](int f) {
      const SurfaceKind kd = m.Faces[static_cast<size_t>(f)].Kind;
      const auto& e = m.FaceExact[static_cast<size_t>(f)];
      return (kd == SurfaceKind::Cylinder || kd == SurfaceKind::Cone ||
               kd == SurfaceKind::Torus) &&
        std::fabs(e[3] * e[3] + e[4] * e[4] + e[5] * e[5] - 1.0) < 1e-9; // a unit axis
    };
    auto sameLine = [&](int f, int g) {
      const auto& a = m.FaceExact[static_cast<size_t>(f)];
      const auto& b = m.FaceExact[static_cast<size_t>(g)];
      const double x[3] = { a[4] * b[5] - a[5] * b[4], a[5] * b[3] - a[3] * b[5],
        a[3] * b[4] - a[4] * b[3] };
      if (!(x[0] * x[0] + x[1] * x[1] + x[2] * x[2] < 1e-18))
        return false;
      double w[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
      const double along = w[0] * a[3] + w[1] * a[4] + w[2] * a[5];
      for (int j = 0; j < 3; ++j)
        w[j] -= along * a[3 + j];
      return w[0] * w[0] + w[1] * w[1] + w[2] * w[2] <= m.Tolerance * m.Tolerance;
    };
    for (const auto& e : m.Edges)
      for (int side = 0; side < 2; ++side)
      {
        const int f = e.Faces[side], g = e.Faces[1 - side];
        if (f < 0 || g < 0 || f == g || !hasAxis(g) ||
          k.FaceInfo[KernelFaceInts * static_cast<size_t>(f) + 8] != 0)
          continue;
        auto& list = axisFaces[static_cast<size_t>(f)];
        if (std::none_of(list.begin(), list.end(), [&](int h) { return sameLine(h, g); }))
          list.push_back(g);
      }
    // The patches of cones (about their own axis) and of faces with no exact surface and no
    // tube beside a face with an axis (about the one of those axes the patch's control points
    // turn round the most, from a tenth of a radian: below that the control net's hull holds
    // the patch closely enough).
    std::vector<std::pair<int, int>> boxPatches; // (patch, the face whose axis)
    for (size_t f = 0; f < nf; ++f)
    {
      const Face& F = m.Faces[f];
      const int kind = k.FaceInfo[KernelFaceInts * f + 8];
      if (kind == 3)
        for (int p = F.FirstPatch; p < F.FirstPatch + F.PatchCount; ++p)
          boxPatches.emplace_back(p, static_cast<int>(f));
      else if (kind == 0 && !axisFaces[f].empty())
        for (int p = F.FirstPatch; p < F.FirstPatch + F.PatchCount; ++p)
          if (!(k.PatchSector[KernelPatchSectorReals * static_cast<size_t>(p) + 9] > T(0)))
            boxPatches.emplace_back(p, -1);
    }
    ParallelFor(boxPatches.size(), 0, [&](size_t i) {
      const int p = boxPatches[i].first;
      const BezierPatch& P = m.Patches[static_cast<size_t>(p)];
      int g = boxPatches[i].second;
      if (g < 0)
      {
        double most = 0.1;
        for (int h : axisFaces[static_cast<size_t>(P.Face)])
        {
          const auto& e = m.FaceExact[static_cast<size_t>(h)];
          const double angle = AngleAroundAxis(P.ControlPoints.data(), &e[0], &e[3]);
          if (angle > most)
          {
            most = angle;
            g = h;
          }
        }
        if (g < 0)
          return;
      }
      // The part of the patch inside its face's trim: a thread's flank runs on inside the core
      // it stands on.
      const std::array<double, 48> part = data.PatchTrimBox.size() == 4 * np
        ? RestrictedControlPoints(P, &data.PatchTrimBox[4 * static_cast<size_t>(p)])
        : P.ControlPoints;
      const auto& e = m.FaceExact[static_cast<size_t>(g)];
      PackPatchAxisBox<T>(P.ControlPoints.data(), part.data(), &e[0], &e[3],
        &k.PatchSector[KernelPatchSectorReals * static_cast<size_t>(p)]);
    });
  }
  for (const auto& l : m.Loops)
    k.Loops.insert(k.Loops.end(), { l.FirstSegment, l.SegmentCount });
  for (const auto& s : m.TrimSegments)
  {
    // The control points, then their box (u0, v0, u1, v1) in the same precision (TRIM_REALS).
    const size_t at = k.Trim.size();
    k.Trim.insert(k.Trim.end(), s.ControlPoints.begin(), s.ControlPoints.end());
    T box[4] = { k.Trim[at], k.Trim[at + 1], k.Trim[at], k.Trim[at + 1] };
    for (size_t i = 1; i < 4; ++i)
    {
      box[0] = std::min(box[0], k.Trim[at + 2 * i]);
      box[1] = std::min(box[1], k.Trim[at + 2 * i + 1]);
      box[2] = std::max(box[2], k.Trim[at + 2 * i]);
      box[3] = std::max(box[3], k.Trim[at + 2 * i + 1]);
    }
    k.Trim.insert(k.Trim.end(), box, box + 4);
    k.TrimEdge.push_back(s.Edge);
    k.TrimRange.insert(k.TrimRange.end(), { static_cast<T>(s.T0), static_cast<T>(s.T1) });
  }
  PackTrimTrees(m, k);
  for (const auto& e : m.Edges)
  {
    k.EdgeInfo.insert(k.EdgeInfo.end(), { e.FirstSegment, e.SegmentCount, e.Faces[0], e.Faces[1] });
    // T0, T1 and the edge's distance from each of its faces' exact surfaces (-1: none).
    const size_t at = 2 * (k.EdgeRange.size() / 4);
    const bool dev = data.EdgeFaceDeviation.size() == 2 * m.Edges.size();
    k.EdgeRange.insert(k.EdgeRange.end(), { static_cast<T>(e.T0), static_cast<T>(e.T1),
      static_cast<T>(dev ? data.EdgeFaceDeviation[at] : -1.0),
      static_cast<T>(dev ? data.EdgeFaceDeviation[at + 1] : -1.0) });
  }
  for (const auto& s : m.EdgeSegments)
  {
    const std::array<double, 3> a{ s.ControlPoints[0] - c[0], s.ControlPoints[1] - c[1],
      s.ControlPoints[2] - c[2] };
    PushSplit(k.EdgeAnchor, a);
    for (int i = 0; i < 12; ++i)
      k.EdgeSeg.push_back(static_cast<T>(s.ControlPoints[i] - c[i % 3] - a[i % 3]));
    k.EdgeSegRange.insert(k.EdgeSegRange.end(), { static_cast<T>(s.T0), static_cast<T>(s.T1) });
    k.EdgeSegEdge.push_back(s.Edge);
  }
  for (const auto& p : data.S1)
  {
    for (int j = 0; j < 3; ++j)
      k.S1Point.push_back(static_cast<T>(p.Point[j] - c[j]));
    k.S1Face.push_back(p.OnEdge ? ~p.Face : p.Face); // edge points: verification only (s1_face)
    k.S1UV.insert(k.S1UV.end(), { static_cast<T>(p.U), static_cast<T>(p.V) });
  }
  PushNodes(data.Nodes, c, k.NodeBox, k.NodeInfo);
  // (SolverData built without BuildVertices or BuildPatchBoxes: no vertices and no boxes, rather
  // than reads past the arrays; the certification is then skipped.)
  k.VertexInfo = data.VertexInfo.size() >= 2 * m.Edges.size()
    ? data.VertexInfo
    : std::vector<int>(2 * m.Edges.size(), -1);
  if (data.PatchBoxes.size() == 6 * m.Patches.size() &&
    data.EdgeBoxes.size() == 6 * m.EdgeSegments.size() && !data.BoxNodes.empty())
  {
    k.PatchBoxes = RelativeBoxes<T>(data.PatchBoxes, c);
    k.EdgeBoxes = RelativeBoxes<T>(data.EdgeBoxes, c);
    PushNodes(data.BoxNodes, c, k.BoxNodeBox, k.BoxNodeInfo);
    k.BoxItems = data.BoxItems;
  }
  PackWallPartners(data, k);
  return k;
}

template <class T>
KernelScalars GetKernelScalars(const BRepModel& m, const SolverData& data, const SolverOptions& options)
{
  KernelScalars s;
  s.Scale = data.Scale;
  s.StepTol = (sizeof(T) == 8 ? 1e-13 : 2e-7) * data.Scale;
  // Float's residual cannot fall below its rounding of the coordinates it is made of (patches
  // up to the model's size across, spheres up to half of it): on a 6.7 m assembly eq. 4 on two
  // parallel planes stalled at |R| = 1.4e-4 above the default 1e-4 and failed every such sample.
  // One float epsilon of the model's size is a floor that Newton reaches; the finish in double
  // polishes to NewtonTolerance.
  s.NewtonTol = sizeof(T) == 4 ?
    std::max(options.NewtonTolerance, static_cast<double>(FLT_EPSILON) * data.Scale) :
    options.NewtonTolerance;
  s.Slack = 2.0 * m.Tolerance;
  s.Clearance = options.Clearance < 0.0 ? 2.0 * m.Tolerance : options.Clearance;
  s.S1Spacing = data.S1Spacing;
  s.MaxIterations = options.MaxIterations;
  s.MaxEdgeIterations = options.MaxEdgeIterations;
  s.Certify = options.Certify ? 1 : 0;
  s.Exterior = options.Exterior ? 1 : 0;
  s.AllSolids = options.AllSolids ? 1 : 0;
  return s;
}

template <class T>
void PackSample(const SolverData& data, const Sample& s, T* out)
{
  const auto& c = data.Centre;
  for (int j = 0; j < 3; ++j)
  {
    const double o = s.Point[j] - c[j];
    out[j] = static_cast<T>(o);
    out[3 + j] = static_cast<T>(o - static_cast<double>(static_cast<T>(o)));
    out[6 + j] = static_cast<T>(s.Direction[j]);
  }
  out[9] = static_cast<T>(s.U);
  out[10] = static_cast<T>(s.V);
  out[11] = static_cast<T>(s.Curvature[0]);
}

template <class T>
bool UnpackResult(const Sample& s, const T* oR, const int* oI, SampleResult& r)
{
  r = SampleResult();
  r.Type = static_cast<ContactType>(oI[0]);
  r.Reason = static_cast<FailReason>(oI[1]);
  r.OppositeFace = oI[2];
  r.OppositePatch = oI[3];
  r.OppositeEdge = oI[4];
  r.Iterations = oI[5];
  r.Residual = static_cast<double>(oR[4]);
  if (r.Type == ContactType::Failed)
    return oI[6] != 0;
  const double t = static_cast<double>(oR[0]);
  r.Radius = t;
  r.Thickness = 2.0 * t;
  for (int j = 0; j < 3; ++j)
  {
    r.Center[j] = s.Point[j] + t * s.Direction[j];
    r.Foot[j] = s.Point[j] + static_cast<double>(oR[1 + j]);
  }
  r.FootParameter = { static_cast<double>(oR[5]), static_cast<double>(oR[6]) };
  return oI[6] != 0;
}

// A face's ints: the 12 PackKernelModel lists, then its wall partners.
static_assert(KernelFaceInts == 12 + KernelWallPartners, "the faces' ints as packed");

template <class T>
void PackWallPartners(const SolverData& data, KernelModel<T>& k)
{
  const size_t nf = k.FaceInfo.size() / KernelFaceInts;
  if (data.WallPartners.size() != KernelWallPartners * nf)
    return;
  for (size_t f = 0; f < nf; ++f)
    for (size_t j = 0; j < KernelWallPartners; ++j)
      k.FaceInfo[KernelFaceInts * f + (KernelFaceInts - KernelWallPartners) + j] =
        data.WallPartners[KernelWallPartners * f + j];
}

template void PackWallPartners<float>(const SolverData&, KernelModel<float>&);
template void PackWallPartners<double>(const SolverData&, KernelModel<double>&);
template KernelModel<float> PackKernelModel<float>(
  const BRepModel&, const SolverData&, const PackOptions&);
template KernelModel<double> PackKernelModel<double>(
  const BRepModel&, const SolverData&, const PackOptions&);
template KernelScalars GetKernelScalars<float>(const BRepModel&, const SolverData&, const SolverOptions&);
template KernelScalars GetKernelScalars<double>(const BRepModel&, const SolverData&, const SolverOptions&);
template void PackSample<float>(const SolverData&, const Sample&, float*);
template void PackSample<double>(const SolverData&, const Sample&, double*);
template bool UnpackResult<float>(const Sample&, const float*, const int*, SampleResult&);
template bool UnpackResult<double>(const Sample&, const double*, const int*, SampleResult&);

} // namespace brt
