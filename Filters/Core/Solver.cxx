#include "Solver.h"

#include "Bezier.h"
#include "TrimClassifier.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <thread>
#include <unordered_map>

namespace brt
{

const char* ContactTypeName(ContactType type)
{
  switch (type)
  {
    case ContactType::SurfaceSurface: return "surface/surface";
    case ContactType::SurfaceEdge: return "surface/edge";
    case ContactType::SurfaceVertex: return "surface/vertex";
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
inline Vec3 Axpy(const Vec3& o, double t, const Vec3& d)
{
  return { o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2] };
}

/// The clearance delta, 2x the conversion tolerance: the solver looks for the largest sphere
/// tangent at O (centre M = O + t d) that no boundary point enters deeper than delta, i.e. it
/// minimises t_delta(P) = (|P-O|^2 - delta^2) / (2 (d.(P-O) - delta)), the t at which P lies
/// delta inside the sphere (|P - M| = t - delta), over the patches. For delta = 0 this is eq. 1.
/// Where the sphere touches a whole arc (an osculating sphere on a round, a spherical corner
/// blend) t(P) is flat along the arc up to the patches' error e, which it amplifies by
/// 1 / (1 - cos theta) (theta the angle at M between O and P): minimising t, double and float
/// picked different noise minima, up to 2% apart. t_delta adds about delta / (1 - cos theta),
/// which the patches' error (< delta / 2) cannot cancel, so its minimum is the arc point
/// farthest from O, well defined in both precisions. Near O, t_delta is large (P within delta of
/// O's tangent plane gives none): the trivial and osculating solutions next to O disappear.
/// The reported radius is eq. 1's t(P) at the foot point found (ReportRadius): exact wherever
/// the contact is a strict minimum of t (plates, tubes, shells: 0 bias), within delta^2 / (2 t)
/// elsewhere.
inline double Clearance(const BRepModel& m, const SolverOptions& opt)
{
  return opt.Clearance < 0.0 ? 2.0 * m.Tolerance : opt.Clearance;
}

/// How far the centre of a sphere may lie outside a face it touches (along the face's outward
/// normal at the foot), other than the sample's own, and still count as touching it from inside
/// (FromInside): the clearance plus the patches' error. A sample on a convex edge (a mesh vertex
/// on it) lies within the conversion tolerance of the face across, possibly on its outer side;
/// its sphere is about the clearance (at the edge the thickness goes to 0), and it touches the
/// face across from "outside" by up to that much (the FRAMEWORK tile's failed samples: all within
/// 1e-3 mm of an edge). A sphere touching a face really from outside has its centre t - delta
/// beyond it: only spheres below twice the clearance plus the tolerance are affected.
inline double OutsideSlack(const BRepModel& m, const SolverOptions& opt)
{
  return Clearance(m, opt) + m.Tolerance;
}

/// t_delta(P) = (|P-O|^2 - delta^2) / (2 (d.(P-O) - delta)), the radius at which the sphere
/// tangent at O holds the boundary point P delta deep (see Clearance; delta = 0: eq. 1),
/// infinite when P is not more than delta in front of O.
double SphereRadius(const Vec3& O, const Vec3& d, const Vec3& P, double delta)
{
  const Vec3 w = Sub(P, O);
  const double b = Dot(d, w) - delta;
  return b > 0.0 ? 0.5 * (Dot(w, w) - delta * delta) / b : std::numeric_limits<double>::infinity();
}

// --- BVH -------------------------------------------------------------------------------------
int Build(std::vector<S1Point>& pts, std::vector<BVHNode>& nodes, int first, int count)
{
  const int id = static_cast<int>(nodes.size());
  nodes.emplace_back();
  BVHNode node;
  node.Min = { std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
    std::numeric_limits<double>::max() };
  node.Max = { -node.Min[0], -node.Min[1], -node.Min[2] };
  for (int i = first; i < first + count; ++i)
    for (int k = 0; k < 3; ++k)
    {
      node.Min[k] = std::min(node.Min[k], pts[i].Point[k]);
      node.Max[k] = std::max(node.Max[k], pts[i].Point[k]);
    }
  if (count <= 4)
  {
    node.First = first;
    node.Count = count;
    nodes[id] = node;
    return id;
  }
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (node.Max[k] - node.Min[k] > node.Max[axis] - node.Min[axis])
      axis = k;
  const int half = count / 2;
  std::nth_element(pts.begin() + first, pts.begin() + first + half, pts.begin() + first + count,
    [axis](const S1Point& a, const S1Point& b) { return a.Point[axis] < b.Point[axis]; });
  Build(pts, nodes, first, half);
  node.Right = Build(pts, nodes, first + half, count - half);
  nodes[id] = node;
  return id;
}

double BoxDistance2(const BVHNode& n, const Vec3& p)
{
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k)
  {
    const double e = std::max({ n.Min[k] - p[k], 0.0, p[k] - n.Max[k] });
    d2 += e * e;
  }
  return d2;
}

/// Eq. 1 with the BVH and the clearance: the s1 point P minimising t_delta(P) over
/// d.(P-O) > delta, below `bound`. A point gives a smaller t_delta exactly when it lies strictly
/// inside the current sphere shrunk by delta (centre M = O + t d, radius t - delta), so nodes
/// farther than that from M are pruned (the paper's bound 2t is looser). With a finite bound
/// this is also the verification: the s1 points deeper than delta inside the sphere found. (The
/// depth must be a distance: near O, eq. 1's t drops steeply for a point barely inside the sphere,
/// and a bound on it rejected maximal spheres on fillets by the thousand.)
/// With `behind`, only the points on the side of O opposite to it count, (P - O).behind < 0 (the
/// second look's other end of an arc).
int Initialise(const BRepModel& m, const SolverData& data, const Sample& s, double delta,
  double& bestT, double bound = std::numeric_limits<double>::infinity(), int excludeFace = -1,
  const Vec3* behind = nullptr)
{
  // Thickness is a property of one solid: in an assembly, the walls of other solids don't count.
  const int solid = m.Faces[s.Face].Solid;
  const double minDist2 = (1e-9 * data.Scale) * (1e-9 * data.Scale);
  bestT = bound; // only points giving a smaller t count: with a finite bound, points inside
                 // the sphere of that radius
  int best = -1;
  int stack[64];
  int top = 0;
  stack[top++] = 0;
  const Vec3& O = s.Point;
  const Vec3& d = s.Direction;
  while (top > 0)
  {
    const BVHNode& n = data.Nodes[stack[--top]];
    if (std::isfinite(bestT))
    {
      const Vec3 M = Axpy(O, bestT, d);
      if (BoxDistance2(n, M) >= (bestT - delta) * (bestT - delta))
        continue;
    }
    if (n.Count > 0)
    {
      for (int i = n.First; i < n.First + n.Count; ++i)
      {
        if (m.Faces[data.S1[i].Face].Solid != solid || data.S1[i].Face == excludeFace ||
          (data.S1[i].OnEdge && !std::isfinite(bound)))
          continue;
        const Vec3 w = Sub(data.S1[i].Point, O);
        const double dn = Dot(d, w), l2 = Dot(w, w);
        // Points in O's tangent plane (its own face, flat around it) give no sphere, nor do
        // points on top of O (an s1 point may coincide with a sample).
        if (dn <= delta + 1e-6 * std::sqrt(l2) || l2 <= minDist2 ||
          (behind && !(Dot(w, *behind) < 0.0)))
          continue;
        const double t = 0.5 * (l2 - delta * delta) / (dn - delta);
        if (t < bestT)
        {
          bestT = t;
          best = i;
        }
      }
      continue;
    }
    const int left = static_cast<int>(&n - data.Nodes.data()) + 1, right = n.Right;
    const Vec3 ref = std::isfinite(bestT) ? Axpy(O, bestT, d) : O;
    const bool leftFirst = BoxDistance2(data.Nodes[left], ref) <= BoxDistance2(data.Nodes[right], ref);
    if (top + 2 > 64)
      continue; // cannot happen for a balanced tree of < 2^60 points
    stack[top++] = leftFirst ? right : left;
    stack[top++] = leftFirst ? left : right;
  }
  return best;
}

/// Least-squares step with a little damping, for a singular Jacobian (e.g. at a pole of the
/// opposite patch, where Su = 0): (J^T J + lambda I) x = J^T r.
bool Solve3(const double J[3][3], const double r[3], double x[3]);
bool Damped3(const double J[3][3], const double r[3], double x[3])
{
  double A[3][3], b[3];
  double trace = 0.0;
  for (int i = 0; i < 3; ++i)
  {
    b[i] = 0.0;
    for (int j = 0; j < 3; ++j)
    {
      A[i][j] = 0.0;
      for (int k = 0; k < 3; ++k)
        A[i][j] += J[k][i] * J[k][j];
    }
    for (int k = 0; k < 3; ++k)
      b[i] += J[k][i] * r[k];
    trace += A[i][i];
  }
  if (!(trace > 0.0))
    return false;
  for (int i = 0; i < 3; ++i)
    A[i][i] += 1e-9 * trace;
  return Solve3(A, b, x);
}

bool Solve3(const double J[3][3], const double r[3], double x[3])
{
  const double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
    J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
    J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
  // Singular relative to the product of the column norms (Hadamard's bound on |det|), which is
  // blind to the columns' different units.
  double bound = 1.0;
  for (int j = 0; j < 3; ++j)
    bound *= std::sqrt(J[0][j] * J[0][j] + J[1][j] * J[1][j] + J[2][j] * J[2][j]);
  if (!(std::fabs(det) > 1e-14 * bound) || !(bound > 0.0))
    return false;
  for (int c = 0; c < 3; ++c)
  {
    double A[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        A[i][j] = j == c ? r[i] : J[i][j];
    x[c] = (A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
             A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
             A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0])) /
      det;
  }
  return true;
}

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
void AddEdgePoints(const BRepModel& m, double spacing, std::vector<S1Point>& s1);
}

SolverData PrepareSolver(const BRepModel& model, const SolverOptions& options)
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
  const double spacing = options.S1Spacing > 0.0 ? options.S1Spacing : data.Scale / 300.0;
  data.S1Spacing = spacing;

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

  // s1: a grid on every patch, sized from the patch's control net, kept where inside the trim.
  for (const BezierPatch& p : model.Patches)
  {
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
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j)
      {
        const double u = p.Domain[0] + (p.Domain[1] - p.Domain[0]) * (i + 0.5) / nu;
        const double v = p.Domain[2] + (p.Domain[3] - p.Domain[2]) * (j + 0.5) / nv;
        if (!ClassifyPoint(model, p.Face, u, v).Inside)
          continue;
        const PatchEval e = EvaluatePatch(p, u, v);
        data.S1.push_back({ e.P, p.Face, false, u, v });
      }
  }
  AddEdgePoints(model, spacing / 3.0, data.S1);
  if (!data.S1.empty())
    Build(data.S1, data.Nodes, 0, static_cast<int>(data.S1.size()));
  BuildVertices(model, data);
  BuildPatchBoxes(model, data);
  return data;
}

void BuildPatchBoxes(const BRepModel& model, SolverData& data)
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
  for (size_t p = 0; p < model.Patches.size(); ++p)
    box(model.Patches[p].ControlPoints.data(), 16, &data.PatchBoxes[6 * p]);
  data.EdgeBoxes.assign(6 * model.EdgeSegments.size(), 0.0);
  for (size_t e = 0; e < model.EdgeSegments.size(); ++e)
    box(model.EdgeSegments[e].ControlPoints.data(), 4, &data.EdgeBoxes[6 * e]);
  // BVH: median split of the box centres along the longest axis, leaves of up to 4 boxes.
  const int np = static_cast<int>(model.Patches.size());
  const int n = np + static_cast<int>(model.EdgeSegments.size());
  auto boxOf = [&](int item) {
    return item < np ? &data.PatchBoxes[6 * static_cast<size_t>(item)]
                     : &data.EdgeBoxes[6 * static_cast<size_t>(item - np)];
  };
  data.BoxItems.resize(static_cast<size_t>(n));
  std::iota(data.BoxItems.begin(), data.BoxItems.end(), 0);
  data.BoxNodes.clear();
  if (n == 0)
    return;
  struct Task
  {
    int First, Count, Parent;
  };
  std::vector<Task> tasks{ { 0, n, -1 } };
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
    for (int i = task.First; i < task.First + task.Count; ++i)
    {
      const double* b = boxOf(data.BoxItems[static_cast<size_t>(i)]);
      for (int k = 0; k < 3; ++k)
      {
        node.Min[k] = std::min(node.Min[k], b[k]);
        node.Max[k] = std::max(node.Max[k], b[3 + k]);
      }
    }
    if (task.Count <= 4)
    {
      node.First = task.First;
      node.Count = task.Count;
      data.BoxNodes.push_back(node);
      continue;
    }
    int axis = 0;
    for (int k = 1; k < 3; ++k)
      if (node.Max[k] - node.Min[k] > node.Max[axis] - node.Min[axis])
        axis = k;
    const int half = task.Count / 2;
    auto first = data.BoxItems.begin() + task.First;
    std::nth_element(first, first + half, first + task.Count, [&](int a, int b) {
      return boxOf(a)[axis] + boxOf(a)[3 + axis] < boxOf(b)[axis] + boxOf(b)[3 + axis];
    });
    data.BoxNodes.push_back(node);
    // Depth first, left child next: the right child is pushed first and popped last; its index
    // is patched into this node when it is built.
    tasks.push_back({ task.First + half, task.Count - half, index });
    tasks.push_back({ task.First, half, -1 });
  }
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

std::vector<Sample> SamplesFromMesh(const BRepModel& model, const SolverData& data)
{
  const DisplayMesh& M = model.Mesh;
  std::vector<Sample> out(M.NumberOfPoints());
  for (size_t i = 0; i < out.size(); ++i)
  {
    out[i].Face = M.FaceIds[i];
    out[i].U = M.UV[2 * i];
    out[i].V = M.UV[2 * i + 1];
    out[i].Point = { M.Points[3 * i], M.Points[3 * i + 1], M.Points[3 * i + 2] };
    out[i].Direction = { -M.Normals[3 * i], -M.Normals[3 * i + 1], -M.Normals[3 * i + 2] };
  }
  // Vertices on a face's boundary: at a convex edge the sphere tangent there has radius 0 and
  // Newton would chase t -> 0. Move them 1e-2 of the way to an adjacent triangle's centroid
  // (in UV, on the patches), where the sphere is small but well defined, also in float.
  std::unordered_map<std::uint64_t, int> uses;
  const size_t nt = M.TriangleFace.size();
  auto key = [](std::uint64_t a, std::uint64_t b) { return a < b ? (a << 32) | b : (b << 32) | a; };
  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k)
      ++uses[key(M.Triangles[3 * t + k], M.Triangles[3 * t + (k + 1) % 3])];
  std::vector<int> adjacent(out.size(), -1);
  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k)
    {
      const int a = M.Triangles[3 * t + k], b = M.Triangles[3 * t + (k + 1) % 3];
      if (uses[key(a, b)] == 1)
        adjacent[a] = adjacent[b] = static_cast<int>(t);
    }
  for (size_t i = 0; i < out.size(); ++i)
  {
    const int t = adjacent[i];
    Sample& s = out[i];
    const Face& F = model.Faces[s.Face];
    if (t < 0 || F.PatchCount == 0)
      continue;
    double cu = 0.0, cv = 0.0;
    for (int k = 0; k < 3; ++k)
    {
      cu += M.UV[2 * M.Triangles[3 * t + k]] / 3.0;
      cv += M.UV[2 * M.Triangles[3 * t + k] + 1] / 3.0;
    }
    s.U += 1e-2 * (cu - s.U);
    s.V += 1e-2 * (cv - s.V);
    const PatchEval e =
      EvaluatePatch(model.Patches[FindPatchFast(model, data, s.Face, s.U, s.V)], s.U, s.V);
    Vec3 n{ e.Du[1] * e.Dv[2] - e.Du[2] * e.Dv[1], e.Du[2] * e.Dv[0] - e.Du[0] * e.Dv[2],
      e.Du[0] * e.Dv[1] - e.Du[1] * e.Dv[0] };
    const double len = std::sqrt(Dot(n, n));
    if (!(len > 0.0))
      continue; // singular point of the patch: keep the exact sample
    const double sign = F.Reversed ? 1.0 : -1.0; // inward = -outward
    s.Point = e.P;
    s.Direction = { sign * n[0] / len, sign * n[1] / len, sign * n[2] / len };
  }
  return out;
}

namespace
{
/// x moved by whole periods into [lo, lo + period) when period > 0.
double Wrap(double x, double lo, double period)
{
  return period > 0.0 ? lo + (x - lo) - period * std::floor((x - lo) / period) : x;
}

/// |R| in model units: the tangential equations divided by the tangent lengths, so that each
/// component is a distance (the raw S_u.(S-M) scales with the face's parametrisation).
double Residual3(const PatchEval& e, const double R[3])
{
  const double lu = std::sqrt(Dot(e.Du, e.Du)), lv = std::sqrt(Dot(e.Dv, e.Dv));
  const double a = lu > 0.0 ? R[0] / lu : 0.0, b = lv > 0.0 ? R[1] / lv : 0.0;
  return std::sqrt(a * a + b * b + R[2] * R[2]);
}
double Residual2(const Vec3& Ct, const double R[2])
{
  const double l = std::sqrt(Dot(Ct, Ct));
  return std::hypot(l > 0.0 ? R[0] / l : 0.0, R[1]);
}

/// Outcome of the surface/surface Newton (eq. 4) on one face.
struct SurfaceSolve
{
  double U = 0.0, V = 0.0, T = 0.0, Res = 0.0;
  int Patch = -1;
  Vec3 Foot{};
  bool Singular = false;
  bool Clamped = false; ///< the last step stopped at the face's domain
  bool Capped = true;   ///< the loop ran out of iterations instead of stopping on its own
  TrimProjection Trim;  ///< trim test of the final (u, v)
  /// |R| within the tolerance; a run that hit the iteration cap with |R| just under the
  /// tolerance (still crawling) is not trusted unless |R| is far below it.
  bool Converged(const SolverOptions& opt) const
  {
    return Res <= opt.NewtonTolerance && (!Capped || Res <= 1e-2 * opt.NewtonTolerance);
  }
  /// The foot point is on the face: inside the trim, or within the face's UV tolerance of it
  /// (a seam, say), and not pushed against the domain by an unconverged run.
  bool OnFace(const Face& F, const SolverOptions& opt) const
  {
    return (Trim.Inside || Trim.Distance <= F.UVTolerance) && (!Clamped || Converged(opt));
  }
  /// (M - P).n_out at the foot point (unit outward normal): <= 0 where the sphere lies on the
  /// material side of the face. A stationary sphere touching the face from outside is no
  /// inscribed sphere (Newton can converge to one); see FromInside.
  double Side = 0.0;
  Vec3 Normal{}; ///< the patch normal at the foot (not unit; outward up to the face's orientation)
};

/// P within the patches' accuracy (2x the conversion tolerance) of O.
bool NearSample(const BRepModel& m, const Sample& s, const Vec3& P)
{
  const Vec3 w = Sub(P, s.Point);
  const double slack = 2.0 * m.Tolerance;
  return Dot(w, w) <= slack * slack;
}

/// P on O's own face next to O: the trivial solution P = O of eq. 4, whatever t comes with it
/// (in float, d.(P-O) is rounding there, and the descent's t with it).
bool AtSample(const BRepModel& m, const Sample& s, int face, const Vec3& P)
{
  return face == s.Face && NearSample(m, s, P);
}

/// The same for an edge of O's own face: an edge point within that accuracy of O (a sample on
/// or next to an edge) is the trivial solution again, with t = |C-O|^2 / (2 d.(C-O)) of rounding
/// (2t = 0.025 mm at 1.3e-4 mm from O on the FRAMEWORK tile; 2.990 for 3.000 on the hinge).
bool EdgeAtSample(const BRepModel& m, const Sample& s, int edge, const Vec3& C)
{
  const Edge& E = m.Edges[edge];
  return (E.Faces[0] == s.Face || E.Faces[1] == s.Face) && NearSample(m, s, C);
}

/// A foot within the patches' accuracy of O on a face that continues O's tangent plane there
/// (its normal within 2e-3 rad of O's, the face across a tangent edge next to O): the trivial
/// solution again, whichever face it is on (a hinge sample on the tangent edge of a 1.5 mm bore
/// read 2t = 2.990 or, in float, 0.333 for 3.000 from a foot 5.7e-5 mm from O). At a sharp
/// convex edge the face across stands at an angle and its contacts are real. (The test's check
/// takes 1e-3 rad: a sphere tangent at a foot that close to O has its normal there within
/// |P - O| / t of d, and float put one at 1.0e-3 rad with its foot 1.98e-4 mm from O.)
bool TangentAtSample(const BRepModel& m, const Sample& s, const Vec3& P, const Vec3& n)
{
  if (!NearSample(m, s, P))
    return false;
  const Vec3& d = s.Direction;
  const Vec3 c{ n[1] * d[2] - n[2] * d[1], n[2] * d[0] - n[0] * d[2], n[0] * d[1] - n[1] * d[0] };
  return Dot(c, c) <= 4e-6 * Dot(n, n);
}

/// Eq. 4 on the sample's own face has a trivial solution: P = O solves it for every t, and
/// Newton converges there when it starts near O (typically after crossing the edge next to O
/// from a neighbour face), stopping at an arbitrary t. Near it lie the osculating spheres: a
/// foot point P on O's own face close to O gives the face's curvature radius between O and P,
/// t = |P-O|^2 / (2 d.(P-O)), and an error e in the patches changes t by about e / d.(P-O)
/// relative: on a round of radius 0.3 patched to 2e-5, spheres 0.2% too small pass as tangent.
/// So a contact on O's own face counts only where it is deep, d.(P-O) >= t/2 (the normals at O
/// and P at least 60 degrees apart: a tube's far wall, a bent sheet's other leg), and not
/// within the patches' accuracy (2x the conversion tolerance) of O. The sphere of a round then
/// comes from the faces the round is tangent to, or from its far side. Contacts on other faces
/// near O are real (a sample next to a convex edge, or next to a tangent fillet).
bool ShallowOwnFaceContact(
  const BRepModel& m, const Sample& s, int face, const Vec3& P, double t)
{
  if (face != s.Face)
    return false;
  const Vec3 w = Sub(P, s.Point);
  return AtSample(m, s, face, P) || Dot(w, s.Direction) < 0.5 * t;
}

/// The sphere touches `face` from inside: its centre lies on the material side of the face at
/// the foot, side = (M - P).n_out <= 0, or, on a face other than the sample's, at most
/// OutsideSlack outside it. On the sample's own face a contact from outside is the trivial
/// solution next to O: no slack there.
bool FromInside(
  const BRepModel& m, const SolverOptions& opt, const Sample& s, int face, double side)
{
  return !(side > (face == s.Face ? 0.0 : OutsideSlack(m, opt)));
}

/// Surface/surface Newton (eq. 4) on `face` from (u, v, t), with trust region and backtracking.
SurfaceSolve SurfaceNewton(const BRepModel& m, const SolverData& data, const SolverOptions& opt,
  const Vec3& O, const Vec3& d, int face, double u, double v, double t, int& iterations)
{
  const Face& F = m.Faces[face];
  const double stepTol = 1e-13 * data.Scale;
  const double delta = Clearance(m, opt);
  SurfaceSolve out;
  int patch = -1;
  bool clamped = false;
  // State at (u, v, t): patch evaluation, w = S - M, residual.
  PatchEval e;
  Vec3 w{};
  double R[3] = { 0, 0, 0 }, res = 0.0;
  auto evaluate = [&](double uu, double vv, double tt) {
    patch = FindPatchFast(m, data, face, uu, vv);
    e = EvaluatePatch(m.Patches[patch], uu, vv);
    w = Sub(e.P, Axpy(O, tt, d));
    R[0] = Dot(e.Du, w);
    R[1] = Dot(e.Dv, w);
    R[2] = tt - delta - std::sqrt(Dot(w, w)); // eq. 4 with the clearance
    res = Residual3(e, R);
  };
  evaluate(u, v, t);
  for (int it = 0; it < opt.MaxIterations; ++it)
  {
    ++iterations;
    const double L = std::sqrt(Dot(w, w));
    if (L <= 0.0 || res < 1e-2 * stepTol)
    {
      out.Capped = false;
      break;
    }
    // Exact Jacobian of eq. 4 (the paper drops the second-derivative terms; with them Newton
    // converges quadratically on fillets and thick curved walls, see docs/Solver.md).
    const double J[3][3] = { { Dot(e.Du, e.Du) + Dot(e.Duu, w), Dot(e.Du, e.Dv) + Dot(e.Duv, w), -Dot(e.Du, d) },
      { Dot(e.Dv, e.Du) + Dot(e.Duv, w), Dot(e.Dv, e.Dv) + Dot(e.Dvv, w), -Dot(e.Dv, d) },
      { -Dot(w, e.Du) / L, -Dot(w, e.Dv) / L, 1.0 + Dot(w, d) / L } };
    const double mr[3] = { -R[0], -R[1], -R[2] };
    double x[3];
    if (!Solve3(J, mr, x) && !Damped3(J, mr, x))
    {
      out.Singular = true;
      out.Capped = false;
      break;
    }
    // Trust region: a step moves the foot point by at most max(2t, 1e-2 of the model) ...
    const Vec3 du = { x[0] * e.Du[0] + x[1] * e.Dv[0], x[0] * e.Du[1] + x[1] * e.Dv[1],
      x[0] * e.Du[2] + x[1] * e.Dv[2] };
    const double move = std::sqrt(Dot(du, du));
    const double limit = std::max(2.0 * std::fabs(t), 1e-2 * data.Scale);
    double f = 1.0;
    if (move > limit)
      f = limit / move;
    if (std::fabs(x[2]) * f > limit)
      f = limit / std::fabs(x[2]);
    // ... and is halved while it does not reduce |R| (at most 6 times).
    const double u0 = u, v0 = v, t0 = t, res0 = res;
    for (int k = 0; k <= 6; ++k, f *= 0.5)
    {
      // Across a seam of a closed face the parameter wraps; elsewhere it stops at the domain.
      const double un = Wrap(u0 + f * x[0], F.Domain[0], F.Period[0]);
      const double vn = Wrap(v0 + f * x[1], F.Domain[2], F.Period[1]);
      u = std::clamp(un, F.Domain[0], F.Domain[1]);
      v = std::clamp(vn, F.Domain[2], F.Domain[3]);
      clamped = u != un || v != vn;
      t = t0 + f * x[2];
      evaluate(u, v, t);
      if (res < res0)
        break;
    }
    if (move + std::fabs(x[2]) < stepTol && !clamped && res <= opt.NewtonTolerance)
    {
      out.Capped = false; // the full Newton step is negligible: converged
      break;
    }
  }
  out.U = u;
  out.V = v;
  out.T = t;
  out.Res = res;
  out.Patch = patch;
  out.Foot = e.P;
  out.Clamped = clamped;
  out.Trim = ClassifyPoint(m, face, u, v);
  const Vec3 n{ e.Du[1] * e.Dv[2] - e.Du[2] * e.Dv[1], e.Du[2] * e.Dv[0] - e.Du[0] * e.Dv[2],
    e.Du[0] * e.Dv[1] - e.Du[1] * e.Dv[0] }; // outward up to the face's orientation
  const double ln = std::sqrt(Dot(n, n));
  const double side = -Dot(w, n) / ln * (F.Reversed ? -1.0 : 1.0); // (M - P) . n_out
  out.Side = side;
  out.Normal = n;
  return out;
}

/// (u, v) on `face` of the point at edge parameter T of `edge`, from that face's trimming
/// segments on the edge, with the unit direction (nu, nv) in (u, v) that points from the edge
/// into the face (the face lies on the left of its trimming loops; 0 where the segment's
/// tangent vanishes); false if the face has no segment covering T.
bool EdgePointIntoFace(const BRepModel& m, int face, int edge, double T, double& u, double& v,
  double& nu, double& nv)
{
  const Face& F = m.Faces[face];
  for (int l = F.FirstLoop; l < F.FirstLoop + F.LoopCount; ++l)
  {
    const TrimLoop& loop = m.Loops[l];
    for (int s = loop.FirstSegment; s < loop.FirstSegment + loop.SegmentCount; ++s)
    {
      const TrimSegment& ts = m.TrimSegments[s];
      const double lo = std::min(ts.T0, ts.T1), hi = std::max(ts.T0, ts.T1);
      if (ts.Edge != edge || T < lo || T > hi || hi <= lo)
        continue;
      const auto e = EvaluateCubic<2>(ts.ControlPoints.data(), (T - ts.T0) / (ts.T1 - ts.T0));
      const double len = std::hypot(e.D1[0], e.D1[1]);
      u = e.P[0];
      v = e.P[1];
      nu = len > 0.0 ? -e.D1[1] / len : 0.0;
      nv = len > 0.0 ? e.D1[0] / len : 0.0;
      return true;
    }
  }
  return false;
}

bool EdgePointOnFace(const BRepModel& m, int face, int edge, double T, double& u, double& v)
{
  double nu = 0.0, nv = 0.0;
  return EdgePointIntoFace(m, face, edge, T, u, v, nu, nv);
}

/// s1 along the edges, `spacing` apart (by each cubic segment's control polygon), on the first
/// face of each edge. A convex edge can cut into a sphere over a cap narrower than the spacing of
/// the patch grid, between its points (a 0.36 mm sphere on the FRAMEWORK tile 0.009 mm into the
/// corner of a wall, over 0.16 mm of the edge): the verification then passed a sphere that is
/// not maximal. Edge points are what such a corner exposes first.
void AddEdgePoints(const BRepModel& m, double spacing, std::vector<S1Point>& s1)
{
  for (int edge = 0; edge < static_cast<int>(m.Edges.size()); ++edge)
  {
    const Edge& E = m.Edges[edge];
    const int face = E.Faces[0];
    if (face < 0 || m.Faces[face].PatchCount == 0)
      continue;
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
        if (!EdgePointOnFace(m, face, edge, T, u, v))
          continue;
        s1.push_back({ EvaluateEdge(m, edge, T).C, face, true, u, v });
      }
    }
  }
}

/// T within 1e-9 of the edge's parameter range of one of its ends: an edge contact there is
/// the vertex's (Newton may converge onto the end without stepping past it; the host polish
/// lands 1e-13 short of it from a float T).
bool AtEdgeEnd(const Edge& E, double T)
{
  const double near = 1e-9 * std::fabs(E.T1 - E.T0);
  return std::fabs(T - E.T0) <= near || std::fabs(T - E.T1) <= near;
}

/// A surface/edge contact on a tangent-continuous edge (a round meeting its tangent plane) is a
/// tangent contact with the faces on both sides: the sphere's normal at the foot, (C - M) / |C - M|,
/// is their normal there. Which of the two types Newton, the descent or float rounding reports
/// there is an accident; such contacts are reported as surface/surface on the first face whose
/// normal at the foot is within 1e-3 rad of the sphere's. Likewise a surface/vertex contact at a
/// vertex where the faces meet tangentially (a corner blend; with the clearance, the contact of
/// a sphere touching a whole arc lies at the arc's far end, often such a vertex). Where that
/// face continues O's tangent plane at a foot next to O (TangentAtSample) the contact is the
/// trivial solution and fails (a float solve reported 2t = 0.515 for 0.58 on the ExpansionCard
/// from an edge 1.98e-4 mm from O).
void TypeTangentEdgeContact(const BRepModel& m, const SolverData& data, const Sample& s,
  double T, SampleResult& r)
{
  if ((r.Type != ContactType::SurfaceEdge && r.Type != ContactType::SurfaceVertex) ||
    r.OppositeEdge < 0)
    return;
  const Vec3 M = Axpy(s.Point, r.Radius, s.Direction);
  const Vec3 q = Sub(r.Foot, M);
  const double lq = std::sqrt(Dot(q, q));
  const Edge& E = m.Edges[r.OppositeEdge];
  for (int k = 0; k < 2 && lq > 0.0; ++k)
  {
    const int f = E.Faces[k];
    if (f < 0 || m.Faces[f].PatchCount == 0)
      continue;
    double u = 0.0, v = 0.0;
    if (!EdgePointOnFace(m, f, r.OppositeEdge, T, u, v))
      continue;
    const int patch = FindPatchFast(m, data, f, u, v);
    const PatchEval e = EvaluatePatch(m.Patches[patch], u, v);
    const Vec3 n{ e.Du[1] * e.Dv[2] - e.Du[2] * e.Dv[1], e.Du[2] * e.Dv[0] - e.Du[0] * e.Dv[2],
      e.Du[0] * e.Dv[1] - e.Du[1] * e.Dv[0] };
    const double ln = std::sqrt(Dot(n, n));
    if (!(ln > 0.0))
      continue;
    const Vec3 c{ n[1] * q[2] - n[2] * q[1], n[2] * q[0] - n[0] * q[2], n[0] * q[1] - n[1] * q[0] };
    if (std::sqrt(Dot(c, c)) <= 1e-3 * ln * lq)
    {
      if (TangentAtSample(m, s, r.Foot, n))
      {
        // That face continues O's tangent plane at a foot next to O: the trivial solution.
        r.Type = ContactType::Failed;
        r.Reason = FailReason::LeftModel;
        return;
      }
      r.Type = ContactType::SurfaceSurface;
      r.OppositeFace = f;
      r.OppositePatch = patch;
      r.OppositeEdge = -1;
      r.FootParameter = { u, v };
      return;
    }
  }
}

/// The surface/surface contact of a surface Newton's result on `face`.
SampleResult SurfaceContact(const Sample& s, int face, const SurfaceSolve& ss)
{
  SampleResult r;
  r.Type = ContactType::SurfaceSurface;
  r.OppositeFace = face;
  r.OppositePatch = ss.Patch;
  r.Residual = ss.Res;
  r.Radius = ss.T;
  r.Thickness = 2.0 * ss.T;
  r.Center = Axpy(s.Point, ss.T, s.Direction);
  r.Foot = ss.Foot;
  r.FootParameter = { ss.U, ss.V };
  return r;
}

/// A surface Newton's result is a valid contact: converged on the face, positive and below the
/// model's size, touching the face from inside, and no osculating contact near O.
bool ValidSurfaceSolve(const BRepModel& m, const SolverData& data, const SolverOptions& opt,
  const Sample& s, int face, const SurfaceSolve& ss)
{
  return !ss.Singular && ss.T > 0.0 && ss.T < data.Scale && ss.Converged(opt) &&
    FromInside(m, opt, s, face, ss.Side) &&
    !ShallowOwnFaceContact(m, s, face, ss.Foot, ss.T) &&
    !TangentAtSample(m, s, ss.Foot, ss.Normal) && ss.OnFace(m.Faces[face], opt);
}

/// Steps 4-7 from (u1, v1) on `face` (an s1 point, or a point the certification found inside
/// the sphere) with the initial radius t.
void SolveFrom(const BRepModel& m, const SolverData& data, const SolverOptions& opt,
  const Sample& s, int face, double u1, double v1, double t, SampleResult& r)
{
  const int iterations = r.Iterations;
  r = SampleResult();
  r.Iterations = iterations;
  const Vec3& O = s.Point;
  const Vec3& d = s.Direction;
  const double delta = Clearance(m, opt);
  auto acceptSurface = [&](int f, const SurfaceSolve& ss) {
    const int its = r.Iterations;
    r = SurfaceContact(s, f, ss);
    r.Iterations = its;
  };
  // --- surface/surface Newton (eq. 4), in the opposite face's (u,v) --------------------------
  const Face& F = m.Faces[face];
  const double stepTol = 1e-13 * data.Scale;
  const SurfaceSolve ss = SurfaceNewton(m, data, opt, O, d, face, u1, v1, t, r.Iterations);
  t = ss.T;
  double res = ss.Res;
  r.OppositeFace = face;
  r.Residual = res;
  if (ss.Singular)
  {
    r.Reason = FailReason::Singular;
    return;
  }
  // No inscribed sphere is larger than the model. (Radii near 0 are right at convex edges.)
  if (!(t > 0.0) || !(t < data.Scale))
  {
    r.Reason = FailReason::LeftModel;
    return;
  }
  // --- trim test (eq. 6 and the corner rule) -------------------------------------------------
  const TrimProjection& proj = ss.Trim;
  if (ss.OnFace(F, opt))
  {
    if (!ss.Converged(opt))
    {
      r.Reason = FailReason::NotConverged;
      return;
    }
    if (!FromInside(m, opt, s, face, ss.Side) ||
      ShallowOwnFaceContact(m, s, face, ss.Foot, ss.T) || TangentAtSample(m, s, ss.Foot, ss.Normal))
    {
      r.Reason = FailReason::LeftModel;
      return;
    }
    acceptSurface(face, ss);
    return;
  }
  // --- surface/edge Newton (eq. 7), started from the projection on the trimming curve ---------
  if (proj.Segment < 0)
  {
    r.Reason = FailReason::NoEdge;
    return;
  }
  const TrimSegment& seg = m.TrimSegments[proj.Segment];
  if (seg.Edge < 0 || m.Edges[seg.Edge].SegmentCount == 0)
  {
    r.Reason = FailReason::NoEdge;
    return;
  }
  const int edge = seg.Edge;
  const Edge& E = m.Edges[edge];
  double T = seg.T0 + proj.Parameter * (seg.T1 - seg.T0);
  const double Tlo = std::min(E.T0, E.T1), Thi = std::max(E.T0, E.T1);
  bool atEnd = false, edgeCapped = true;
  Vec3 C{};
  for (int it = 0; it < opt.MaxEdgeIterations; ++it)
  {
    const EdgeEval ee = EvaluateEdge(m, edge, T);
    C = ee.C;
    const Vec3 we = Sub(C, Axpy(O, t, d));
    const double L = std::sqrt(Dot(we, we));
    const double Re[2] = { Dot(ee.Ct, we), t - delta - L }; // eq. 7 with the clearance
    res = Residual2(ee.Ct, Re);
    ++r.Iterations;
    if (L <= 0.0)
      break;
    const double J00 = Dot(ee.Ct, ee.Ct) + Dot(ee.Ctt, we), J01 = -Dot(ee.Ct, d);
    const double J10 = -Dot(we, ee.Ct) / L, J11 = 1.0 + Dot(we, d) / L;
    const double det = J00 * J11 - J01 * J10;
    if (std::fabs(det) < 1e-300)
    {
      r.Reason = FailReason::Singular;
      return;
    }
    const double dT = (-Re[0] * J11 + Re[1] * J01) / det;
    const double dt = (-Re[1] * J00 + Re[0] * J10) / det;
    const double speed = std::sqrt(Dot(ee.Ct, ee.Ct));
    const double limit = std::max(2.0 * std::fabs(t), 1e-2 * data.Scale);
    double f = 1.0;
    if (std::fabs(dT) * speed > limit)
      f = limit / (std::fabs(dT) * speed);
    if (std::fabs(dt) * f > limit)
      f = limit / std::fabs(dt);
    T += f * dT;
    t += f * dt;
    const double Tc = std::clamp(T, Tlo, Thi);
    if (Tc != T)
    {
      // Ran into an end of the edge: the sphere touches that vertex (eq. 1 is exact for it).
      T = Tc;
      C = EvaluateEdge(m, edge, T).C;
      t = SphereRadius(O, d, C, delta);
      if (!std::isfinite(t))
      {
        r.Reason = FailReason::LeftModel;
        return;
      }
      const Vec3 w2 = Sub(C, Axpy(O, t, d));
      res = std::fabs(t - delta - std::sqrt(Dot(w2, w2)));
      atEnd = true;
      edgeCapped = false;
      break;
    }
    if (std::fabs(dT) * speed + std::fabs(dt) < stepTol && res <= opt.NewtonTolerance)
    {
      const EdgeEval e2 = EvaluateEdge(m, edge, T);
      C = e2.C;
      const Vec3 w2 = Sub(C, Axpy(O, t, d));
      const double R2[2] = { Dot(e2.Ct, w2), t - delta - std::sqrt(Dot(w2, w2)) };
      res = Residual2(e2.Ct, R2);
      edgeCapped = false;
      break;
    }
  }
  r.OppositeEdge = edge;
  r.Residual = res;
  const bool edgeValid = t > 0.0 && t < data.Scale;
  const bool edgeConverged =
    res <= opt.NewtonTolerance && (!edgeCapped || res <= 1e-2 * opt.NewtonTolerance);
  // --- the face across that edge ----------------------------------------------------------------
  // Where the edge is tangent-continuous (a fillet meeting a plane), the true sphere touches the
  // neighbouring face rather than the edge, and eq. 7 overestimates it. Continue the surface
  // Newton on the neighbour from the edge point and keep its sphere when it is valid and no
  // larger (or when the edge Newton failed).
  const int nb = E.Faces[0] == face ? E.Faces[1] : E.Faces[0];
  double un = 0.0, vn = 0.0;
  if (nb >= 0 && nb != face && m.Faces[nb].PatchCount > 0 && EdgePointOnFace(m, nb, edge, T, un, vn))
  {
    const SurfaceSolve sn = SurfaceNewton(m, data, opt, O, d, nb, un, vn,
      edgeValid ? t : ss.T, r.Iterations);
    if (ValidSurfaceSolve(m, data, opt, s, nb, sn) &&
      (!(edgeValid && edgeConverged) || sn.T <= t * (1.0 + 1e-12)))
    {
      acceptSurface(nb, sn);
      return;
    }
  }
  // No inscribed sphere is larger than the model. (Radii near 0 are right at convex edges.)
  if (!edgeValid)
  {
    r.Reason = FailReason::LeftModel;
    return;
  }
  if (!edgeConverged)
  {
    r.Reason = FailReason::EdgeNotConverged;
    return;
  }
  if (EdgeAtSample(m, s, edge, C))
  {
    r.Reason = FailReason::LeftModel; // the trivial solution C = O
    return;
  }
  r.Type = atEnd || AtEdgeEnd(E, T) ? ContactType::SurfaceVertex : ContactType::SurfaceEdge;
  r.Radius = t;
  r.Thickness = 2.0 * t;
  r.Center = Axpy(O, t, d);
  r.Foot = C;
  r.FootParameter = { T, 0.0 };
  TypeTangentEdgeContact(m, data, s, T, r);
}
/// The reported sphere: eq. 1's t(P) at the foot point P the clearance selected (Clearance).
void ReportRadius(const Sample& s, SampleResult& r)
{
  if (r.Type == ContactType::Failed)
    return;
  r.Radius = SphereRadius(s.Point, s.Direction, r.Foot, 0.0);
  r.Thickness = 2.0 * r.Radius;
  r.Center = Axpy(s.Point, r.Radius, s.Direction);
}

/// One face's part of Descend: minimises t(u, v) over the trimmed `face` from (u, v) by Newton
/// steps on grad t, made positive definite with the first fundamental form where the Hessian is
/// not, with a backtracking line search that only accepts a smaller t (or, once t no longer
/// changes beyond rounding, a smaller tangential residual). Returns the last point; `crossing`
/// is the trimming segment the last step wanted to cross (-1: a minimum inside the face).
struct DescentPoint
{
  double U = 0.0, V = 0.0, T = 0.0;
  PatchEval E;
  int Patch = -1;
};
DescentPoint DescendOnFace(const BRepModel& m, const SolverData& data, const SolverOptions& opt,
  const Sample& s, int face, double u, double v, int& crossing, int& iterations)
{
  const Vec3& O = s.Point;
  const Vec3& d = s.Direction;
  const Face& F = m.Faces[face];
  const double tiny = 1e-14 * data.Scale;
  const double roundoff = 8.0 * std::numeric_limits<double>::epsilon();
  const double delta = Clearance(m, opt);
  auto evaluate = [&](double uu, double vv, DescentPoint& st) {
    st.U = uu;
    st.V = vv;
    st.Patch = FindPatchFast(m, data, face, uu, vv);
    st.E = EvaluatePatch(m.Patches[st.Patch], uu, vv);
    st.T = SphereRadius(O, d, st.E.P, delta);
  };
  // Tangential part of eq. 4's residual, as a distance: zero where t(u, v) is stationary.
  auto tangential = [&](const DescentPoint& st) {
    const Vec3 w = Sub(st.E.P, Axpy(O, st.T, d));
    const double lu = std::sqrt(Dot(st.E.Du, st.E.Du)), lv = std::sqrt(Dot(st.E.Dv, st.E.Dv));
    const double a = lu > 0.0 ? Dot(w, st.E.Du) / lu : 0.0, b = lv > 0.0 ? Dot(w, st.E.Dv) / lv : 0.0;
    return std::sqrt(a * a + b * b);
  };
  DescentPoint cur;
  evaluate(u, v, cur);
  crossing = -1;
  if (!std::isfinite(cur.T))
    return cur;
  for (int it = 0; it < 4 * opt.MaxIterations; ++it)
  {
    ++iterations;
    const PatchEval& e = cur.E;
    const Vec3 w0 = Sub(e.P, O);
    // grad t_delta = (S - M).S_u / (d.(S - O) - delta); the Hessian below likewise.
    const double b = Dot(d, w0) - delta, t = cur.T;
    const Vec3 w = Sub(e.P, Axpy(O, t, d)); // S - M
    const double g[2] = { Dot(w, e.Du) / b, Dot(w, e.Dv) / b };
    const double du_d = Dot(d, e.Du), dv_d = Dot(d, e.Dv);
    double H[2][2] = {
      { (Dot(e.Du, e.Du) - 2.0 * g[0] * du_d + Dot(w, e.Duu)) / b,
        (Dot(e.Du, e.Dv) - g[1] * du_d - g[0] * dv_d + Dot(w, e.Duv)) / b },
      { 0.0, (Dot(e.Dv, e.Dv) - 2.0 * g[1] * dv_d + Dot(w, e.Dvv)) / b } };
    H[1][0] = H[0][1];
    const double G[2][2] = { { Dot(e.Du, e.Du) / b, Dot(e.Du, e.Dv) / b },
      { Dot(e.Du, e.Dv) / b, Dot(e.Dv, e.Dv) / b } };
    // Levenberg-Marquardt: H + lambda G, lambda raised until positive definite.
    double step[2] = { 0.0, 0.0 };
    for (double lambda = 0.0; lambda < 1e12; lambda = lambda == 0.0 ? 1e-3 : 10.0 * lambda)
    {
      const double a00 = H[0][0] + lambda * G[0][0], a01 = H[0][1] + lambda * G[0][1],
                   a11 = H[1][1] + lambda * G[1][1];
      const double det = a00 * a11 - a01 * a01;
      if (a00 > 0.0 && det > 0.0)
      {
        step[0] = -(a11 * g[0] - a01 * g[1]) / det;
        step[1] = -(a00 * g[1] - a01 * g[0]) / det;
        break;
      }
    }
    const Vec3 move3 = { step[0] * e.Du[0] + step[1] * e.Dv[0],
      step[0] * e.Du[1] + step[1] * e.Dv[1], step[0] * e.Du[2] + step[1] * e.Dv[2] };
    const double len = std::sqrt(Dot(move3, move3));
    const double limit = std::max(t, 1e-3 * data.Scale);
    double f = len > limit ? limit / len : 1.0;
    const double slope = g[0] * step[0] + g[1] * step[1]; // < 0
    crossing = -1;
    if (len * f < tiny || !(slope < 0.0))
      break; // stationary: a minimum of t on the face
    const double res0 = tangential(cur);
    bool accepted = false;
    for (int k = 0; k < 40; ++k, f *= 0.5)
    {
      const double un = Wrap(cur.U + f * step[0], F.Domain[0], F.Period[0]);
      const double vn = Wrap(cur.V + f * step[1], F.Domain[2], F.Period[1]);
      const double uc = std::clamp(un, F.Domain[0], F.Domain[1]);
      const double vc = std::clamp(vn, F.Domain[2], F.Domain[3]);
      const TrimProjection tp = ClassifyPoint(m, face, uc, vc);
      if (!(tp.Inside || tp.Distance <= F.UVTolerance) || uc != un || vc != vn)
      {
        if (crossing < 0)
          crossing = tp.Segment; // the first (longest) step that left the face
        continue;
      }
      DescentPoint next;
      evaluate(uc, vc, next);
      if (next.T <= t + 1e-4 * f * slope ||
        (next.T <= t + roundoff * t && tangential(next) < res0))
      {
        cur = next;
        accepted = true;
        break;
      }
    }
    // No step length decreases t: along the edge a longer step crossed (crossing >= 0), or at
    // the minimum within rounding. A step cut to nothing because longer ones left the face: the
    // minimum is on that edge.
    if (!accepted || len * f < tiny)
      break;
  }
  return cur;
}

/// The minimum of t_delta(C(T)) along `edge` from T: Newton on t'(T) where t(T) is convex,
/// elsewhere the longest step downhill, cut back by a line search (where a sphere touches a whole
/// arc, t is flat and concave along it: metric-scaled gradient steps crawled and ran out of
/// iterations); it stops at the edge's ends.
struct EdgeMinimum
{
  double T = 0.0, t = 0.0;
  EdgeEval E;
  bool AtEnd = false;
};
EdgeMinimum MinimiseOnEdge(const BRepModel& m, const SolverData& data, const SolverOptions& opt,
  const Sample& s, int edge, double T, int& iterations)
{
  const Vec3& O = s.Point;
  const Vec3& d = s.Direction;
  const double tiny = 1e-14 * data.Scale;
  const double roundoff = 8.0 * std::numeric_limits<double>::epsilon();
  const double delta = Clearance(m, opt);
  const Edge& E = m.Edges[edge];
  const double Tlo = std::min(E.T0, E.T1), Thi = std::max(E.T0, E.T1);
  T = std::clamp(T, Tlo, Thi);
  EdgeEval ee = EvaluateEdge(m, edge, T);
  double t = SphereRadius(O, d, ee.C, delta);
  bool atEnd = T == Tlo || T == Thi; // (a start at an end that no step leaves is that vertex)
  for (int it = 0; it < 2 * opt.MaxEdgeIterations && std::isfinite(t); ++it)
  {
    ++iterations;
    const double b = Dot(d, Sub(ee.C, O)) - delta;
    const Vec3 w = Sub(ee.C, Axpy(O, t, d));
    const double g = Dot(w, ee.Ct) / b;
    const double dCt = Dot(d, ee.Ct);
    const double h = (Dot(ee.Ct, ee.Ct) - 2.0 * g * dCt + Dot(w, ee.Ctt)) / b;
    const double speed = std::sqrt(Dot(ee.Ct, ee.Ct));
    const double limit = std::max(t, 1e-3 * data.Scale);
    double dT = h > 0.0 ? -g / h : (g > 0.0 ? -1.0 : 1.0) * limit / std::max(speed, 1e-300);
    if (std::fabs(dT) * speed > limit)
      dT *= limit / (std::fabs(dT) * speed);
    if (std::fabs(dT) * speed < tiny)
      break;
    const double res0 = speed > 0.0 ? std::fabs(Dot(w, ee.Ct)) / speed : 0.0;
    bool accepted = false;
    for (int k = 0; k < 40; ++k, dT *= 0.5)
    {
      const double Tn = std::clamp(T + dT, Tlo, Thi);
      const EdgeEval en = EvaluateEdge(m, edge, Tn);
      const double tn = SphereRadius(O, d, en.C, delta);
      const double sn = std::sqrt(Dot(en.Ct, en.Ct));
      const double resn =
        sn > 0.0 ? std::fabs(Dot(Sub(en.C, Axpy(O, tn, d)), en.Ct)) / sn : 0.0;
      if (tn <= t + 1e-4 * g * (Tn - T) || (tn <= t + roundoff * t && resn < res0))
      {
        atEnd = Tn == Tlo || Tn == Thi;
        accepted = T != Tn;
        T = Tn;
        ee = en;
        t = tn;
        break;
      }
    }
    if (!accepted)
      break;
  }
  EdgeMinimum em;
  em.T = T;
  em.t = t;
  em.E = ee;
  em.AtEnd = atEnd;
  return em;
}

/// The contact at an edge minimum on `face`'s edge: surface/edge, or surface/vertex at an end of
/// the edge (typed surface/surface where the faces meet tangentially); failed where t is not
/// positive or the residual of eq. 7 is above the tolerance.
SampleResult EdgeContact(const BRepModel& m, const SolverData& data, const SolverOptions& opt,
  const Sample& s, int face, int edge, const EdgeMinimum& em)
{
  const Vec3& O = s.Point;
  const Vec3& d = s.Direction;
  const double t = em.t;
  SampleResult r;
  const Vec3 w = Sub(em.E.C, Axpy(O, t, d));
  const double Re[2] = { Dot(em.E.Ct, w), t - Clearance(m, opt) - std::sqrt(Dot(w, w)) };
  r.Residual = em.AtEnd ? std::fabs(Re[1]) : Residual2(em.E.Ct, Re);
  if (!(t > 0.0) || !std::isfinite(t) || EdgeAtSample(m, s, edge, em.E.C))
    r.Reason = FailReason::LeftModel; // (or the trivial solution C = O)
  else if (!(r.Residual <= opt.NewtonTolerance))
    r.Reason = FailReason::EdgeNotConverged;
  if (r.Reason != FailReason::None)
    return r;
  r.Type = em.AtEnd || AtEdgeEnd(m.Edges[edge], em.T) ? ContactType::SurfaceVertex
                                                       : ContactType::SurfaceEdge;
  r.OppositeFace = face;
  r.OppositeEdge = edge;
  r.Radius = t;
  r.Thickness = 2.0 * t;
  r.Center = Axpy(O, t, d);
  r.Foot = em.E.C;
  r.FootParameter = { em.T, 0.0 };
  TypeTangentEdgeContact(m, data, s, em.T, r);
  return r;
}

/// The fallback of SolveOne for the hard samples: a descent on t instead of a Newton on eq. 4.
/// Every stationary point of t(P) over a face is a tangent sphere (grad t = (S-M).S_u / d.(S-O)),
/// but Newton finds any of them, maxima and saddles too, and may leave the face on the way; the
/// smallest sphere is the minimum of t over the boundary. This minimises t over the trimmed face
/// from (u, v) (DescendOnFace). Where the minimum lies on the face's boundary it goes on along
/// the nearest edge (minimising t(T) over the edge, stopping at its ends: surface/edge and
/// surface/vertex contacts), and from the edge's minimum into the face across it (a fillet's
/// tangent plane, a corner's other wall), up to 4 faces. Since t only decreases, it cannot climb
/// back to the sphere it started below.
SampleResult Descend(const BRepModel& m, const SolverData& data, const SolverOptions& opt,
  const Sample& s, int face, double u, double v, int& iterations)
{
  const Vec3& O = s.Point;
  const Vec3& d = s.Direction;
  const double delta = Clearance(m, opt);
  SampleResult best; // the best edge contact so far
  for (int hop = 0; hop < 4; ++hop)
  {
    int crossing = -1;
    const DescentPoint cur = DescendOnFace(m, data, opt, s, face, u, v, crossing, iterations);
    // On the face: a minimum of t in its interior, if the last step did not want to leave it.
    bool faceOk = false; // the face point itself is a tangent sphere
    auto onFace = [&]() {
      SampleResult r;
      const PatchEval& e = cur.E;
      if (!std::isfinite(cur.T))
        return best; // no sphere on this face: the last edge contact, if any
      const Vec3 w = Sub(e.P, Axpy(O, cur.T, d));
      const double R[3] = { Dot(e.Du, w), Dot(e.Dv, w), cur.T - delta - std::sqrt(Dot(w, w)) };
      const Vec3 n{ e.Du[1] * e.Dv[2] - e.Du[2] * e.Dv[1], e.Du[2] * e.Dv[0] - e.Du[0] * e.Dv[2],
        e.Du[0] * e.Dv[1] - e.Du[1] * e.Dv[0] };
      r.Residual = Residual3(e, R);
      if (!FromInside(m, opt, s, face,
            -Dot(w, n) / std::sqrt(Dot(n, n)) * (m.Faces[face].Reversed ? -1.0 : 1.0)))
        r.Reason = FailReason::LeftModel; // touches the face from outside
      else if (AtSample(m, s, face, e.P) || TangentAtSample(m, s, e.P, n))
        r.Reason = FailReason::LeftModel; // the trivial solution P = O
      else if (!(r.Residual <= opt.NewtonTolerance) || !(cur.T > 0.0) || !(cur.T < data.Scale))
        r.Reason = FailReason::NotConverged;
      else
      {
        r.Type = ContactType::SurfaceSurface;
        r.OppositeFace = face;
        r.OppositePatch = cur.Patch;
        r.Radius = cur.T;
        r.Thickness = 2.0 * cur.T;
        r.Center = Axpy(O, cur.T, d);
        r.Foot = e.P;
        r.FootParameter = { cur.U, cur.V };
      }
      faceOk = r.Type != ContactType::Failed;
      // Coming from an edge, the face result counts only where it is valid and smaller.
      if (best.Type != ContactType::Failed &&
        (r.Type == ContactType::Failed || !(r.Radius < best.Radius)))
        return best;
      return r;
    };
    if (crossing < 0)
      return onFace();
    // The edge: the trimming segment nearest the last point (the step that crossed may have
    // been long), else the crossed one.
    const TrimProjection near = ClassifyPoint(m, face, cur.U, cur.V);
    int segment = crossing;
    double at = 0.0;
    if (near.Segment >= 0 && m.TrimSegments[near.Segment].Edge >= 0)
    {
      segment = near.Segment;
      at = near.Parameter;
    }
    else
    {
      double dist = 0.0;
      at = ProjectOnSegment(m.TrimSegments[crossing].ControlPoints, cur.U, cur.V, &dist);
    }
    const TrimSegment& seg = m.TrimSegments[segment];
    if (seg.Edge < 0 || m.Edges[seg.Edge].SegmentCount == 0)
      return onFace(); // a pole: stay at the best point of the face
    // Along the edge: minimise t(T) = t(C(T)).
    const int edge = seg.Edge;
    const Edge& E = m.Edges[edge];
    const EdgeMinimum em =
      MinimiseOnEdge(m, data, opt, s, edge, seg.T0 + at * (seg.T1 - seg.T0), iterations);
    const double t = em.t;
    // Keep the face point (or the last edge contact) where it is lower. Where the face point
    // is no tangent sphere (t still falls across the boundary: a round's tangent edge), the
    // edge goes on even at the same t.
    const SampleResult faceResult = onFace();
    if (!(t < (best.Type == ContactType::Failed ? data.Scale : best.Radius)) ||
      (faceOk && !(t < cur.T)))
      return faceResult;
    const SampleResult r = EdgeContact(m, data, opt, s, face, edge, em);
    if (r.Type == ContactType::Failed)
      return best.Type != ContactType::Failed ? best : r;
    best = r;
    // Across the edge: the neighbour face may go lower still (a round's tangent plane).
    const int nb = E.Faces[0] == face ? E.Faces[1] : E.Faces[0];
    double un = 0.0, vn = 0.0, nu = 0.0, nv = 0.0;
    if (em.AtEnd || nb < 0 || nb == face || m.Faces[nb].PatchCount == 0 ||
      !EdgePointIntoFace(m, nb, edge, em.T, un, vn, nu, nv))
      return best;
    // Only where t falls into that face: grad t . (into the face) < 0.
    const PatchEval en = EvaluatePatch(m.Patches[FindPatchFast(m, data, nb, un, vn)], un, vn);
    const Vec3 wn = Sub(en.P, Axpy(O, t, d));
    if (!(Dot(wn, en.Du) * nu + Dot(wn, en.Dv) * nv < 0.0))
      return best;
    face = nb;
    u = un;
    v = vn;
  }
  return best;
}

/// Descend on the face across the edge nearest the sample O (`near`: O's projection on its trim,
/// from ClassifyPoint), from near that edge's point nearest O: a sample next to a convex edge has
/// a sphere of about its distance from the edge, closer to O than any s1 point. On the edge itself
/// t is undefined (the point lies in O's tangent plane), so the start is moved into the neighbour
/// face, by the offset (1e-6 to 1e-1 of its UV diagonal) that gives the smallest t.
SampleResult DescendAcrossNearestEdge(const BRepModel& m, const SolverData& data,
  const SolverOptions& opt, const Sample& s, const TrimProjection& near, int& iterations)
{
  if (near.Segment < 0 || m.TrimSegments[near.Segment].Edge < 0)
    return SampleResult();
  const TrimSegment& seg = m.TrimSegments[near.Segment];
  const int edge = seg.Edge;
  const Edge& E = m.Edges[edge];
  const int nb = E.Faces[0] == s.Face ? E.Faces[1] : E.Faces[0];
  if (nb < 0 || nb == s.Face || m.Faces[nb].PatchCount == 0)
    return SampleResult();
  const Face& N = m.Faces[nb];
  double u0 = 0.0, v0 = 0.0, nu = 0.0, nv = 0.0;
  if (!EdgePointIntoFace(m, nb, edge, seg.T0 + near.Parameter * (seg.T1 - seg.T0), u0, v0, nu, nv))
    return SampleResult();
  const double diag = std::hypot(N.Domain[1] - N.Domain[0], N.Domain[3] - N.Domain[2]);
  double bestT = std::numeric_limits<double>::infinity(), bu = 0.0, bv = 0.0;
  for (double h = 1e-6; h < 0.2; h *= 10.0)
  {
    const double u = std::clamp(u0 + h * diag * nu, N.Domain[0], N.Domain[1]);
    const double v = std::clamp(v0 + h * diag * nv, N.Domain[2], N.Domain[3]);
    if (!ClassifyPoint(m, nb, u, v).Inside)
      continue;
    const double t = SphereRadius(s.Point, s.Direction,
      EvaluatePatch(m.Patches[FindPatchFast(m, data, nb, u, v)], u, v).P, Clearance(m, opt));
    if (t < bestT)
    {
      bestT = t;
      bu = u;
      bv = v;
    }
  }
  if (!std::isfinite(bestT))
    return SampleResult();
  return Descend(m, data, opt, s, nb, bu, bv, iterations);
}

/// The edges and faces at the vertex at end `end` (0: T0, 1: T1) of `edge`, from a contact of
/// radius t at or next to it: the minimum along each edge from the vertex (`edge`'s reported on
/// `faceOfEdge`) and the surface Newton on each face from it (but `skipFace`), each passed to
/// `consider`. A sphere touching a vertex can touch a face or an edge meeting there a little
/// lower a few 1e-3 mm away (the NIST part's 1.5 mm round meets its end faces at vertices: the
/// reference reported the vertex, 2t = 3.00011617, the double kernel the face next to it
/// 1.8e-3 mm away, 3.00011465), and the vertex's own edge may have its minimum just before the
/// end, which eq. 7's Newton steps past (FRAMEWORK: 8e-4 mm before it, 1.2e-6 lower in t). Each
/// face is tried once.
template <class Consider>
void AroundVertex(const BRepModel& m, const SolverData& data, const SolverOptions& opt,
  const Sample& s, int faceOfEdge, int edge, int end, int skipFace, double t, int& iterations,
  Consider&& consider)
{
  const int record = data.VertexInfo.empty() ? -1 : data.VertexInfo[2 * edge + end];
  if (record < 0)
    return;
  int tried[8] = { skipFace, -1, -1, -1, -1, -1, -1, -1 };
  int triedCount = 1;
  for (int i = 1; i <= data.VertexInfo[record]; ++i)
  {
    const int e = data.VertexInfo[record + i] / 2;
    const Edge& E = m.Edges[e];
    const double Te = data.VertexInfo[record + i] % 2 ? E.T1 : E.T0;
    consider(EdgeContact(m, data, opt, s, e == edge ? faceOfEdge : E.Faces[0], e,
      MinimiseOnEdge(m, data, opt, s, e, Te, iterations)));
    for (int k = 0; k < 2; ++k)
    {
      const int f = E.Faces[k];
      if (f < 0 || m.Faces[f].PatchCount == 0 ||
        std::find(tried, tried + triedCount, f) != tried + triedCount)
        continue;
      if (triedCount < 8)
        tried[triedCount++] = f;
      double u = 0.0, v = 0.0;
      if (!EdgePointOnFace(m, f, e, Te, u, v))
        continue;
      const SurfaceSolve ss = SurfaceNewton(m, data, opt, s.Point, s.Direction, f, u, v, t, iterations);
      if (ValidSurfaceSolve(m, data, opt, s, f, ss))
        consider(SurfaceContact(s, f, ss));
    }
  }
}

void SecondLookNear(const BRepModel& m, const SolverData& data, const SolverOptions& opt,
  const Sample& s, SampleResult& r, int& iterations, const TrimProjection* footTrim = nullptr);

/// The second look at a verified contact r (t_delta in r.Radius): other local minima of t_delta
/// that a path may have missed, where the answer would otherwise depend on rounding.
/// - The other end of an arc: a sphere touching a whole arc (a round of about its radius) has a
///   minimum of t_delta at each far end; the first path reaches one. When the contact lies well
///   off O's normal line (d.(P-O) < 1.2 t), descend again from the best s1 point on the other
///   side of that line.
///   (The s1 verification cannot always tell: a sphere overlapping a side wall by 0.03 mm over a
///   patch narrower than s1's spacing passed it on the ExpansionCard.)
/// - The face across the edge nearest O, where that edge is within t and one s1 spacing of O
///   (farther, s1 covers the wall across): next to a corner the
///   other wall can be nearer than any s1 point (an L-bracket's sample 0.002 from an edge read
///   2t = 0.0147 while the wall across that edge allows 0.0042).
/// - The edge next to the contact: where faces meet at a tangent edge, with steps and kinks at
///   the tolerance's scale, the edge and the faces on both sides each have a minimum a few 1e-4
///   apart. A surface contact within rho (1% of t, at least 20x the conversion tolerance) of its
///   face's boundary also tries the minimum along that edge; an edge contact tries the surface
///   Newton on the faces on both sides from the edge point.
/// Every candidate is a sphere tangent at O smaller than the verified one, hence inside it: no
/// new verification is needed. The smallest wins.
void SecondLook(const BRepModel& m, const SolverData& data, const SolverOptions& opt,
  const Sample& s, const TrimProjection& own, SampleResult& r)
{
  if (r.Type == ContactType::Failed)
    return;
  const Vec3& O = s.Point;
  const Vec3& d = s.Direction;
  const double delta = Clearance(m, opt);
  const double rho = std::max(1e-2 * r.Radius, 20.0 * m.Tolerance);
  int iterations = r.Iterations;
  // Lower by more than rounding: a tie within it keeps the first contact (float rounding otherwise
  // picks an edge contact next to a face contact of the same sphere, e.g. on a torus's seam).
  const double roundoff = std::numeric_limits<double>::epsilon();
  auto consider = [&](const SampleResult& c) {
    if (c.Type != ContactType::Failed && c.Radius < r.Radius * (1.0 - roundoff))
    {
      r = c;
      r.Iterations = iterations;
    }
  };
  const Vec3 w = Sub(r.Foot, O);
  const double a = Dot(d, w);
  const Vec3 wt = Axpy(w, -a, d);
  if (a < 1.2 * r.Radius && Dot(wt, wt) > rho * rho)
  {
    double t = 0.0;
    const int p = Initialise(m, data, s, delta, t, 1.2 * r.Radius, -1, &wt);
    if (p >= 0)
      consider(Descend(m, data, opt, s, data.S1[p].Face, data.S1[p].U, data.S1[p].V, iterations));
  }
  // O within t of its face's boundary, and within one s1 spacing (farther, s1 covers the wall
  // across): the face across the nearest edge may come closer than any s1 point (a sample next
  // to a corner, between two walls).
  if (own.Segment >= 0 && m.TrimSegments[own.Segment].Edge >= 0)
  {
    const TrimSegment& seg = m.TrimSegments[own.Segment];
    const Vec3 toEdge =
      Sub(EvaluateEdge(m, seg.Edge, seg.T0 + own.Parameter * (seg.T1 - seg.T0)).C, O);
    const double reach = std::min(r.Radius, data.S1Spacing);
    if (Dot(toEdge, toEdge) < reach * reach)
      consider(DescendAcrossNearestEdge(m, data, opt, s, own, iterations));
  }
  SecondLookNear(m, data, opt, s, r, iterations);
  r.Iterations = iterations;
}

/// The local part of the second look (SecondLook): from a contact r (t_delta in r.Radius), the
/// minimum along the edge next to a surface contact, the surface Newton on the faces beside an
/// edge contact, and the edges and faces around a vertex contact (AroundVertex). Each is a
/// Newton from the contact itself; the smallest sphere wins. `footTrim`: the trim test of a
/// surface contact's foot where the caller has it (saves classifying it again).
void SecondLookNear(const BRepModel& m, const SolverData& data, const SolverOptions& opt,
  const Sample& s, SampleResult& r, int& iterations, const TrimProjection* footTrim)
{
  if (r.Type == ContactType::Failed)
    return;
  const Vec3& O = s.Point;
  const Vec3& d = s.Direction;
  const double rho = std::max(1e-2 * r.Radius, 20.0 * m.Tolerance);
  const double roundoff = std::numeric_limits<double>::epsilon();
  auto consider = [&](const SampleResult& c) {
    if (c.Type != ContactType::Failed && c.Radius < r.Radius * (1.0 - roundoff))
    {
      r = c;
      r.Iterations = iterations;
    }
  };
  // The vertex at or next to the contact (an end of its edge, or of the edge nearest a surface
  // contact, within rho of the foot): the edges and faces around it, last.
  int vertexEdge = -1, vertexEnd = 0;
  auto nearVertex = [&](int edge, double T, const Vec3& foot) {
    const Edge& E = m.Edges[edge];
    const int end = std::fabs(T - E.T1) < std::fabs(T - E.T0) ? 1 : 0;
    const Vec3 gap = Sub(EvaluateEdge(m, edge, end ? E.T1 : E.T0).C, foot);
    if (Dot(gap, gap) <= rho * rho)
    {
      vertexEdge = edge;
      vertexEnd = end;
    }
  };
  // Next to an edge: its minimum; from an edge contact, the surface Newton on the faces on
  // both sides, from the edge point.
  const SampleResult first = r;
  if (r.Type == ContactType::SurfaceSurface)
  {
    const TrimProjection near = footTrim
      ? *footTrim
      : ClassifyPoint(m, r.OppositeFace, r.FootParameter[0], r.FootParameter[1]);
    if (near.Segment >= 0 && m.TrimSegments[near.Segment].Edge >= 0)
    {
      const TrimSegment& seg = m.TrimSegments[near.Segment];
      const double T = seg.T0 + near.Parameter * (seg.T1 - seg.T0);
      const Vec3 gap = Sub(EvaluateEdge(m, seg.Edge, T).C, r.Foot);
      if (Dot(gap, gap) <= rho * rho)
      {
        nearVertex(seg.Edge, T, r.Foot);
        consider(EdgeContact(m, data, opt, s, r.OppositeFace, seg.Edge,
          MinimiseOnEdge(m, data, opt, s, seg.Edge, T, iterations)));
      }
    }
  }
  if (r.Type != ContactType::SurfaceSurface && r.OppositeEdge >= 0)
  {
    const int edge = r.OppositeEdge;
    const double T = r.FootParameter[0];
    const double t = r.Radius;
    nearVertex(edge, T, r.Foot); // (a vertex contact's own)
    const Edge& E = m.Edges[edge];
    // (From a vertex, AroundVertex starts the same Newtons on these faces.)
    for (int k = 0; k < 2 && r.Type != ContactType::SurfaceVertex; ++k)
    {
      const int f = E.Faces[k];
      double u = 0.0, v = 0.0;
      if (f < 0 || (k == 1 && f == E.Faces[0]) || m.Faces[f].PatchCount == 0 ||
        !EdgePointOnFace(m, f, edge, T, u, v))
        continue;
      const SurfaceSolve ss = SurfaceNewton(m, data, opt, O, d, f, u, v, t, iterations);
      if (ValidSurfaceSolve(m, data, opt, s, f, ss))
        consider(SurfaceContact(s, f, ss));
    }
  }
  if (vertexEdge >= 0)
    AroundVertex(m, data, opt, s, first.OppositeFace, vertexEdge, vertexEnd,
      first.Type == ContactType::SurfaceSurface ? first.OppositeFace : -1, first.Radius,
      iterations, consider);
}

/// A point of the trimmed faces that lies inside a sphere: where to restart from.
struct PointInside
{
  int Face = -1;
  double U = 0.0, V = 0.0;
  double T = 0.0; ///< eq. 1's radius through the point (with the depth as clearance)
};

/// The certification of a sphere against the patches (SolverOptions::Certify): the deepest point
/// of the trimmed faces of O's solid more than `depth` inside the sphere of radius t tangent at
/// O (by more than half the conversion tolerance). Every patch whose control-point box reaches
/// into the sphere is searched: the centre's
/// nearest point on the patch (a 5x5 grid, then Newton on |S - M|^2 in the patch's (s, r),
/// clamped to the patch), kept if it lies inside the face's trim; otherwise the deepest grid
/// point inside the trim. False where no point is that deep: the sphere is empty up to the
/// depth, at the patches' accuracy.
bool FindPointInside(const BRepModel& m, const SolverData& data, const Sample& s, double t,
  double depth, PointInside& out)
{
  const Vec3& O = s.Point;
  const Vec3& d = s.Direction;
  const Vec3 M = Axpy(O, t, d);
  // The contact itself lies `depth` inside (the clearance): a point counts when it lies deeper
  // by more than half the conversion tolerance, above the Newton solves' error at the contact.
  const double reach = t - depth - 0.5 * m.Tolerance;
  if (!(reach > 0.0) || data.PatchBoxes.size() != 6 * m.Patches.size() ||
    data.EdgeBoxes.size() != 6 * m.EdgeSegments.size() || data.BoxNodes.empty())
    return false;
  const int solid = m.Faces[s.Face].Solid;
  double best = reach; // distance of the deepest point so far
  bool found = false;
  // O's own face: the patches there may lie a little more than the tolerance off O's exact
  // point (a toroidal shell converted within 1e-6: 2.75e-6 at O's own patch point, the trivial
  // solution P = O), so its points must lie deeper by twice the tolerance more. Within the
  // patches' accuracy of O (twice the slack), no face counts.
  auto NearSampleOnOwnFace = [&](int face, const Vec3& w, double dist) {
    return (face == s.Face && !(dist < reach - 2.0 * m.Tolerance)) ||
      Dot(w, w) <= 16.0 * m.Tolerance * m.Tolerance;
  };
  auto consider = [&](int face, const BezierPatch& patch, double ls, double lr, const Vec3& P) {
    const double dist = std::sqrt(Dot(Sub(P, M), Sub(P, M)));
    if (!(dist < best))
      return;
    const double u = patch.Domain[0] + ls * (patch.Domain[1] - patch.Domain[0]);
    const double v = patch.Domain[2] + lr * (patch.Domain[3] - patch.Domain[2]);
    // A point far from the loops also passes the crossing test: the nearest-segment test can
    // misjudge a point equidistant from several parts of a loop (seen at a face's UV corner).
    const TrimProjection tp = ClassifyPoint(m, face, u, v);
    if (!tp.Inside || (tp.Distance > 1e-3 * (m.Faces[face].Domain[1] - m.Faces[face].Domain[0] +
                                               m.Faces[face].Domain[3] - m.Faces[face].Domain[2]) &&
                        !InsideByCrossings(m, face, u, v)))
      return;
    const Vec3 w = Sub(P, O);
    const double dn = Dot(d, w);
    if (!(dn > depth) || NearSampleOnOwnFace(face, w, dist))
      return;
    best = dist;
    found = true;
    out.Face = face;
    out.U = u;
    out.V = v;
    out.T = 0.5 * (Dot(w, w) - depth * depth) / (dn - depth);
  };
  // Squared distance from M to a box (min x, y, z, max x, y, z).
  auto boxGap2 = [&](const double* b) {
    double g2 = 0.0;
    for (int k = 0; k < 3; ++k)
    {
      const double g = std::max({ b[k] - M[k], 0.0, M[k] - b[3 + k] });
      g2 += g * g;
    }
    return g2;
  };
  auto checkPatch = [&](size_t p) {
    const BezierPatch& patch = m.Patches[p];
    if (m.Faces[patch.Face].Solid != solid)
      return;
    if (boxGap2(&data.PatchBoxes[6 * p]) >= best * best)
      return;
    // Grid start; grid points inside the trim are candidates themselves.
    double bs = 0.5, br = 0.5, bd = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= 4; ++i)
      for (int j = 0; j <= 4; ++j)
      {
        const double ls = 0.25 * i, lr = 0.25 * j;
        const PatchEval e = EvaluatePatchLocal(patch.ControlPoints, ls, lr);
        const Vec3 P{ e.P[0], e.P[1], e.P[2] };
        const double dd = Dot(Sub(P, M), Sub(P, M));
        if (dd < bd)
        {
          bd = dd;
          bs = ls;
          br = lr;
        }
        if (dd < best * best)
          consider(patch.Face, patch, ls, lr, P);
      }
    // Newton on f = |S - M|^2 / 2 from the nearest grid point.
    double ls = bs, lr = br;
    for (int it = 0; it < 8; ++it)
    {
      const PatchEval e = EvaluatePatchLocal(patch.ControlPoints, ls, lr);
      const Vec3 w{ e.P[0] - M[0], e.P[1] - M[1], e.P[2] - M[2] };
      const Vec3 Su{ e.Du[0], e.Du[1], e.Du[2] }, Sv{ e.Dv[0], e.Dv[1], e.Dv[2] };
      const Vec3 Suu{ e.Duu[0], e.Duu[1], e.Duu[2] }, Suv{ e.Duv[0], e.Duv[1], e.Duv[2] },
        Svv{ e.Dvv[0], e.Dvv[1], e.Dvv[2] };
      const double g0 = Dot(Su, w), g1 = Dot(Sv, w);
      double h00 = Dot(Su, Su) + Dot(Suu, w), h01 = Dot(Su, Sv) + Dot(Suv, w),
             h11 = Dot(Sv, Sv) + Dot(Svv, w);
      double det = h00 * h11 - h01 * h01;
      if (!(h00 > 0.0) || !(det > 0.0))
      {
        // Not convex here: Gauss-Newton.
        h00 = Dot(Su, Su);
        h01 = Dot(Su, Sv);
        h11 = Dot(Sv, Sv);
        det = h00 * h11 - h01 * h01;
        if (!(det > 0.0))
          break;
      }
      const double ds = -(h11 * g0 - h01 * g1) / det, dr = -(h00 * g1 - h01 * g0) / det;
      const double ns = std::clamp(ls + ds, 0.0, 1.0), nr = std::clamp(lr + dr, 0.0, 1.0);
      const bool done = std::fabs(ns - ls) + std::fabs(nr - lr) < 1e-12;
      ls = ns;
      lr = nr;
      if (done)
        break;
    }
    const PatchEval e = EvaluatePatchLocal(patch.ControlPoints, ls, lr);
    consider(patch.Face, patch, ls, lr, Vec3{ e.P[0], e.P[1], e.P[2] });
  };
  // The edges: where a face's part inside the sphere ends at its trim (a corner cutting in), the
  // deepest point lies on an edge. Restart from the edge point, moved a hair into a face.
  auto checkEdge = [&](size_t es) {
    const EdgeSegment& seg = m.EdgeSegments[es];
    const Edge& E = m.Edges[seg.Edge];
    if (E.Faces[0] < 0 || m.Faces[E.Faces[0]].Solid != solid)
      return;
    if (boxGap2(&data.EdgeBoxes[6 * es]) >= best * best)
      return;
    double T = seg.T0, bd = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= 8; ++i)
    {
      const double Ti = seg.T0 + (seg.T1 - seg.T0) * i / 8.0;
      const Vec3 w = Sub(EvaluateEdge(m, seg.Edge, Ti).C, M);
      if (Dot(w, w) < bd)
      {
        bd = Dot(w, w);
        T = Ti;
      }
    }
    for (int it = 0; it < 8; ++it)
    {
      const EdgeEval ee = EvaluateEdge(m, seg.Edge, T);
      const Vec3 w = Sub(ee.C, M);
      const double g = Dot(ee.Ct, w), h = Dot(ee.Ct, ee.Ct) + Dot(ee.Ctt, w);
      const double h2 = h > 0.0 ? h : Dot(ee.Ct, ee.Ct);
      if (!(h2 > 0.0))
        break;
      const double next = std::clamp(T - g / h2, std::min(seg.T0, seg.T1), std::max(seg.T0, seg.T1));
      const bool done = std::fabs(next - T) <= 1e-12 * (std::fabs(T) + 1.0);
      T = next;
      if (done)
        break;
    }
    const Vec3 C = EvaluateEdge(m, seg.Edge, T).C;
    const double dist = std::sqrt(Dot(Sub(C, M), Sub(C, M)));
    const Vec3 w = Sub(C, O);
    const double dn = Dot(d, w);
    if (!(dist < best) || !(dn > depth) ||
      NearSampleOnOwnFace(E.Faces[0] == s.Face || E.Faces[1] == s.Face ? s.Face : -1, w, dist))
      return;
    for (int k = 0; k < 2; ++k)
    {
      const int face = E.Faces[k];
      double u = 0.0, v = 0.0, nu = 0.0, nv = 0.0;
      if (face < 0 || m.Faces[face].PatchCount == 0 ||
        !EdgePointIntoFace(m, face, seg.Edge, T, u, v, nu, nv))
        continue;
      const Face& F = m.Faces[face];
      const double hair = 1e-6 * (F.Domain[1] - F.Domain[0] + F.Domain[3] - F.Domain[2]);
      best = dist;
      found = true;
      out.Face = face;
      out.U = u + hair * nu;
      out.V = v + hair * nv;
      out.T = 0.5 * (Dot(w, w) - depth * depth) / (dn - depth);
      break;
    }
  };
  const size_t np = m.Patches.size();
  auto gap2 = [&](const BVHNode& n) {
    const double b[6] = { n.Min[0], n.Min[1], n.Min[2], n.Max[0], n.Max[1], n.Max[2] };
    return boxGap2(b);
  };
  int stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0)
  {
    const BVHNode& n = data.BoxNodes[static_cast<size_t>(stack[--top])];
    if (gap2(n) >= best * best)
      continue;
    if (n.Count > 0)
    {
      for (int i = n.First; i < n.First + n.Count; ++i)
      {
        const size_t item = static_cast<size_t>(data.BoxItems[static_cast<size_t>(i)]);
        if (item < np)
          checkPatch(item);
        else
          checkEdge(item - np);
      }
      continue;
    }
    const int left = static_cast<int>(&n - data.BoxNodes.data()) + 1, right = n.Right;
    if (top + 2 > 64)
      continue; // cannot happen for a balanced tree
    const bool leftFirst = gap2(data.BoxNodes[static_cast<size_t>(left)]) <=
      gap2(data.BoxNodes[static_cast<size_t>(right)]);
    stack[top++] = leftFirst ? right : left;
    stack[top++] = leftFirst ? left : right;
  }
  return found;
}

/// Step 3, then steps 4-7 (once more from another face if that fails); then the verification
/// that the sphere is maximal: a point of s1 gives
/// a smaller t in eq. 1 exactly when it lies inside the sphere, so the bounded BVH query finds any
/// s1 point inside it. Newton may have converged to another stationary (tangent but not
/// inscribed) sphere; it restarts from that point (at most 3 times), and each restart must shrink
/// the sphere. A sphere that still contains an s1 point fails as not maximal.
void SolveWithClearance(const BRepModel& m, const SolverData& data, const SolverOptions& opt,
  const Sample& s, SampleResult& r)
{
  r = SampleResult();
  const double delta = Clearance(m, opt);
  // O's projection on its own trim: the edge nearest O, for the descent across it.
  const TrimProjection own = ClassifyPoint(m, s.Face, s.U, s.V);
  double t = 0.0;
  int p = Initialise(m, data, s, delta, t);
  if (p < 0)
  {
    r.Reason = FailReason::NoOppositePoint;
    return;
  }
  const int first = p;
  SolveFrom(m, data, opt, s, data.S1[p].Face, data.S1[p].U, data.S1[p].V, t, r);
  if (r.Type == ContactType::Failed && r.OppositeFace >= 0)
  {
    // The start on that face led nowhere (e.g. a convex blend with no tangent sphere): try the
    // best start on any other face once.
    p = Initialise(m, data, s, delta, t, std::numeric_limits<double>::infinity(), r.OppositeFace);
    if (p >= 0)
    {
      SampleResult other;
      other.Iterations = r.Iterations;
      SolveFrom(m, data, opt, s, data.S1[p].Face, data.S1[p].U, data.S1[p].V, t, other);
      if (other.Type != ContactType::Failed)
        r = other;
      else
        r.Iterations = other.Iterations;
    }
  }
  if (r.Type == ContactType::Failed)
  {
    // Newton found no sphere from the best starts: descend on t from the best start, and on the
    // face across the edge nearest O; keep the smaller valid sphere (verified below).
    int iterations = r.Iterations;
    const SampleResult a =
      Descend(m, data, opt, s, data.S1[first].Face, data.S1[first].U, data.S1[first].V, iterations);
    const SampleResult b = DescendAcrossNearestEdge(m, data, opt, s, own, iterations);
    if (b.Type != ContactType::Failed &&
      (a.Type == ContactType::Failed || b.Radius < a.Radius))
      r = b;
    else if (a.Type != ContactType::Failed)
      r = a;
    r.Iterations = iterations;
  }
  // Points inside by less than the patches' accuracy (2x the tolerance) prove nothing: the
  // patches wander by up to the tolerance, and the sample itself lies on the exact surface, up
  // to the tolerance off them. A point is more than `depth` inside the sphere (centre O + t d,
  // radius t) exactly when its t_depth is below t, whatever clearance found the sphere.
  const double depth = std::max(delta, 2.0 * m.Tolerance);
  for (int check = 0; r.Type != ContactType::Failed; ++check)
  {
    p = Initialise(m, data, s, depth, t, r.Radius * (1.0 - 1e-6));
    PointInside inside;
    if (p >= 0)
      inside = { data.S1[p].Face, data.S1[p].U, data.S1[p].V, t };
    else
    {
      SecondLook(m, data, opt, s, own, r); // no s1 point inside: maximal at the resolution of s1
      // Then the patches themselves: a wall narrower than s1's spacing can still reach in.
      if (!opt.Certify || !FindPointInside(m, data, s, r.Radius, depth, inside))
        return;
      t = inside.T;
    }
    // A point inside proves the true radius is below t(p) < r.Radius: the sphere found is not it.
    SampleResult again;
    again.Iterations = r.Iterations;
    if (check < 3)
      SolveFrom(m, data, opt, s, inside.Face, inside.U, inside.V, t, again);
    if (check < 3 && (again.Type == ContactType::Failed || !(again.Radius < r.Radius * (1.0 - 1e-6))))
    {
      // Newton went back to the same sphere or failed: descend on t from the point inside.
      int iterations = again.Iterations;
      again = Descend(m, data, opt, s, inside.Face, inside.U, inside.V, iterations);
      if (again.Type == ContactType::Failed || !(again.Radius < r.Radius * (1.0 - 1e-6)))
      {
        // A sample next to a convex edge has a small sphere touching the face across that
        // edge, closer to O than any s1 point: descend there from the edge point nearest O.
        const SampleResult across = DescendAcrossNearestEdge(m, data, opt, s, own, iterations);
        if (across.Type != ContactType::Failed)
          again = across;
      }
      again.Iterations = iterations;
    }
    if (check == 3 || again.Type == ContactType::Failed ||
      !(again.Radius < r.Radius * (1.0 - 1e-6)))
    {
      const int iterations = std::max(r.Iterations, again.Iterations);
      const int face = r.OppositeFace;
      const double residual = r.Residual;
      r = SampleResult();
      r.Reason = FailReason::NotMaximal;
      r.OppositeFace = face;
      r.Residual = residual;
      r.Iterations = iterations;
      return;
    }
    r = again;
  }
}

/// SolveWithClearance, and for a sample that fails with a clearance, again without one: within
/// the clearance of an acute convex edge every sphere the clearance admits has its centre
/// outside the material; there the exact contact (eq. 1) is the answer.
void SolveOne(const BRepModel& m, const SolverData& data, const SolverOptions& opt,
  const Sample& s, SampleResult& r)
{
  SolveWithClearance(m, data, opt, s, r);
  if (r.Type != ContactType::Failed || !(Clearance(m, opt) > 0.0))
    return;
  SolverOptions exact = opt;
  exact.Clearance = 0.0;
  SampleResult again;
  SolveWithClearance(m, data, exact, s, again);
  again.Iterations += r.Iterations;
  if (again.Type != ContactType::Failed)
    r = again;
  else
    r.Iterations = again.Iterations;
}
} // namespace

bool SphereHoldsBoundary(const BRepModel& model, const SolverData& data,
  const SolverOptions& options, const Sample& sample, const SampleResult& r)
{
  if (r.Type == ContactType::Failed)
    return false;
  const double depth = std::max(Clearance(model, options), 2.0 * model.Tolerance);
  PointInside inside;
  return FindPointInside(model, data, sample, r.Radius, depth, inside);
}

void SolveReference(const BRepModel& model, const SolverData& data, const SolverOptions& options,
  const std::vector<Sample>& samples, std::vector<SampleResult>& results)
{
  results.resize(samples.size());
  SolveReferenceRange(model, data, options, samples, results, 0, samples.size());
}

void SolveReferenceRange(const BRepModel& model, const SolverData& data,
  const SolverOptions& options, const std::vector<Sample>& samples,
  std::vector<SampleResult>& results, size_t first, size_t last)
{
  for (size_t i = first; i < last; ++i)
  {
    if (data.Nodes.empty())
    {
      results[i] = SampleResult();
      results[i].Reason = FailReason::NoOppositePoint;
    }
    else
    {
      SolveOne(model, data, options, samples[i], results[i]);
      ReportRadius(samples[i], results[i]);
    }
  }
}

void SolveReferenceParallel(const BRepModel& model, const SolverData& data,
  const SolverOptions& options, const std::vector<Sample>& samples,
  std::vector<SampleResult>& results, const std::vector<size_t>& which, unsigned threads)
{
  ParallelFor(which.size(), threads, [&](size_t j) {
    SolveReferenceRange(model, data, options, samples, results, which[j], which[j] + 1);
  });
}

void PolishResult(const BRepModel& m, const SolverData& data, const SolverOptions& opt,
  const Sample& s, SampleResult& r)
{
  if (r.Type == ContactType::Failed || data.Nodes.empty())
    return;
  int iterations = 0;
  SampleResult c;
  TrimProjection footTrim;
  const TrimProjection* trim = nullptr;
  // The solver's internal radius is t_delta (Clearance); r carries eq. 1's.
  const double tDelta = SphereRadius(s.Point, s.Direction, r.Foot, Clearance(m, opt));
  if (r.Type == ContactType::SurfaceSurface &&
    ShallowOwnFaceContact(m, s, r.OppositeFace, r.Foot, r.Radius))
  {
    // Only the descent finds such a contact (an osculating sphere next to O, on a concave
    // round): Newton from it goes to the trivial solution P = O. Descend again, in double.
    c = Descend(m, data, opt, s, r.OppositeFace, r.FootParameter[0], r.FootParameter[1],
      iterations);
  }
  else if (r.Type == ContactType::SurfaceSurface)
  {
    const SurfaceSolve ss = SurfaceNewton(m, data, opt, s.Point, s.Direction, r.OppositeFace,
      r.FootParameter[0], r.FootParameter[1], std::isfinite(tDelta) ? tDelta : r.Radius,
      iterations);
    if (ValidSurfaceSolve(m, data, opt, s, r.OppositeFace, ss))
    {
      c = SurfaceContact(s, r.OppositeFace, ss);
      footTrim = ss.Trim;
      trim = &footTrim;
    }
  }
  else if (r.OppositeEdge >= 0)
  {
    // A vertex: the edge's end in double (its float T is the end rounded to float).
    const Edge& E = m.Edges[r.OppositeEdge];
    double T = r.FootParameter[0];
    if (r.Type == ContactType::SurfaceVertex)
      T = std::fabs(T - E.T1) < std::fabs(T - E.T0) ? E.T1 : E.T0;
    c = EdgeContact(m, data, opt, s, r.OppositeFace, r.OppositeEdge,
      MinimiseOnEdge(m, data, opt, s, r.OppositeEdge, T, iterations));
  }
  if (c.Type == ContactType::Failed)
    return;
  const double rho = std::max(1e-2 * r.Radius, 20.0 * m.Tolerance);
  const Vec3 moved = Sub(c.Foot, r.Foot);
  if (Dot(moved, moved) > rho * rho)
    return;
  SecondLookNear(m, data, opt, s, c, iterations, trim);
  ReportRadius(s, c);
  c.Iterations = r.Iterations + iterations;
  r = c;
}

} // namespace brt
