#include "CoincidentFaces.h"

#include <BRepTools.hxx>
#include <BRepTopAdaptor_FClass2d.hxx>
#include <BRep_Tool.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <Geom_Surface.hxx>
#include <Standard_Failure.hxx>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace brt
{
namespace
{
constexpr int Picks = 9;              // vertices of a face asked
constexpr double MeshCos = 0.8660254; // cos 30 degrees: a triangle's normal against the surface's
constexpr double ExactCos = 0.990268; // cos 8 degrees: the two surfaces' normals

using Vec = std::array<double, 3>;

Vec At(const std::vector<double>& xyz, int i)
{
  const size_t k = 3 * static_cast<size_t>(i);
  return { xyz[k], xyz[k + 1], xyz[k + 2] };
}

Vec Sub(const Vec& a, const Vec& b)
{
  return { a[0] - b[0], a[1] - b[1], a[2] - b[2] };
}

double Dot(const Vec& a, const Vec& b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

Vec Cross(const Vec& a, const Vec& b)
{
  return { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0] };
}

// Up to Picks vertices of each face that lie on none of its mesh's boundary edges (an edge of one
// of the face's triangles that no other of its triangles has), spread over the face: three times
// as many are asked, spread over the face's vertices, and up to Picks kept, spread over those of
// them off the boundary. In time linear in the mesh's size.
std::vector<std::vector<int>> InnerVertices(const DisplayMesh& M, size_t faceCount)
{
  std::vector<std::vector<int>> asked(faceCount);
  {
    std::vector<std::vector<int>> all(faceCount);
    for (size_t v = 0; v < M.FaceIds.size(); ++v)
    {
      const int f = M.FaceIds[v];
      if (f >= 0 && static_cast<size_t>(f) < faceCount)
        all[static_cast<size_t>(f)].push_back(static_cast<int>(v));
    }
    for (size_t f = 0; f < faceCount; ++f)
    {
      const size_t n = all[f].size(), k = std::min<size_t>(3 * Picks, n);
      for (size_t i = 0; i < k; ++i)
        asked[f].push_back(all[f][(i * n) / k + (n / k) / 2]);
    }
  }
  // The triangles round each asked vertex, and their edges from it.
  std::vector<int> slot(M.FaceIds.size(), -1);
  std::vector<int> askedVertex;
  for (const auto& a : asked)
    for (int v : a)
    {
      slot[static_cast<size_t>(v)] = static_cast<int>(askedVertex.size());
      askedVertex.push_back(v);
    }
  std::vector<std::vector<int>> ends(askedVertex.size()); // the other corners, two per triangle
  for (size_t t = 0; 3 * t + 2 < M.Triangles.size(); ++t)
    for (size_t c = 0; c < 3; ++c)
    {
      const auto v = static_cast<size_t>(M.Triangles[3 * t + c]);
      const int s = v < slot.size() ? slot[v] : -1;
      if (s < 0)
        continue;
      ends[static_cast<size_t>(s)].push_back(M.Triangles[3 * t + (c + 1) % 3]);
      ends[static_cast<size_t>(s)].push_back(M.Triangles[3 * t + (c + 2) % 3]);
    }
  // A vertex is inner where each edge from it belongs to two of its triangles.
  auto inner = [&](int v) {
    std::vector<int>& e = ends[static_cast<size_t>(slot[static_cast<size_t>(v)])];
    if (e.empty())
      return false;
    std::sort(e.begin(), e.end());
    for (size_t i = 0; i < e.size();)
    {
      size_t j = i + 1;
      while (j < e.size() && e[j] == e[i])
        ++j;
      if (j - i != 2)
        return false;
      i = j;
    }
    return true;
  };
  std::vector<std::vector<int>> picks(faceCount);
  for (size_t f = 0; f < faceCount; ++f)
  {
    std::vector<int> in;
    for (int v : asked[f])
      if (inner(v))
        in.push_back(v);
    const size_t n = in.size(), k = std::min<size_t>(Picks, n);
    for (size_t i = 0; i < k; ++i)
      picks[f].push_back(in[(i * n) / k]);
  }
  return picks;
}

// Whether `a`'s picked vertices lie on face `b` as the exact faces say: at least 3 and at least
// half of them within `gap` of b's surface, b's outward normal there within 8 degrees of a's,
// inside b's boundary.
bool LiesOn(const BRepModel& model, const std::vector<TopoDS_Face>& faces,
  const std::vector<int>& picks, int b, double gap)
{
  const TopoDS_Face& fb = faces[static_cast<size_t>(b)];
  Handle(Geom_Surface) surface = BRep_Tool::Surface(fb);
  if (surface.IsNull())
    return false;
  double u0 = 0.0, u1 = 0.0, v0 = 0.0, v1 = 0.0;
  BRepTools::UVBounds(fb, u0, u1, v0, v1);
  GeomAPI_ProjectPointOnSurf project;
  project.Init(surface, u0, u1, v0, v1);
  BRepTopAdaptor_FClass2d classifier(fb, 1e-9);
  const DisplayMesh& M = model.Mesh;
  auto onB = [&](int v) {
    const Vec p = At(M.Points, v), na = At(M.Normals, v);
    project.Perform(gp_Pnt(p[0], p[1], p[2]));
    if (!project.IsDone() || project.NbPoints() == 0 || project.LowerDistance() > gap)
      return false;
    double u = 0.0, w = 0.0;
    project.LowerDistanceParameters(u, w);
    gp_Pnt q;
    gp_Vec du, dv;
    surface->D1(u, w, q, du, dv);
    gp_Vec nb = du.Crossed(dv);
    if (nb.Magnitude() < 1e-14)
      return false;
    nb.Normalize();
    if (model.Faces[static_cast<size_t>(b)].Reversed)
      nb.Reverse();
    return nb.X() * na[0] + nb.Y() * na[1] + nb.Z() * na[2] >= ExactCos &&
      classifier.Perform(gp_Pnt2d(u, w)) == TopAbs_IN;
  };
  const int n = static_cast<int>(picks.size());
  int hits = 0, misses = 0;
  for (int v : picks)
    if (onB(v))
      ++hits;
    else if (2 * ++misses > n)
      break; // (half cannot be reached any more)
  return hits >= 3 && 2 * hits >= n;
}
} // namespace

std::vector<std::pair<int, int>> FindCoincidentFaces(const BRepModel& model,
  const std::vector<TopoDS_Face>& faces, double tolerance, double deflection)
{
  std::vector<std::pair<int, int>> found;
  const DisplayMesh& M = model.Mesh;
  const size_t nf = std::min(model.Faces.size(), faces.size());
  const size_t nt = M.TriangleFace.size();
  if (nf < 2 || nt == 0 || M.Normals.size() != M.Points.size())
    return found;
  const std::vector<std::vector<int>> picks = InnerVertices(M, nf);

  // The picked vertices in a hash grid of cells, each triangle then asking the cells its box,
  // grown by the reach, meets. The cells start at the mesh's box over 64 along its longest side
  // and are halved (down to over 4096) while one of them holds more than 64 vertices: a screw's
  // thread of thousands of faces in one cell of an assembly would otherwise have each of its
  // triangles test every vertex of the thread. A triangle meeting more than 512 cells asks the
  // vertices in its box's x range instead (the vertices sorted along x).
  Vec lo{ 1e300, 1e300, 1e300 }, hi{ -1e300, -1e300, -1e300 };
  for (size_t i = 0; i + 2 < M.Points.size(); i += 3)
    for (size_t k = 0; k < 3; ++k)
    {
      lo[k] = std::min(lo[k], M.Points[i + k]);
      hi[k] = std::max(hi[k], M.Points[i + k]);
    }
  const double reach = 2.0 * deflection + 10.0 * tolerance;
  const double size = std::max({ hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-9 });
  std::vector<int> picked;
  for (size_t a = 0; a < nf; ++a)
    if (picks[a].size() >= 3)
      picked.insert(picked.end(), picks[a].begin(), picks[a].end());
  double cell = 0.0;
  auto index = [&](double x, size_t k) {
    return static_cast<int64_t>(std::floor((x - lo[k]) / cell));
  };
  auto key = [](int64_t i, int64_t j, int64_t k) {
    return static_cast<uint64_t>(i & 0x1fffff) << 42 | static_cast<uint64_t>(j & 0x1fffff) << 21 |
      static_cast<uint64_t>(k & 0x1fffff);
  };
  std::unordered_map<uint64_t, std::vector<int>> grid; // cell -> picked vertices
  for (double parts = 64.0; parts <= 4096.0; parts *= 2.0)
  {
    cell = size / parts + reach;
    grid.clear();
    size_t most = 0;
    for (int v : picked)
    {
      const Vec p = At(M.Points, v);
      std::vector<int>& in = grid[key(index(p[0], 0), index(p[1], 1), index(p[2], 2))];
      in.push_back(v);
      most = std::max(most, in.size());
    }
    if (most <= 64 || cell < 2.0 * reach)
      break;
  }
  std::vector<std::pair<double, int>> alongX;
  alongX.reserve(picked.size());
  for (int v : picked)
    alongX.emplace_back(M.Points[3 * static_cast<size_t>(v)], v);
  std::sort(alongX.begin(), alongX.end());

  // On the mesh: for each picked vertex of a face, the other faces of its solid with a triangle
  // under it (the vertex within the reach of the triangle's plane, its foot inside the triangle
  // but for a twentieth, the triangle's normal within 30 degrees of the vertex's).
  std::vector<uint64_t> over; // vertex << 32 | face b, once per triangle
  for (size_t t = 0; t < nt; ++t)
  {
    const int b = M.TriangleFace[t];
    if (b < 0 || static_cast<size_t>(b) >= nf)
      continue;
    const Vec q0 = At(M.Points, M.Triangles[3 * t]), q1 = At(M.Points, M.Triangles[3 * t + 1]),
              q2 = At(M.Points, M.Triangles[3 * t + 2]);
    const Vec e1 = Sub(q1, q0), e2 = Sub(q2, q0), n = Cross(e1, e2);
    const double area2 = std::sqrt(Dot(n, n));
    if (!(area2 > 0.0))
      continue;
    Vec bmin{}, bmax{};
    for (size_t k = 0; k < 3; ++k)
    {
      bmin[k] = std::min({ q0[k], q1[k], q2[k] }) - reach;
      bmax[k] = std::max({ q0[k], q1[k], q2[k] }) + reach;
    }
    auto test = [&](int v) {
      const int a = M.FaceIds[static_cast<size_t>(v)];
      if (a == b ||
        model.Faces[static_cast<size_t>(a)].Solid != model.Faces[static_cast<size_t>(b)].Solid)
        return;
      const Vec p = At(M.Points, v), na = At(M.Normals, v);
      if (Dot(n, na) < MeshCos * area2)
        return;
      const Vec d = Sub(p, q0);
      if (std::fabs(Dot(d, n)) > reach * area2)
        return;
      // Barycentric coordinates of p's foot, with a margin of a twentieth.
      const double s = Dot(Cross(d, e2), n) / (area2 * area2);
      const double r = Dot(Cross(e1, d), n) / (area2 * area2);
      if (s < -0.05 || r < -0.05 || s + r > 1.05)
        return;
      over.push_back(static_cast<uint64_t>(v) << 32 | static_cast<uint32_t>(b));
    };
    std::array<int64_t, 3> from{}, to{};
    for (size_t k = 0; k < 3; ++k)
    {
      from[k] = index(bmin[k], k);
      to[k] = index(bmax[k], k);
    }
    if ((to[0] - from[0] + 1) * (to[1] - from[1] + 1) * (to[2] - from[2] + 1) > 512)
    {
      auto it = std::lower_bound(alongX.begin(), alongX.end(), std::make_pair(bmin[0], -1));
      for (; it != alongX.end() && it->first <= bmax[0]; ++it)
      {
        const double* p = &M.Points[3 * static_cast<size_t>(it->second)];
        if (p[1] >= bmin[1] && p[1] <= bmax[1] && p[2] >= bmin[2] && p[2] <= bmax[2])
          test(it->second);
      }
      continue;
    }
    for (int64_t i = from[0]; i <= to[0]; ++i)
      for (int64_t j = from[1]; j <= to[1]; ++j)
        for (int64_t k = from[2]; k <= to[2]; ++k)
        {
          const auto it = grid.find(key(i, j, k));
          if (it != grid.end())
            for (int v : it->second)
              test(v);
        }
  }
  // Each (vertex, face) once, then counted per (face a, face b).
  std::sort(over.begin(), over.end());
  over.erase(std::unique(over.begin(), over.end()), over.end());
  std::vector<uint64_t> candidates; // a << 32 | b, in order
  {
    std::vector<uint64_t> pairs;
    pairs.reserve(over.size());
    for (const uint64_t o : over)
    {
      const auto a = static_cast<uint64_t>(M.FaceIds[static_cast<size_t>(o >> 32)]);
      pairs.push_back(a << 32 | (o & 0xffffffffu));
    }
    std::sort(pairs.begin(), pairs.end());
    for (size_t i = 0; i < pairs.size();)
    {
      size_t j = i + 1;
      while (j < pairs.size() && pairs[j] == pairs[i])
        ++j;
      const int hits = static_cast<int>(j - i);
      const size_t a = static_cast<size_t>(pairs[i] >> 32);
      if (hits >= 3 && 2 * hits >= static_cast<int>(picks[a].size()))
        candidates.push_back(pairs[i]);
      i = j;
    }
  }

  // On the exact faces.
  for (const uint64_t c : candidates)
  {
    const int a = static_cast<int>(c >> 32), b = static_cast<int>(c & 0xffffffffu);
    const double gap = std::max({ 10.0 * tolerance,
      BRep_Tool::Tolerance(faces[static_cast<size_t>(a)]),
      BRep_Tool::Tolerance(faces[static_cast<size_t>(b)]) });
    try
    {
      if (LiesOn(model, faces, picks[static_cast<size_t>(a)], b, gap))
        found.emplace_back(a, b);
    }
    catch (const Standard_Failure&)
    {
      // (a surface OpenCASCADE cannot project onto: not taken for coincident)
    }
  }
  return found;
}
} // namespace brt
