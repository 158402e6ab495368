#include "Skeleton.h"

#include "MeshGeometry.h"

#include <map>
#include <numeric>
#include <queue>
#include <set>

namespace brt
{
using namespace mesh;

Skeleton BuildSkeleton(const MidsurfaceInput& in, const SkeletonOptions& opt)
{
  CheckMidsurfaceInput(in, "BuildSkeleton");
  const size_t nV = in.Points.size() / 3, nT = in.Triangles.size() / 3;
  Skeleton out;
  auto O = [&](size_t v) { return At(in.Points, v); };
  auto centre = [&](size_t v) {
    return Add(O(v), Mul(At(in.Normals, v), -0.5 * in.Thickness[v]));
  };

  // 1. Rod samples: wall samples whose face triangles' images on the medial axis collapse.
  std::vector<char> wall(nV, 0);
  for (size_t v = 0; v < nV; ++v)
    wall[v] = std::isfinite(in.Thickness[v]) && in.Thickness[v] > 0.0 && in.ContactType[v] == 1 &&
      !in.EdgeZone[v] && in.ContactAngle[v] >= opt.SheetAngle;
  std::vector<double> ratioSum(nV, 0.0);
  std::vector<int> ratioCount(nV, 0);
  for (size_t t = 0; t < nT; ++t)
  {
    const int* v = &in.Triangles[3 * t];
    if (!wall[size_t(v[0])] || !wall[size_t(v[1])] || !wall[size_t(v[2])])
      continue;
    const V3 n0 = Cross(Sub(O(size_t(v[1])), O(size_t(v[0]))), Sub(O(size_t(v[2])), O(size_t(v[0]))));
    const V3 c0 = centre(size_t(v[0]));
    const V3 n1 = Cross(Sub(centre(size_t(v[1])), c0), Sub(centre(size_t(v[2])), c0));
    const double a0 = Norm(n0);
    if (a0 <= 0.0)
      continue;
    const double ratio = Norm(n1) / a0;
    for (int k = 0; k < 3; ++k)
    {
      ratioSum[size_t(v[k])] += ratio;
      ratioCount[size_t(v[k])] += 1;
    }
  }
  std::vector<char> rod(nV, 0);
  std::vector<double> radii;
  for (size_t v = 0; v < nV; ++v)
    if (ratioCount[v] > 0 && ratioSum[v] / ratioCount[v] < opt.MaximumAreaRatio)
    {
      rod[v] = 1;
      radii.push_back(0.5 * in.Thickness[v]);
      ++out.RodSamples;
    }
  if (radii.empty())
    return out;

  // 2. Clusters (Ferley's sample simplification): each centre joins the nearest cluster leader
  //    within ClusterSize median radii, or leads a new cluster; then too small clusters (noise).
  const double cell = opt.ClusterSize * Median(radii);
  Grid leaders(cell);
  std::vector<V3> lead;
  std::vector<int> clusterOf(nV, -1);
  std::vector<V3> sum;
  std::vector<double> rsum;
  std::vector<int> count;
  for (size_t v = 0; v < nV; ++v)
  {
    if (!rod[v])
      continue;
    const V3 c = centre(v);
    int best = -1;
    double bestD = cell;
    leaders.QueryBall(c, cell, [&](int l) {
      const double d = Norm(Sub(lead[size_t(l)], c));
      if (d <= bestD)
      {
        bestD = d;
        best = l;
      }
    });
    if (best < 0)
    {
      best = int(lead.size());
      lead.push_back(c);
      leaders.Insert(c, best);
      sum.push_back({ 0.0, 0.0, 0.0 });
      rsum.push_back(0.0);
      count.push_back(0);
    }
    clusterOf[v] = best;
    sum[size_t(best)] = Add(sum[size_t(best)], c);
    rsum[size_t(best)] += 0.5 * in.Thickness[v];
    count[size_t(best)] += 1;
  }
  const size_t nC = sum.size();
  std::vector<char> alive(nC, 1);
  for (size_t c = 0; c < nC; ++c)
    if (count[c] < opt.MinimumSamples)
    {
      alive[c] = 0;
      ++out.NoiseClusters;
    }
  std::vector<V3> pos(nC);
  std::vector<double> rad(nC);
  for (size_t c = 0; c < nC; ++c)
  {
    pos[c] = Mul(sum[c], 1.0 / count[c]);
    rad[c] = rsum[c] / count[c];
  }
  auto length = [&](int a, int b) { return Norm(Sub(pos[size_t(a)], pos[size_t(b)])); };

  // 3. Edges between clusters of neighbouring samples on the surface. Neighbouring clusters of a
  //    band of centres make small cycles: a minimum spanning forest keeps a tree, and an edge it
  //    left out comes back when its cycle is long (a ring: more than LoopLength radii).
  std::set<std::pair<int, int>> candidates;
  for (size_t t = 0; t < nT; ++t)
    for (int k = 0; k < 3; ++k)
    {
      const int a = clusterOf[size_t(in.Triangles[3 * t + k])];
      const int b = clusterOf[size_t(in.Triangles[3 * t + (k + 1) % 3])];
      if (a >= 0 && b >= 0 && a != b && alive[size_t(a)] && alive[size_t(b)])
        candidates.insert({ std::min(a, b), std::max(a, b) });
    }
  std::vector<std::pair<int, int>> sorted(candidates.begin(), candidates.end());
  std::sort(sorted.begin(), sorted.end(), [&](const auto& x, const auto& y) {
    return length(x.first, x.second) < length(y.first, y.second);
  });
  std::vector<int> parent(nC);
  std::iota(parent.begin(), parent.end(), 0);
  std::function<int(int)> find = [&](int x) {
    return parent[size_t(x)] == x ? x : parent[size_t(x)] = find(parent[size_t(x)]);
  };
  std::vector<std::set<int>> adj(nC);
  std::vector<std::pair<int, int>> left;
  for (const auto& e : sorted)
  {
    const int ra = find(e.first), rb = find(e.second);
    if (ra == rb)
    {
      left.push_back(e);
      continue;
    }
    parent[size_t(ra)] = rb;
    adj[size_t(e.first)].insert(e.second);
    adj[size_t(e.second)].insert(e.first);
  }
  const double rRef = Median(radii);
  for (const auto& e : left)
  {
    // Path length in the current graph from a to b (Dijkstra, bounded by the loop length).
    const double limit = opt.LoopLength * rRef;
    std::map<int, double> dist{ { e.first, 0.0 } };
    using QE = std::pair<double, int>;
    std::priority_queue<QE, std::vector<QE>, std::greater<QE>> queue;
    queue.push({ 0.0, e.first });
    double found = std::numeric_limits<double>::infinity();
    while (!queue.empty())
    {
      const auto [d, x] = queue.top();
      queue.pop();
      if (d > dist[x] || d > limit)
        continue;
      if (x == e.second)
      {
        found = d;
        break;
      }
      for (int w : adj[size_t(x)])
      {
        const double dw = d + length(x, w);
        auto it = dist.find(w);
        if (it == dist.end() || dw < it->second)
        {
          dist[w] = dw;
          queue.push({ dw, w });
        }
      }
    }
    if (found + length(e.first, e.second) > limit)
    {
      adj[size_t(e.first)].insert(e.second);
      adj[size_t(e.second)].insert(e.first);
    }
    else
      ++out.ShortCycles;
  }

  // 4. Spurs: a chain from a free end to a junction (degree >= 3), shorter than
  //    MinimumBranchLength radii of the junction node, is removed; repeated until none is left.
  for (bool changed = true; changed;)
  {
    changed = false;
    for (size_t e = 0; e < nC; ++e)
    {
      if (!alive[e] || adj[e].size() != 1)
        continue;
      std::vector<int> chain{ int(e) };
      int prev = -1, cur = int(e);
      double len = 0.0;
      while (adj[size_t(cur)].size() <= 2)
      {
        int next = -1;
        for (int w : adj[size_t(cur)])
          if (w != prev)
            next = w;
        if (next < 0)
          break;
        len += length(cur, next);
        prev = cur;
        cur = next;
        if (adj[size_t(cur)].size() <= 2)
          chain.push_back(cur);
      }
      if (adj[size_t(cur)].size() < 3 || len >= opt.MinimumBranchLength * rad[size_t(cur)])
        continue;
      for (int c : chain)
      {
        for (int w : adj[size_t(c)])
          adj[size_t(w)].erase(c);
        adj[size_t(c)].clear();
        alive[size_t(c)] = 0;
      }
      ++out.RemovedSpurs;
      changed = true;
    }
  }
  // 5. Junctions: where rods meet, the spheres touch more than one rod and their samples are not
  //    rod samples, so the branches end short of the junction. Free ends within JunctionReach
  //    radii of each other whose directions run towards a common point are joined there.
  {
    struct End
    {
      int Node;
      V3 P, Dir;
      double R;
    };
    std::vector<End> ends;
    for (size_t c = 0; c < nC; ++c)
      if (alive[c] && adj[c].size() == 1)
      {
        // The direction: from a few nodes back along the branch to the end.
        int prev = int(c), cur = *adj[c].begin();
        double len = length(prev, cur);
        while (adj[size_t(cur)].size() == 2 && len < 2.0 * rad[c])
        {
          int next = -1;
          for (int w : adj[size_t(cur)])
            if (w != prev)
              next = w;
          len += length(cur, next);
          prev = cur;
          cur = next;
        }
        const V3 dir = Unit(Sub(pos[c], pos[size_t(cur)]));
        if (Norm(dir) > 0.0)
          ends.push_back({ int(c), pos[c], dir, rad[c] });
      }
    std::vector<int> group(ends.size());
    std::iota(group.begin(), group.end(), 0);
    std::function<int(int)> root = [&](int x) {
      return group[size_t(x)] == x ? x : group[size_t(x)] = root(group[size_t(x)]);
    };
    for (size_t i = 0; i < ends.size(); ++i)
      for (size_t j = i + 1; j < ends.size(); ++j)
      {
        const double reach = opt.JunctionReach * std::max(ends[i].R, ends[j].R);
        const V3 ij = Sub(ends[j].P, ends[i].P);
        const double d = Norm(ij);
        // Close, and each runs towards the other's side.
        if (d <= 2.0 * reach && Dot(ends[i].Dir, ij) > 0.0 && Dot(ends[j].Dir, ij) < 0.0)
          group[size_t(root(int(i)))] = root(int(j));
      }
    // Connected components before joining: an end may meet a rod that runs on through the
    // junction (a T, or the other rod of a cross), at one of that rod's nodes.
    std::vector<int> comp(nC, -1);
    for (size_t c = 0; c < nC; ++c)
    {
      if (!alive[c] || comp[c] >= 0)
        continue;
      std::vector<int> stack{ int(c) };
      comp[c] = int(c);
      while (!stack.empty())
      {
        const int x = stack.back();
        stack.pop_back();
        for (int w : adj[size_t(x)])
          if (comp[size_t(w)] < 0)
          {
            comp[size_t(w)] = int(c);
            stack.push_back(w);
          }
      }
    }
    // The node of another component nearest to the point x, within `reach`, or -1.
    auto throughNode = [&](const V3& x, double reach, const std::set<int>& own) {
      int best = -1;
      double bestD = reach;
      for (size_t c = 0; c < nC; ++c)
        if (alive[c] && adj[c].size() >= 2 && !own.count(comp[c]))
        {
          const double d = Norm(Sub(pos[c], x));
          if (d <= bestD)
          {
            bestD = d;
            best = int(c);
          }
        }
      return best;
    };
    std::map<int, std::vector<int>> groups;
    for (size_t i = 0; i < ends.size(); ++i)
      groups[root(int(i))].push_back(int(i));
    for (const auto& g : groups)
    {
      std::set<int> own;
      for (int i : g.second)
        own.insert(comp[size_t(ends[size_t(i)].Node)]);
      if (g.second.size() == 1)
      {
        // A single end: a rod running across its direction within JunctionReach radii.
        const End& e = ends[size_t(g.second[0])];
        int best = -1;
        double bestAlong = opt.JunctionReach * 2.0 * e.R;
        for (size_t c = 0; c < nC; ++c)
        {
          if (!alive[c] || adj[c].size() < 2 || own.count(comp[c]))
            continue;
          const V3 pc = Sub(pos[c], e.P);
          const double along = Dot(pc, e.Dir);
          const double lateral = Norm(Sub(pc, Mul(e.Dir, along)));
          if (along >= 0.0 && along <= bestAlong && lateral <= std::max(rad[c], e.R))
          {
            bestAlong = along;
            best = int(c);
          }
        }
        if (best >= 0)
        {
          adj[size_t(e.Node)].insert(best);
          adj[size_t(best)].insert(e.Node);
        }
        continue;
      }
      // The point nearest to every end's line (least squares): sum (I - d d^T) (x - p) = 0.
      double A[3][3] = {}, b[3] = {}, rsumJ = 0.0;
      for (int i : g.second)
      {
        const End& e = ends[size_t(i)];
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c)
          {
            const double m = (r == c ? 1.0 : 0.0) - e.Dir[size_t(r)] * e.Dir[size_t(c)];
            A[r][c] += m;
            b[r] += m * e.P[size_t(c)];
          }
        rsumJ += e.R;
      }
      const double det = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
        A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
        A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
      V3 J{ 0.0, 0.0, 0.0 };
      if (std::fabs(det) > 1e-9)
      {
        // Cramer's rule.
        for (int k = 0; k < 3; ++k)
        {
          double M[3][3];
          for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c)
              M[r][c] = c == k ? b[r] : A[r][c];
          J[size_t(k)] = (M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) -
                           M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
                           M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0])) /
            det;
        }
      }
      else
      {
        // Collinear ends (one rod, interrupted): their mean.
        for (int i : g.second)
          J = Add(J, Mul(ends[size_t(i)].P, 1.0 / double(g.second.size())));
      }
      bool ok = true;
      for (int i : g.second)
      {
        const End& e = ends[size_t(i)];
        const double along = Dot(Sub(J, e.P), e.Dir);
        ok = ok && along >= -0.5 * e.R && Norm(Sub(J, e.P)) <= opt.JunctionReach * 2.0 * e.R;
      }
      if (!ok)
        continue;
      const int through = throughNode(J, rsumJ / double(g.second.size()), own);
      if (through >= 0)
      {
        for (int i : g.second)
        {
          adj[size_t(ends[size_t(i)].Node)].insert(through);
          adj[size_t(through)].insert(ends[size_t(i)].Node);
        }
        continue;
      }
      const int j = int(pos.size());
      pos.push_back(J);
      rad.push_back(rsumJ / double(g.second.size()));
      count.push_back(0);
      alive.push_back(1);
      adj.emplace_back();
      for (int i : g.second)
      {
        adj[size_t(ends[size_t(i)].Node)].insert(j);
        adj[size_t(j)].insert(ends[size_t(i)].Node);
      }
    }
  }
  const size_t nN = pos.size();

  // 6. Polylines: chains between nodes of degree != 2, then loops of degree-2 nodes.
  std::vector<int> nodeId(nN, -1);
  auto node = [&](int c) {
    if (nodeId[size_t(c)] < 0)
    {
      nodeId[size_t(c)] = int(out.Radius.size());
      out.Points.insert(out.Points.end(), pos[size_t(c)].begin(), pos[size_t(c)].end());
      out.Radius.push_back(rad[size_t(c)]);
      out.Samples.push_back(count[size_t(c)]);
    }
    return nodeId[size_t(c)];
  };
  std::set<std::pair<int, int>> used;
  auto walk = [&](int start, int first) {
    std::vector<int> line{ node(start) };
    int prev = start, cur = first;
    used.insert({ std::min(start, first), std::max(start, first) });
    while (true)
    {
      line.push_back(node(cur));
      if (adj[size_t(cur)].size() != 2 || cur == start)
        break;
      int next = -1;
      for (int w : adj[size_t(cur)])
        if (w != prev)
          next = w;
      if (next < 0 || used.count({ std::min(cur, next), std::max(cur, next) }))
        break;
      used.insert({ std::min(cur, next), std::max(cur, next) });
      prev = cur;
      cur = next;
    }
    out.Polylines.push_back(line);
  };
  for (size_t c = 0; c < nN; ++c)
    if (alive[c] && !adj[c].empty() && adj[c].size() != 2)
    {
      (adj[c].size() == 1 ? out.EndNodes : out.JunctionNodes) += 1;
      for (int w : adj[c])
        if (!used.count({ std::min(int(c), w), std::max(int(c), w) }))
          walk(int(c), w);
    }
  for (size_t c = 0; c < nN; ++c)
    if (alive[c] && adj[c].size() == 2)
    {
      const int w = *adj[c].begin();
      if (!used.count({ std::min(int(c), w), std::max(int(c), w) }))
        walk(int(c), w);
    }
  return out;
}
} // namespace brt
