#include "Midsurface.h"

#include "MeshGeometry.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <queue>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace brt
{
namespace
{
using namespace mesh;

/// Edge -> triangles of a triangle list.
std::unordered_map<uint64_t, std::vector<int>> EdgeMap(const std::vector<int>& tris)
{
  std::unordered_map<uint64_t, std::vector<int>> edges;
  edges.reserve(tris.size());
  for (size_t t = 0; t < tris.size() / 3; ++t)
    for (int k = 0; k < 3; ++k)
      edges[EdgeKey(tris[3 * t + k], tris[3 * t + (k + 1) % 3])].push_back(int(t));
  return edges;
}

/// The mesh under construction: points with their thickness, kind, sheet normal and sheet.
struct Mesh
{
  std::vector<double> Points;
  std::vector<double> Thickness;
  std::vector<int> Kind;
  std::vector<double> Normal; ///< the sheet's normal at the point (the sample's inward normal)
  std::vector<int> Tris;
  std::vector<int> TriSheet;

  int AddPoint(const V3& p, double h, int kind, const V3& n)
  {
    this->Points.insert(this->Points.end(), p.begin(), p.end());
    this->Normal.insert(this->Normal.end(), n.begin(), n.end());
    this->Thickness.push_back(h);
    this->Kind.push_back(kind);
    return int(this->Thickness.size()) - 1;
  }
  size_t NumberOfPoints() const { return this->Thickness.size(); }

  /// Merges points closer than tol (the first keeps its place; the thickness is averaged; the
  /// kind is the smallest), drops the triangles that collapse and the duplicates, and the points
  /// no triangle uses.
  void Merge(double tol)
  {
    const size_t n = this->NumberOfPoints();
    Grid grid(4.0 * tol);
    std::vector<int> to(n, -1);
    std::vector<double> sum(n, 0.0);
    std::vector<int> count(n, 0);
    for (size_t i = 0; i < n; ++i)
    {
      const V3 p = At(this->Points, i);
      int found = -1;
      grid.QueryBall(p, tol, [&](int j) {
        if (found < 0 && Norm(Sub(At(this->Points, size_t(j)), p)) <= tol)
          found = j;
      });
      if (found < 0)
      {
        grid.Insert(p, int(i));
        found = int(i);
      }
      to[i] = found;
      sum[size_t(found)] += this->Thickness[i];
      count[size_t(found)] += 1;
      this->Kind[size_t(found)] = std::min(this->Kind[size_t(found)], this->Kind[i]);
    }
    std::vector<int> tris, sheets;
    std::map<std::array<int, 3>, int> unique;
    for (size_t t = 0; t < this->Tris.size() / 3; ++t)
    {
      std::array<int, 3> v{ to[size_t(this->Tris[3 * t])], to[size_t(this->Tris[3 * t + 1])],
        to[size_t(this->Tris[3 * t + 2])] };
      if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2])
        continue;
      auto key = v;
      std::sort(key.begin(), key.end());
      if (!unique.emplace(key, int(t)).second)
        continue;
      tris.insert(tris.end(), v.begin(), v.end());
      sheets.push_back(this->TriSheet[t]);
    }
    // Compact the points.
    std::vector<int> newId(n, -1);
    Mesh out;
    for (int& v : tris)
    {
      if (newId[size_t(v)] < 0)
      {
        const size_t i = size_t(v);
        newId[i] = out.AddPoint(At(this->Points, i), sum[i] / count[i], this->Kind[i],
          At(this->Normal, i));
      }
      v = newId[size_t(v)];
    }
    out.Tris = std::move(tris);
    out.TriSheet = std::move(sheets);
    *this = std::move(out);
  }

  /// Within one sheet an edge has at most two triangles: strips of neighbouring boundary edges
  /// that overlap (around a corner of the boundary) would fold it. Removes the strip triangles
  /// (those with a junction vertex) beyond two, the latest first; returns how many.
  int RemoveFoldedStrips()
  {
    int removed = 0;
    for (int pass = 0; pass < 4; ++pass)
    {
      const auto edges = EdgeMap(this->Tris);
      std::vector<char> drop(this->TriSheet.size(), 0);
      for (const auto& e : edges)
      {
        if (e.second.size() < 3)
          continue;
        std::map<int, std::vector<int>> bySheet;
        for (int t : e.second)
          if (!drop[size_t(t)])
            bySheet[this->TriSheet[size_t(t)]].push_back(t);
        for (auto& s : bySheet)
        {
          auto& ts = s.second;
          std::sort(ts.begin(), ts.end());
          size_t kept = ts.size();
          for (auto it = ts.rbegin(); it != ts.rend() && kept > 2; ++it)
          {
            bool strip = false;
            for (int k = 0; k < 3; ++k)
              strip = strip || this->Kind[size_t(this->Tris[3 * size_t(*it) + k])] == 2;
            if (strip)
            {
              drop[size_t(*it)] = 1;
              --kept;
            }
          }
        }
      }
      int n = 0;
      std::vector<int> tris, sheets;
      for (size_t t = 0; t < this->TriSheet.size(); ++t)
        if (drop[t])
          ++n;
        else
        {
          tris.insert(tris.end(), this->Tris.begin() + long(3 * t), this->Tris.begin() + long(3 * t + 3));
          sheets.push_back(this->TriSheet[t]);
        }
      if (n == 0)
        break;
      removed += n;
      this->Tris = std::move(tris);
      this->TriSheet = std::move(sheets);
    }
    return removed;
  }

  /// Splits boundary edges at the boundary points of other triangles that lie on them (within
  /// tol), so that boundaries that meet share their vertices.
  void ConformBoundaries(double tol, double cell)
  {
    for (int pass = 0; pass < 8; ++pass)
    {
      const auto edges = EdgeMap(this->Tris);
      std::vector<char> onBoundary(this->NumberOfPoints(), 0);
      std::vector<std::pair<uint64_t, int>> boundary;
      for (const auto& e : edges)
        if (e.second.size() == 1)
        {
          boundary.emplace_back(e.first, e.second[0]);
          onBoundary[e.first >> 32] = 1;
          onBoundary[e.first & 0xffffffffu] = 1;
        }
      Grid grid(cell);
      for (size_t i = 0; i < this->NumberOfPoints(); ++i)
        if (onBoundary[i])
          grid.Insert(At(this->Points, i), int(i));
      // One split edge per triangle and pass.
      std::map<int, std::pair<std::array<int, 2>, std::vector<std::pair<double, int>>>> splits;
      for (const auto& be : boundary)
      {
        const int a = int(be.first >> 32), b = int(be.first & 0xffffffffu);
        if (splits.count(be.second))
          continue;
        const V3 pa = At(this->Points, size_t(a)), pb = At(this->Points, size_t(b));
        const V3 ab = Sub(pb, pa);
        const double len2 = Dot(ab, ab);
        if (len2 <= 0.0)
          continue;
        V3 lo, hi;
        for (int k = 0; k < 3; ++k)
        {
          lo[size_t(k)] = std::min(pa[size_t(k)], pb[size_t(k)]) - tol;
          hi[size_t(k)] = std::max(pa[size_t(k)], pb[size_t(k)]) + tol;
        }
        std::vector<std::pair<double, int>> on;
        grid.Query(lo, hi, [&](int c) {
          if (c == a || c == b)
            return;
          const V3 pc = At(this->Points, size_t(c));
          const double u = Dot(Sub(pc, pa), ab) / len2;
          if (u <= 1e-9 || u >= 1.0 - 1e-9)
            return;
          if (Norm(Sub(pc, Add(pa, Mul(ab, u)))) <= tol)
            on.emplace_back(u, c);
        });
        if (on.empty())
          continue;
        std::sort(on.begin(), on.end());
        splits[be.second] = { { a, b }, std::move(on) };
      }
      if (splits.empty())
        return;
      std::vector<int> tris;
      std::vector<int> sheets;
      for (size_t t = 0; t < this->Tris.size() / 3; ++t)
      {
        const auto it = splits.find(int(t));
        if (it == splits.end())
        {
          tris.insert(tris.end(), this->Tris.begin() + long(3 * t), this->Tris.begin() + long(3 * t + 3));
          sheets.push_back(this->TriSheet[t]);
          continue;
        }
        // Rotate the triangle so the split edge is (v0, v1) in its own order.
        std::array<int, 3> v{ this->Tris[3 * t], this->Tris[3 * t + 1], this->Tris[3 * t + 2] };
        const int a = it->second.first[0], b = it->second.first[1];
        while (!((v[0] == a && v[1] == b) || (v[0] == b && v[1] == a)))
          std::rotate(v.begin(), v.begin() + 1, v.end());
        std::vector<int> chain;
        chain.push_back(v[0]);
        if (v[0] == a)
          for (const auto& c : it->second.second)
            chain.push_back(c.second);
        else
          for (auto c = it->second.second.rbegin(); c != it->second.second.rend(); ++c)
            chain.push_back(c->second);
        chain.push_back(v[1]);
        for (size_t k = 0; k + 1 < chain.size(); ++k)
        {
          tris.insert(tris.end(), { chain[k], chain[k + 1], v[2] });
          sheets.push_back(this->TriSheet[t]);
        }
      }
      this->Tris = std::move(tris);
      this->TriSheet = std::move(sheets);
    }
  }
};
} // namespace

EdgeCounts CountEdges(const std::vector<int>& triangles)
{
  EdgeCounts c;
  const auto edges = EdgeMap(triangles);
  std::unordered_map<int, int> parent;
  std::function<int(int)> find = [&](int x) {
    auto it = parent.find(x);
    if (it == parent.end())
    {
      parent[x] = x;
      return x;
    }
    if (it->second == x)
      return x;
    const int r = find(it->second);
    parent[x] = r;
    return r;
  };
  for (const auto& e : edges)
  {
    if (e.second.size() == 1)
      ++c.Boundary;
    else if (e.second.size() == 2)
      ++c.Manifold;
    else
    {
      ++c.NonManifold;
      const int a = find(int(e.first >> 32)), b = find(int(e.first & 0xffffffffu));
      parent[a] = b;
    }
  }
  std::unordered_map<int, int> roots;
  for (const auto& p : parent)
    roots[find(p.first)] = 1;
  c.NonManifoldChains = int(roots.size());
  return c;
}

void CheckMidsurfaceInput(const MidsurfaceInput& in, const char* who)
{
  const size_t nV = in.Points.size() / 3;
  if (in.Normals.size() != 3 * nV || in.FaceIds.size() != nV || in.Thickness.size() != nV ||
    in.ContactType.size() != nV || in.OppositeFace.size() != nV ||
    in.ContactAngle.size() != nV || in.EdgeZone.size() != nV)
    throw std::invalid_argument(std::string(who) + ": per-vertex arrays of different lengths");
  for (int v : in.Triangles)
    if (v < 0 || size_t(v) >= nV)
      throw std::invalid_argument(std::string(who) + ": a triangle refers to a missing vertex");
}

Midsurface BuildMidsurface(const MidsurfaceInput& in, const MidsurfaceOptions& opt)
{
  CheckMidsurfaceInput(in, "BuildMidsurface");
  const size_t nV = in.Points.size() / 3, nT = in.Triangles.size() / 3;

  Midsurface out;
  auto O = [&](size_t v) { return At(in.Points, v); };
  auto D = [&](size_t v) { return Mul(At(in.Normals, v), -1.0); };

  // Vertex areas and adjacency (within a face: the reader does not share vertices).
  std::vector<double> area(nV, 0.0);
  std::vector<std::vector<int>> nbr(nV);
  for (size_t t = 0; t < nT; ++t)
  {
    const int* v = &in.Triangles[3 * t];
    const double a =
      0.5 * Norm(Cross(Sub(O(size_t(v[1])), O(size_t(v[0]))), Sub(O(size_t(v[2])), O(size_t(v[0])))));
    for (int k = 0; k < 3; ++k)
    {
      area[size_t(v[k])] += a / 3.0;
      nbr[size_t(v[k])].push_back(v[(k + 1) % 3]);
      nbr[size_t(v[k])].push_back(v[(k + 2) % 3]);
    }
  }
  for (auto& n : nbr)
  {
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
  }

  // 1. Sheet samples and the face pairs they join.
  auto solved = [&](size_t v) { return std::isfinite(in.Thickness[v]) && in.ContactType[v] > 0; };
  std::vector<char> sheet(nV, 0);
  for (size_t v = 0; v < nV; ++v)
    sheet[v] = solved(v) && in.Thickness[v] > 0.0 && in.ContactType[v] == 1 && !in.EdgeZone[v] &&
      in.ContactAngle[v] >= opt.SheetAngle && in.OppositeFace[v] >= 0 &&
      in.OppositeFace[v] != in.FaceIds[v];
  struct Pair
  {
    int A, B;
    double Area[2] = { 0.0, 0.0 };
    std::vector<double> H, W; // thickness and vertex area of each sheet sample
    bool Thin = false;
    int Rep = -1;
    int Sheet = -1;
    double Median = 0.0;
    int Triangles = 0;
    bool Noise = false;
  };
  std::map<uint64_t, int> pairIndex;
  std::vector<Pair> pairs;
  auto pairOf = [&](int f, int g) {
    const auto it = pairIndex.find(EdgeKey(f, g));
    return it == pairIndex.end() ? -1 : it->second;
  };
  for (size_t v = 0; v < nV; ++v)
    if (sheet[v])
    {
      const int f = in.FaceIds[v], g = in.OppositeFace[v];
      auto it = pairIndex.find(EdgeKey(f, g));
      if (it == pairIndex.end())
      {
        it = pairIndex.emplace(EdgeKey(f, g), int(pairs.size())).first;
        Pair p;
        p.A = std::min(f, g);
        p.B = std::max(f, g);
        pairs.push_back(p);
      }
      Pair& p = pairs[size_t(it->second)];
      p.Area[f == p.A ? 0 : 1] += area[v];
      p.H.push_back(in.Thickness[v]);
      p.W.push_back(area[v]);
    }
  // Triangles whose three vertices are sheet samples of one pair: a pair without one is a few
  // isolated samples (next to edges), not a wall.
  for (size_t t = 0; t < nT; ++t)
  {
    const int* v = &in.Triangles[3 * t];
    if (!sheet[size_t(v[0])] || !sheet[size_t(v[1])] || !sheet[size_t(v[2])])
      continue;
    const int g = in.OppositeFace[size_t(v[0])];
    if (in.OppositeFace[size_t(v[1])] == g && in.OppositeFace[size_t(v[2])] == g)
      pairs[size_t(pairOf(in.FaceIds[size_t(v[0])], g))].Triangles += 1;
  }
  std::vector<double> thinH;
  for (auto& p : pairs)
  {
    // By area: the median sample of a sliver-strip mesh lies where its vertices crowd.
    p.Median = WeightedMedian(p.H, p.W);
    p.Noise = p.H.size() < 3 || p.Triangles == 0;
    // Slender: thin against its extent. Thin: slender and a wall (not noise). Pairs that are not
    // slender are reported (a block's few wall samples included), noise that is slender is not.
    const bool slender =
      p.Median <= opt.MaximumSlenderness * std::sqrt(std::max(p.Area[0], p.Area[1]));
    p.Thin = !p.Noise && slender;
    p.Noise = p.Noise && slender;
    if (p.Thin)
      thinH.push_back(p.Median);
  }
  if (thinH.empty())
  {
    // Nothing thin: report the faces with wall samples.
    std::map<int, double> faces;
    for (size_t v = 0; v < nV; ++v)
      if (sheet[v] && !pairs[size_t(pairOf(in.FaceIds[v], in.OppositeFace[v]))].Noise)
        faces[in.FaceIds[v]] = 0.0;
    for (size_t v = 0; v < nV; ++v)
      if (faces.count(in.FaceIds[v]))
        out.NotThinArea += area[v];
    for (const auto& f : faces)
      out.NotThinFaces.push_back(f.first);
    for (size_t v = 0; v < nV; ++v)
      out.PrunedSamples += solved(v) ? 1 : 0;
    return out;
  }
  const double hRef = Median(thinH);
  const double tol = 1e-3 * hRef;

  // Faces with wall samples mostly in pairs that are not thin: reported.
  {
    std::map<int, std::array<double, 2>> faceArea; // thin, not thin
    for (size_t v = 0; v < nV; ++v)
      if (sheet[v])
      {
        const Pair& p = pairs[size_t(pairOf(in.FaceIds[v], in.OppositeFace[v]))];
        if (p.Thin || !p.Noise) // noise (isolated samples) is neither
          faceArea[in.FaceIds[v]][p.Thin ? 0 : 1] += area[v];
      }
    std::map<int, char> notThin;
    for (const auto& f : faceArea)
      if (f.second[1] > f.second[0])
        notThin[f.first] = 1;
    for (size_t v = 0; v < nV; ++v)
      if (notThin.count(in.FaceIds[v]))
        out.NotThinArea += area[v];
    for (const auto& f : notThin)
      out.NotThinFaces.push_back(f.first);
  }
  std::vector<char> faceThin; // the face is in a thin pair
  int nFaces = 0;
  for (int f : in.FaceIds)
    nFaces = std::max(nFaces, f + 1);
  for (const auto& p : pairs)
    nFaces = std::max(nFaces, p.B + 1);
  faceThin.assign(size_t(nFaces), 0);
  for (const auto& p : pairs)
    if (p.Thin)
      faceThin[size_t(p.A)] = faceThin[size_t(p.B)] = 1;

  // 2. Which face of a pair carries the sheet: the one with more concave edge length towards faces
  //    of other thin pairs (its boundary is where junctions start), then the larger sheet area,
  //    then the lower id.
  std::vector<double> junctionScore(size_t(nFaces), 0.0);
  {
    const auto edges = EdgeMap(in.Triangles);
    struct BEdge
    {
      int A, B, Tri;
    };
    std::vector<BEdge> bedges;
    double longest = 0.0;
    for (const auto& e : edges)
      if (e.second.size() == 1)
      {
        const int a = int(e.first >> 32), b = int(e.first & 0xffffffffu);
        bedges.push_back({ a, b, e.second[0] });
        longest = std::max(longest, Norm(Sub(O(size_t(a)), O(size_t(b)))));
      }
    Grid grid(std::max(longest, 1e-12));
    for (size_t i = 0; i < bedges.size(); ++i)
      grid.Insert(Mul(Add(O(size_t(bedges[i].A)), O(size_t(bedges[i].B))), 0.5), int(i));
    for (const auto& be : bedges)
    {
      const int f = in.FaceIds[size_t(be.A)];
      if (!faceThin[size_t(f)])
        continue;
      const V3 a = O(size_t(be.A)), b = O(size_t(be.B));
      const V3 m = Mul(Add(a, b), 0.5);
      const double len = Norm(Sub(b, a));
      // The face across: the other face's boundary edge nearest to the midpoint.
      double best = std::numeric_limits<double>::infinity();
      int across = -1;
      grid.QueryBall(m, longest, [&](int j) {
        const BEdge& o = bedges[size_t(j)];
        const int g = in.FaceIds[size_t(o.A)];
        if (g == f)
          return;
        const V3 oa = O(size_t(o.A)), ob = O(size_t(o.B));
        const V3 ab = Sub(ob, oa);
        const double l2 = Dot(ab, ab);
        const double u = l2 > 0.0 ? std::clamp(Dot(Sub(m, oa), ab) / l2, 0.0, 1.0) : 0.0;
        const double d = Norm(Sub(m, Add(oa, Mul(ab, u))));
        if (d < best)
        {
          best = d;
          across = j;
        }
      });
      if (across < 0 || best > 0.5 * len + tol)
        continue;
      const BEdge& o = bedges[size_t(across)];
      const int g = in.FaceIds[size_t(o.A)];
      if (!faceThin[size_t(g)])
        continue;
      const int* tv = &in.Triangles[3 * size_t(o.Tri)];
      const V3 c =
        Mul(Add(Add(O(size_t(tv[0])), O(size_t(tv[1]))), O(size_t(tv[2]))), 1.0 / 3.0);
      const V3 dF = Unit(Add(D(size_t(be.A)), D(size_t(be.B))));
      const V3 mc = Sub(c, m);
      if (Dot(mc, dF) < -0.25 * Norm(mc))
        junctionScore[size_t(f)] += len;
    }
  }
  int nSheets = 0;
  for (auto& p : pairs)
  {
    if (!p.Thin)
      continue;
    // A side that sees much less of the sheet than the other (its samples touch other faces
    // there, or none at all) cannot carry it: the larger side does. Between comparable sides the
    // junction edges decide.
    const double sa = junctionScore[size_t(p.A)], sb = junctionScore[size_t(p.B)];
    const double small = std::min(p.Area[0], p.Area[1]), large = std::max(p.Area[0], p.Area[1]);
    if (small < 0.75 * large)
      p.Rep = p.Area[0] > p.Area[1] ? p.A : p.B;
    else if (std::fabs(sa - sb) > 1e-9 * (sa + sb))
      p.Rep = sa > sb ? p.A : p.B;
    else if (std::fabs(p.Area[0] - p.Area[1]) > 1e-3 * (p.Area[0] + p.Area[1]))
      p.Rep = p.Area[0] > p.Area[1] ? p.A : p.B;
    else
      p.Rep = p.A;
    p.Sheet = nSheets++;
    MidsurfaceSheet s;
    s.Face = p.Rep;
    s.OppositeFace = p.Rep == p.A ? p.B : p.A;
    s.Thickness = p.Median;
    out.Sheets.push_back(s);
  }

  // 3. The vertices of the sheets' faces: sheet samples at their sphere centres; edge-zone
  //    vertices within ExtrapolationLimit thicknesses of a sheet sample (along the face) at
  //    O + d h/2 with that sample's h (Dijkstra from the sheet samples, through edge zones only).
  std::vector<int> partner(nV, -1), source(nV, -1), hops(nV, 0);
  std::vector<double> hOf(nV, 0.0), dist(nV, std::numeric_limits<double>::infinity());
  {
    using QE = std::pair<double, int>;
    std::priority_queue<QE, std::vector<QE>, std::greater<QE>> queue;
    for (size_t v = 0; v < nV; ++v)
      if (sheet[v])
      {
        const int k = pairOf(in.FaceIds[v], in.OppositeFace[v]);
        if (!pairs[size_t(k)].Thin)
          continue;
        partner[v] = in.OppositeFace[v];
        hOf[v] = in.Thickness[v];
        dist[v] = 0.0;
        source[v] = int(v);
        queue.push({ 0.0, int(v) });
      }
    while (!queue.empty())
    {
      const auto [dv, v] = queue.top();
      queue.pop();
      if (dv > dist[size_t(v)])
        continue;
      for (int w : nbr[size_t(v)])
      {
        if (sheet[size_t(w)] || !in.EdgeZone[size_t(w)])
          continue;
        // Ordered by the path along the face, limited by the straight distance to the source
        // (a corner of a rim is sqrt(2) h/2 from the nearest sheet sample, its path longer).
        // On a mesh coarser than the wall is thick the edge zone is the rim's own vertices, an
        // edge or two from the nearest sheet sample: two steps are always allowed.
        const double dw = dv + Norm(Sub(O(size_t(w)), O(size_t(v))));
        const int src = source[size_t(v)];
        if ((Norm(Sub(O(size_t(w)), O(size_t(src)))) > opt.ExtrapolationLimit * hOf[size_t(v)] &&
              hops[size_t(v)] >= 2) ||
          dw >= dist[size_t(w)])
          continue;
        dist[size_t(w)] = dw;
        hops[size_t(w)] = hops[size_t(v)] + 1;
        source[size_t(w)] = src;
        partner[size_t(w)] = partner[size_t(v)];
        hOf[size_t(w)] = hOf[size_t(v)];
        queue.push({ dw, w });
      }
    }
  }

  Mesh mesh;
  std::vector<int> outId(nV, -1);
  auto emit = [&](size_t v) {
    if (outId[v] < 0)
    {
      const V3 p = Add(O(v), Mul(D(v), 0.5 * hOf[v]));
      outId[v] = mesh.AddPoint(p, hOf[v], sheet[v] ? 0 : 1, D(v));
    }
    return outId[v];
  };
  std::vector<char> used(nV, 0);
  for (size_t t = 0; t < nT; ++t)
  {
    const int* v = &in.Triangles[3 * t];
    const int f = in.FaceIds[size_t(v[0])];
    int sheets[3];
    bool ok = true;
    for (int k = 0; k < 3 && ok; ++k)
    {
      const int g = partner[size_t(v[k])];
      const int pi = g < 0 ? -1 : pairOf(f, g);
      ok = pi >= 0 && pairs[size_t(pi)].Thin && pairs[size_t(pi)].Rep == f;
      sheets[k] = ok ? pairs[size_t(pi)].Sheet : -1;
    }
    if (!ok)
      continue;
    // A sheet that degenerates (the centres of a convex face thicker than its curvature radius
    // converge on a line: a rod, not a wall) folds or collapses its triangles: they are left out.
    {
      const V3 q0 = Add(O(size_t(v[0])), Mul(D(size_t(v[0])), 0.5 * hOf[size_t(v[0])]));
      const V3 q1 = Add(O(size_t(v[1])), Mul(D(size_t(v[1])), 0.5 * hOf[size_t(v[1])]));
      const V3 q2 = Add(O(size_t(v[2])), Mul(D(size_t(v[2])), 0.5 * hOf[size_t(v[2])]));
      const V3 n0 = Cross(Sub(O(size_t(v[1])), O(size_t(v[0]))), Sub(O(size_t(v[2])), O(size_t(v[0]))));
      const V3 n1 = Cross(Sub(q1, q0), Sub(q2, q0));
      if (Dot(n1, n0) < opt.MinimumAreaRatio * Dot(n0, n0))
      {
        ++out.CollapsedTriangles;
        continue;
      }
    }
    const int s = sheets[1] == sheets[2] ? sheets[1] : sheets[0];
    mesh.Tris.insert(mesh.Tris.end(), { emit(size_t(v[0])), emit(size_t(v[1])), emit(size_t(v[2])) });
    mesh.TriSheet.push_back(s);
    for (int k = 0; k < 3; ++k)
      used[size_t(v[k])] = 1;
  }
  // The rest of the solved samples: the other side of a sheet, or pruned (edge zones at corners
  // and junctions, the parabolic sheets of concave edges, pairs that are not thin). Connected
  // regions of pruned samples on a face are the pruned branches of the medial axis.
  std::vector<char> pruned(nV, 0);
  for (size_t v = 0; v < nV; ++v)
    if (used[v])
      (sheet[v] ? out.SheetSamples : out.ExtendedVertices) += 1;
    else if (sheet[v] && pairs[size_t(pairOf(in.FaceIds[v], in.OppositeFace[v]))].Thin)
      ++out.OppositeSideSamples;
    else if (solved(v))
    {
      ++out.PrunedSamples;
      pruned[v] = 1;
    }
  {
    std::vector<char> seen(nV, 0);
    for (size_t v = 0; v < nV; ++v)
    {
      if (!pruned[v] || seen[v])
        continue;
      ++out.PrunedBranches;
      std::vector<int> stack{ int(v) };
      seen[v] = 1;
      while (!stack.empty())
      {
        const int w = stack.back();
        stack.pop_back();
        for (int x : nbr[size_t(w)])
          if (pruned[size_t(x)] && !seen[size_t(x)])
          {
            seen[size_t(x)] = 1;
            stack.push_back(x);
          }
      }
    }
  }

  // Seams and the copies of one point on two faces of one side become one vertex.
  mesh.Merge(tol);

  // 4. Junctions. A boundary vertex of a sheet sample (not an outline: those are edge zones) is
  //    carried along its sheet, away from it, to the nearest plane of another sheet's boundary
  //    within JunctionReach thicknesses; the strips between the boundary and those points join
  //    the sheets, and coinciding junction points are merged so the sheets share the junction.
  {
    const auto edges = EdgeMap(mesh.Tris);
    const size_t n = mesh.NumberOfPoints();
    std::vector<char> onBoundary(n, 0);
    std::vector<int> sheetOf(n, -1);
    for (size_t t = 0; t < mesh.Tris.size() / 3; ++t)
      for (int k = 0; k < 3; ++k)
        sheetOf[size_t(mesh.Tris[3 * t + k])] = mesh.TriSheet[t];
    struct BoundaryEdge
    {
      int A, B, Tri; // (A, B) as in its triangle
    };
    std::vector<BoundaryEdge> boundary;
    double longest = 0.0;
    for (const auto& e : edges)
      if (e.second.size() == 1)
      {
        const int t = e.second[0];
        int a = int(e.first >> 32), b = int(e.first & 0xffffffffu);
        for (int k = 0; k < 3; ++k)
          if (mesh.Tris[3 * size_t(t) + k] == b && mesh.Tris[3 * size_t(t) + (k + 1) % 3] == a)
            std::swap(a, b);
        boundary.push_back({ a, b, t });
        onBoundary[size_t(a)] = onBoundary[size_t(b)] = 1;
        longest =
          std::max(longest, Norm(Sub(At(mesh.Points, size_t(a)), At(mesh.Points, size_t(b)))));
      }
    double hMax = 0.0;
    for (size_t i = 0; i < n; ++i)
      if (onBoundary[i])
        hMax = std::max(hMax, mesh.Thickness[i]);
    Grid grid(std::max(longest, opt.JunctionReach * hMax / 2.0));
    for (size_t i = 0; i < n; ++i)
      if (onBoundary[i])
        grid.Insert(At(mesh.Points, i), int(i));

    // Per boundary edge (a, b): the direction e away from the sheet, in its plane, and for each
    // end the nearest plane of another sheet's boundary vertex along e (the junction point).
    // Edges with a sheet sample at an end are junction edges when both ends find a plane; edges
    // of edge-zone vertices (the outline) only where they continue a junction edge in the same
    // direction (the ends of a junction line, where it meets the outline).
    struct JEdge
    {
      int A, B;
      V3 E, JA, JB;
      bool Found = false, Accepted = false;
    };
    std::vector<JEdge> jedges;
    std::vector<std::vector<int>> edgesAt(n);
    std::vector<V3> eV(n, V3{ 0.0, 0.0, 0.0 }); // per boundary vertex: the mean of its edges' e
    for (const auto& be : boundary)
    {
      JEdge je;
      je.A = be.A;
      je.B = be.B;
      const V3 pa = At(mesh.Points, size_t(je.A)), pb = At(mesh.Points, size_t(je.B));
      const V3 nrm = Unit(Add(At(mesh.Normal, size_t(je.A)), At(mesh.Normal, size_t(je.B))));
      // e: in the sheet's plane, across the edge, away from its triangle (by the centroid).
      V3 e = Unit(Cross(Sub(pb, pa), nrm));
      const int* tv = &mesh.Tris[3 * size_t(be.Tri)];
      const V3 c = Mul(Add(Add(At(mesh.Points, size_t(tv[0])), At(mesh.Points, size_t(tv[1]))),
                         At(mesh.Points, size_t(tv[2]))),
        1.0 / 3.0);
      if (Dot(e, Sub(c, Mul(Add(pa, pb), 0.5))) > 0.0)
        e = Mul(e, -1.0);
      je.E = e;
      eV[size_t(je.A)] = Add(eV[size_t(je.A)], e);
      eV[size_t(je.B)] = Add(eV[size_t(je.B)], e);
      edgesAt[size_t(je.A)].push_back(int(jedges.size()));
      edgesAt[size_t(je.B)].push_back(int(jedges.size()));
      jedges.push_back(je);
    }
    for (auto& e : eV)
      e = Unit(e);
    auto junctionPoint = [&](size_t i, const V3& e, V3& J) {
      const V3 p = At(mesh.Points, i);
      const double hp = mesh.Thickness[i];
      double bestS = std::numeric_limits<double>::infinity();
      // Both boundaries run up to R to the junction point, so they lie up to 2R apart.
      grid.QueryBall(p, 2.0 * opt.JunctionReach * std::max(hp, hMax), [&](int q) {
        if (sheetOf[size_t(q)] == sheetOf[i])
          return;
        const double R = opt.JunctionReach * std::max(hp, mesh.Thickness[size_t(q)]);
        const V3 pq = At(mesh.Points, size_t(q));
        if (Norm(Sub(pq, p)) > 2.0 * R)
          return;
        const V3 nq = At(mesh.Normal, size_t(q));
        const double denom = Dot(nq, e);
        if (std::fabs(denom) < 0.5)
          return;
        const double s = Dot(nq, Sub(pq, p)) / denom;
        if (s < -tol || s > R)
          return;
        // The other boundary must itself run towards the junction point: both sheets end short of
        // it and meet there (a boundary beside the point, or facing away, is another feature).
        const V3 qj = Sub(Add(p, Mul(e, std::max(s, 0.0))), pq);
        const double lqj = Norm(qj);
        if (lqj > R || (lqj > tol && Dot(qj, eV[size_t(q)]) < 0.5 * lqj))
          return;
        bestS = std::min(bestS, std::max(s, 0.0));
      });
      if (!std::isfinite(bestS))
        return false;
      J = Add(p, Mul(e, bestS));
      return true;
    };
    for (auto& je : jedges)
    {
      const V3 e = je.E;
      je.Found = Norm(e) > 0.0 && junctionPoint(size_t(je.A), e, je.JA) &&
        junctionPoint(size_t(je.B), e, je.JB);
      je.Accepted = je.Found && (mesh.Kind[size_t(je.A)] == 0 || mesh.Kind[size_t(je.B)] == 0);
      if (!je.Found && mesh.Kind[size_t(je.A)] == 0 && mesh.Kind[size_t(je.B)] == 0)
        ++out.OpenJunctionEdges;
    }
    for (bool grown = true; grown;)
    {
      grown = false;
      for (auto& je : jedges)
      {
        if (!je.Found || je.Accepted)
          continue;
        for (int v : { je.A, je.B })
          for (int k : edgesAt[size_t(v)])
            if (jedges[size_t(k)].Accepted && Dot(jedges[size_t(k)].E, je.E) > 0.9)
              je.Accepted = true;
        grown = grown || je.Accepted;
      }
    }
    for (const auto& je : jedges)
    {
      if (!je.Accepted)
        continue;
      const int s = sheetOf[size_t(je.A)];
      const int ja = mesh.AddPoint(je.JA, mesh.Thickness[size_t(je.A)], 2, At(mesh.Normal, size_t(je.A)));
      const int jb = mesh.AddPoint(je.JB, mesh.Thickness[size_t(je.B)], 2, At(mesh.Normal, size_t(je.B)));
      mesh.Tris.insert(mesh.Tris.end(), { je.B, je.A, ja });
      mesh.TriSheet.push_back(s);
      mesh.Tris.insert(mesh.Tris.end(), { je.B, ja, jb });
      mesh.TriSheet.push_back(s);
    }
    mesh.Merge(tol);
    mesh.ConformBoundaries(tol, std::max(longest, tol));
    mesh.Merge(tol);
    out.FoldedStripTriangles = mesh.RemoveFoldedStrips();
  }

  // 5. Results.
  out.Points = mesh.Points;
  out.Thickness = mesh.Thickness;
  out.PointKind = mesh.Kind;
  out.Triangles = mesh.Tris;
  out.TriangleSheet = mesh.TriSheet;
  for (int k : out.PointKind)
    out.JunctionVertices += k == 2 ? 1 : 0;
  for (size_t t = 0; t < out.TriangleSheet.size(); ++t)
  {
    MidsurfaceSheet& s = out.Sheets[size_t(out.TriangleSheet[t])];
    const int* v = &out.Triangles[3 * t];
    s.Area += 0.5 *
      Norm(Cross(Sub(At(out.Points, size_t(v[1])), At(out.Points, size_t(v[0]))),
        Sub(At(out.Points, size_t(v[2])), At(out.Points, size_t(v[0])))));
    s.Triangles += 1;
  }
  {
    const auto edges = EdgeMap(out.Triangles);
    for (const auto& e : edges)
    {
      if (e.second.size() < 3)
        continue;
      bool one = true;
      for (int t : e.second)
        one = one && out.TriangleSheet[size_t(t)] == out.TriangleSheet[size_t(e.second[0])];
      out.FoldEdges += one ? 1 : 0;
    }
  }
  const EdgeCounts ec = CountEdges(out.Triangles);
  out.BoundaryEdges = ec.Boundary;
  out.NonManifoldEdges = ec.NonManifold;
  out.Junctions = ec.NonManifoldChains;
  return out;
}

std::string WriteShellDeck(const Midsurface& m, const std::string& path, const ShellDeckOptions& o)
{
  if (m.Triangles.empty())
    return "the midsurface has no triangles";
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f)
    return "cannot write '" + path + "'";
  const size_t nT = m.Triangles.size() / 3;
  std::vector<double> pts = m.Points, thick = m.Thickness;
  // Midside nodes on the chords: one per edge.
  std::unordered_map<uint64_t, int> mid;
  std::vector<std::array<int, 6>> elems(nT);
  for (size_t t = 0; t < nT; ++t)
  {
    for (int k = 0; k < 3; ++k)
      elems[t][size_t(k)] = m.Triangles[3 * t + k];
    if (!o.Quadratic)
      continue;
    for (int k = 0; k < 3; ++k)
    {
      const int a = m.Triangles[3 * t + k], b = m.Triangles[3 * t + (k + 1) % 3];
      auto it = mid.find(EdgeKey(a, b));
      if (it == mid.end())
      {
        const int id = int(thick.size());
        for (int c = 0; c < 3; ++c)
          pts.push_back(0.5 * (m.Points[3 * size_t(a) + c] + m.Points[3 * size_t(b) + c]));
        thick.push_back(0.5 * (m.Thickness[size_t(a)] + m.Thickness[size_t(b)]));
        it = mid.emplace(EdgeKey(a, b), id).first;
      }
      elems[t][size_t(3 + k)] = it->second;
    }
  }
  std::fprintf(f, "** BRepThickness midsurface: %zu sheets, %zu elements, %zu nodes (docs/Midsurface.md)\n",
    m.Sheets.size(), nT, thick.size());
  std::fprintf(f, "** Units: mm, N, MPa, t/mm^3. No step: add boundary conditions and loads.\n");
  std::fprintf(f, "*NODE, NSET=NALL\n");
  for (size_t i = 0; i < thick.size(); ++i)
    std::fprintf(f, "%zu, %.14g, %.14g, %.14g\n", i + 1, pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]);
  const char* type = o.Quadratic ? "S6" : "S3";
  for (size_t s = 0; s < m.Sheets.size(); ++s)
  {
    bool any = false;
    for (size_t t = 0; t < nT; ++t)
    {
      if (size_t(m.TriangleSheet[t]) != s)
        continue;
      if (!any)
        std::fprintf(f, "*ELEMENT, TYPE=%s, ELSET=SHEET%zu\n", type, s + 1);
      any = true;
      std::fprintf(f, "%zu", t + 1);
      for (int k = 0; k < (o.Quadratic ? 6 : 3); ++k)
        std::fprintf(f, ", %d", elems[t][size_t(k)] + 1);
      std::fprintf(f, "\n");
    }
  }
  std::fprintf(f, "*ELSET, ELSET=EALL\n");
  for (size_t s = 0; s < m.Sheets.size(); ++s)
    if (m.Sheets[s].Triangles > 0)
      std::fprintf(f, "SHEET%zu\n", s + 1);
  // Nodes on free edges (with their midside nodes).
  {
    std::unordered_map<uint64_t, int> count;
    for (size_t t = 0; t < nT; ++t)
      for (int k = 0; k < 3; ++k)
        ++count[EdgeKey(m.Triangles[3 * t + k], m.Triangles[3 * t + (k + 1) % 3])];
    std::vector<int> nodes;
    for (const auto& e : count)
      if (e.second == 1)
      {
        nodes.push_back(int(e.first >> 32));
        nodes.push_back(int(e.first & 0xffffffffu));
        if (o.Quadratic)
          nodes.push_back(mid.at(e.first));
      }
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    if (!nodes.empty())
    {
      std::fprintf(f, "*NSET, NSET=NBOUNDARY\n");
      for (size_t i = 0; i < nodes.size(); ++i)
        std::fprintf(f, "%d%s", nodes[i] + 1, (i % 8 == 7 || i + 1 == nodes.size()) ? "\n" : ", ");
    }
  }
  // CalculiX reads at most 20 characters per number.
  std::fprintf(f, "*MATERIAL, NAME=%s\n*ELASTIC\n%.12g, %.12g\n*DENSITY\n%.12g\n",
    o.Material.c_str(), o.YoungsModulus, o.PoissonRatio, o.Density);
  std::vector<double> sorted(m.Thickness);
  std::fprintf(f, "*SHELL SECTION, ELSET=EALL, MATERIAL=%s, NODAL THICKNESS\n%.12g\n",
    o.Material.c_str(), Median(sorted));
  std::fprintf(f, "*NODAL THICKNESS\n");
  for (size_t i = 0; i < thick.size(); ++i)
    std::fprintf(f, "%zu, %.12g\n", i + 1, thick[i]);
  const bool ok = std::fclose(f) == 0;
  return ok ? std::string() : "error writing '" + path + "'";
}
} // namespace brt
