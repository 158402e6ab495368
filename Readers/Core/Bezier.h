// BRepThickness: evaluation of cubic Bezier curves and bicubic Bezier patches (double).
// Header-only, free of VTK and OpenCASCADE; the OpenCL kernels mirror these formulas.
#pragma once

#include "BRepModel.h"

#include <array>

namespace brt
{

/// Cubic Bernstein basis and its first two derivatives at t.
struct Bernstein3
{
  std::array<double, 4> B, D, DD;
  explicit Bernstein3(double t)
  {
    const double s = 1.0 - t;
    B = { s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t };
    D = { -3.0 * s * s, 3.0 * s * s - 6.0 * s * t, 6.0 * s * t - 3.0 * t * t, 3.0 * t * t };
    DD = { 6.0 * s, -12.0 * s + 6.0 * t, 6.0 * s - 12.0 * t, 6.0 * t };
  }
};

/// Point, first and second derivative of a cubic Bezier curve with N-dimensional control points
/// stored contiguously (cp[i*N + k]).
template <int N>
struct CurveEval
{
  std::array<double, N> P{}, D1{}, D2{};
};

template <int N>
inline CurveEval<N> EvaluateCubic(const double* cp, double t)
{
  const Bernstein3 b(t);
  CurveEval<N> e;
  for (int i = 0; i < 4; ++i)
  {
    for (int k = 0; k < N; ++k)
    {
      e.P[k] += b.B[i] * cp[i * N + k];
      e.D1[k] += b.D[i] * cp[i * N + k];
      e.D2[k] += b.DD[i] * cp[i * N + k];
    }
  }
  return e;
}

struct PatchEval
{
  std::array<double, 3> P{}, Du{}, Dv{};
  std::array<double, 3> Duu{}, Duv{}, Dvv{};
};

/// Evaluates a bicubic patch at local (s, r) in [0,1]^2: point, first and second derivatives
/// w.r.t. s and r.
inline PatchEval EvaluatePatchLocal(const std::array<double, 48>& cp, double s, double r)
{
  const Bernstein3 bu(s), bv(r);
  PatchEval e;
  for (int i = 0; i < 4; ++i)
  {
    for (int j = 0; j < 4; ++j)
    {
      const double* c = &cp[(4 * i + j) * 3];
      const double w = bu.B[i] * bv.B[j];
      const double wu = bu.D[i] * bv.B[j];
      const double wv = bu.B[i] * bv.D[j];
      const double wuu = bu.DD[i] * bv.B[j];
      const double wuv = bu.D[i] * bv.D[j];
      const double wvv = bu.B[i] * bv.DD[j];
      for (int k = 0; k < 3; ++k)
      {
        e.P[k] += w * c[k];
        e.Du[k] += wu * c[k];
        e.Dv[k] += wv * c[k];
        e.Duu[k] += wuu * c[k];
        e.Duv[k] += wuv * c[k];
        e.Dvv[k] += wvv * c[k];
      }
    }
  }
  return e;
}

/// Evaluates a patch at face parameters (u, v); derivatives are w.r.t. u and v.
inline PatchEval EvaluatePatch(const BezierPatch& patch, double u, double v)
{
  const auto& d = patch.Domain;
  const double du = d[1] - d[0], dv = d[3] - d[2];
  PatchEval e = EvaluatePatchLocal(patch.ControlPoints, (u - d[0]) / du, (v - d[2]) / dv);
  for (int k = 0; k < 3; ++k)
  {
    e.Du[k] /= du;
    e.Dv[k] /= dv;
    e.Duu[k] /= du * du;
    e.Duv[k] /= du * dv;
    e.Dvv[k] /= dv * dv;
  }
  return e;
}

/// Index of the patch of `face` whose domain contains (u, v) (clamped to the face grid).
int FindPatch(const BRepModel& model, int face, double u, double v);

} // namespace brt
