// Small geometry helpers shared by the midsurface and the skeleton (Filters/Core only).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <unordered_map>
#include <vector>

namespace brt::mesh
{
using V3 = std::array<double, 3>;

inline V3 At(const std::vector<double>& a, size_t i)
{
  return { a[3 * i], a[3 * i + 1], a[3 * i + 2] };
}
inline V3 Sub(const V3& a, const V3& b)
{
  return { a[0] - b[0], a[1] - b[1], a[2] - b[2] };
}
inline V3 Add(const V3& a, const V3& b)
{
  return { a[0] + b[0], a[1] + b[1], a[2] + b[2] };
}
inline V3 Mul(const V3& a, double s)
{
  return { a[0] * s, a[1] * s, a[2] * s };
}
inline double Dot(const V3& a, const V3& b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
inline V3 Cross(const V3& a, const V3& b)
{
  return { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0] };
}
inline double Norm(const V3& a)
{
  return std::sqrt(Dot(a, a));
}
inline V3 Unit(const V3& a)
{
  const double n = Norm(a);
  return n > 0.0 ? Mul(a, 1.0 / n) : V3{ 0.0, 0.0, 0.0 };
}

inline uint64_t EdgeKey(int a, int b)
{
  if (a > b)
    std::swap(a, b);
  return (uint64_t(uint32_t(a)) << 32) | uint32_t(b);
}

/// Uniform grid of points for neighbour queries.
class Grid
{
public:
  explicit Grid(double cell)
    : Cell(cell > 0.0 ? cell : 1.0)
  {
  }
  void Insert(const V3& p, int id) { this->Cells[this->Key(this->Index(p))].push_back(id); }
  /// Calls f(id) for every id in the cells that the box [lo, hi] overlaps.
  void Query(const V3& lo, const V3& hi, const std::function<void(int)>& f) const
  {
    const auto a = this->Index(lo), b = this->Index(hi);
    for (int64_t i = a[0]; i <= b[0]; ++i)
      for (int64_t j = a[1]; j <= b[1]; ++j)
        for (int64_t k = a[2]; k <= b[2]; ++k)
        {
          const auto it = this->Cells.find(this->Key({ i, j, k }));
          if (it != this->Cells.end())
            for (int id : it->second)
              f(id);
        }
  }
  void QueryBall(const V3& p, double r, const std::function<void(int)>& f) const
  {
    this->Query(Sub(p, { r, r, r }), Add(p, { r, r, r }), f);
  }

private:
  std::array<int64_t, 3> Index(const V3& p) const
  {
    return { int64_t(std::floor(p[0] / this->Cell)), int64_t(std::floor(p[1] / this->Cell)),
      int64_t(std::floor(p[2] / this->Cell)) };
  }
  static uint64_t Key(const std::array<int64_t, 3>& i)
  {
    return uint64_t(i[0]) * 73856093ULL ^ uint64_t(i[1]) * 19349663ULL ^
      uint64_t(i[2]) * 83492791ULL;
  }
  double Cell;
  std::unordered_map<uint64_t, std::vector<int>> Cells;
};

inline double Median(std::vector<double> v)
{
  if (v.empty())
    return std::numeric_limits<double>::quiet_NaN();
  const size_t m = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + m, v.end());
  return v[m];
}

/// The median of v weighted by w (each value stands for its weight, an area): the smallest value
/// at which the weights of the values up to it reach half of the total. Unlike the plain median,
/// it does not follow where a mesh happens to be dense.
inline double WeightedMedian(const std::vector<double>& v, const std::vector<double>& w)
{
  if (v.empty())
    return std::numeric_limits<double>::quiet_NaN();
  std::vector<size_t> order(v.size());
  for (size_t i = 0; i < order.size(); ++i)
    order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return v[a] < v[b]; });
  double total = 0.0;
  for (double x : w)
    total += x;
  double sum = 0.0;
  for (size_t i : order)
  {
    sum += w[i];
    if (sum >= 0.5 * total)
      return v[i];
  }
  return v[order.back()];
}

} // namespace brt::mesh
