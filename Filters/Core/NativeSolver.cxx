#include "NativeSolver.h"

#include "KernelData.h"
#include "KernelLanguage.h"
#include "NativeKernelWide.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace brt
{
namespace kernel
{
// The kernel source, compiled here as C++ in double (KernelLanguage.h).
#include "thickness.cl"
} // namespace kernel
static_assert(S1_SPLIT_ROOT == S1SplitRoot, "the kernel's split root marker differs from Solver.h");
// The packing (KernelData.h) and the kernel source agree on their records' sizes.
static_assert(SAMPLE_REALS == KernelSampleReals && OUT_REALS == KernelOutReals &&
    OUT_INTS == KernelOutInts && FACE_INTS == KernelFaceInts &&
    FACE_REALS == KernelFaceReals && FACE_TRIM_EDGE_GAP == KernelFaceTrimEdgeGap &&
    FACE_LOOPS_CROSS == KernelFaceLoopsCross &&
    WALL_PARTNERS == KernelWallPartners && TRIM_REALS == KernelTrimReals &&
    TRIM_LEAF == KernelTrimLeaf && PATCH_SECTOR_REALS == KernelPatchSectorReals &&
    PATCH_HULL_REALS == KernelPatchHullReals,
  "the kernel's record sizes differ from KernelData.h");

struct NativeSolver::Impl
{
  const BRepModel& Model;
  const SolverData& Data;
  KernelModel<double> K;

  Impl(const BRepModel& m, const SolverData& d, const PackOptions& pack)
    : Model(m)
    , Data(d)
    , K(PackKernelModel<double>(m, d, pack))
  {
  }

  /// The x86-64-v3 build of the kernel source runs the solve and the ray (NativeKernelWide.h).
  bool Wide = NativeKernelWide();

  int PatchCount() const { return static_cast<int>(Model.Patches.size()); }

  kernel::Model View(const KernelScalars& s) const
  {
    return KernelView<kernel::Model>(K, s, PatchCount());
  }
};

NativeSolver::NativeSolver(const BRepModel& model, const SolverData& data, const PackOptions& pack)
  : P(std::make_unique<Impl>(model, data, pack))
{
}

NativeSolver::~NativeSolver() = default;

void NativeSolver::SetWallPartners()
{
  PackWallPartners(P->Data, P->K);
}

const char* NativeSolver::KernelBuild() const
{
  return P->Wide ? "x86-64-v3" : "baseline";
}

void NativeSolver::UseBaselineBuild()
{
  P->Wide = false;
}

bool NativeSolver::Solve(const SolverOptions& options, const std::vector<Sample>& samples,
  std::vector<SampleResult>& results, const std::vector<size_t>* which, unsigned threads,
  std::vector<unsigned char>* exactPass, const std::function<bool(size_t)>& progress) const
{
  if (!which)
    results.assign(samples.size(), SampleResult());
  if (exactPass)
    exactPass->resize(samples.size(), 0);
  const size_t n = which ? which->size() : samples.size();
  if (P->Data.Nodes.empty())
  {
    for (size_t j = 0; j < n; ++j)
    {
      SampleResult& r = results[which ? (*which)[j] : j];
      r = SampleResult();
      r.Reason = FailReason::NoOppositePoint;
    }
    return true;
  }
  const KernelScalars s = GetKernelScalars<double>(P->Model, P->Data, options);
  const kernel::Model view = P->View(s);
  const KernelModel<double>& K = P->K;
#if BRT_NATIVE_WIDE
  const bool wide = P->Wide;
  const int patchCount = P->PatchCount();
#endif
  // The chains (solve_chain, ChainStarts) in SpatialOrder, in blocks of about 32 samples:
  // neighbours share the trees' nodes near them.
  const std::vector<size_t> order = SpatialOrder(samples, which);
  const int chain = ChainLength(options, false);
  const std::vector<size_t> starts = ChainStarts(samples, order, chain);
  const size_t chains = starts.size() - 1;
  return ParallelForWithProgress(chains, threads, std::max(1, 32 / chain), [&](size_t c) {
    const size_t first = starts[c], count = starts[c + 1] - first;
    double in[KernelMaxChain * KernelSampleReals], outR[KernelMaxChain * KernelOutReals];
    int faces[KernelMaxChain], outI[KernelMaxChain * KernelOutInts];
    for (size_t k = 0; k < count; ++k)
    {
      const Sample& sample = samples[order[first + k]];
      PackSample(P->Data, sample, in + KernelSampleReals * k);
      faces[k] = sample.Face;
    }
#if BRT_NATIVE_WIDE
    if (wide)
      SolveChainWide(K, s, patchCount, in, faces, static_cast<int>(count), outR, outI);
    else
#endif
      kernel::solve_chain(view, K.S1Point.data(), K.S1Face.data(), K.S1UV.data(),
        K.NodeBox.data(), K.NodeInfo.data(), in, faces, static_cast<int>(count), s.Scale,
        s.StepTol, s.NewtonTol, s.MaxIterations, s.MaxEdgeIterations, outR, outI);
    for (size_t k = 0; k < count; ++k)
    {
      const size_t i = order[first + k];
      const bool exact =
        UnpackResult(samples[i], outR + KernelOutReals * k, outI + KernelOutInts * k, results[i]);
      if (exactPass)
        (*exactPass)[i] = exact ? 1 : 0;
    }
  }, [&](size_t done) { return !progress || progress(done < chains ? starts[done] : n); });
}

namespace
{
/// A sample as the kernels take it: O as hi + lo parts relative to the model's centre, and d.
struct SampleFrame
{
  kernel::real3 Ohi, Olo, d;
};

SampleFrame Frame(const SolverData& data, const Sample& sample)
{
  double in[KernelSampleReals];
  PackSample(data, sample, in);
  return { { in[0], in[1], in[2] }, { in[3], in[4], in[5] }, { in[6], in[7], in[8] } };
}

/// A result as the kernel source's Result (foot relative to O, t at the clearance `delta`).
kernel::Result ToKernel(const Sample& s, const SampleResult& r, double delta)
{
  kernel::Result k = kernel::no_result();
  k.type = static_cast<int>(r.Type);
  k.reason = static_cast<int>(r.Reason);
  k.face = r.OppositeFace;
  k.patch = r.OppositePatch;
  k.edge = r.OppositeEdge;
  k.res = r.Residual;
  k.foot = kernel::real3{ r.Foot[0] - s.Point[0], r.Foot[1] - s.Point[1], r.Foot[2] - s.Point[2] };
  k.param = kernel::real2{ r.FootParameter[0], r.FootParameter[1] };
  const kernel::real3 d{ s.Direction[0], s.Direction[1], s.Direction[2] };
  k.t = kernel::sphere_radius(d, k.foot, delta);
  return k;
}
} // namespace

bool NativeSolver::HoldsBoundary(
  const SolverOptions& options, const Sample& sample, const SampleResult& r) const
{
  if (r.Type == ContactType::Failed || r.Type == ContactType::OtherSolid || P->Data.Nodes.empty())
    return false;
  KernelScalars s = GetKernelScalars<double>(P->Model, P->Data, options);
  s.Certify = 1;
  kernel::Model view = P->View(s);
  const SampleFrame f = Frame(P->Data, sample);
  const kernel::real3 Ohi = f.Ohi, Olo = f.Olo, d = f.d;
  // The sample's (u, v) reaches the certification as in a chain's solve (memo_own_point).
  kernel::ChainMemo memo;
  kernel::memo_clear(&memo);
  view.memo = &memo;
  kernel::memo_own_point(
    &view, &memo, sample.Face, kernel::real2{ sample.U, sample.V }, Ohi, Olo);
  kernel::PointInside inside;
  return kernel::find_point_inside(&view, sample.Face, Ohi, Olo, d, r.Radius,
           std::max(s.Clearance, s.Slack), &inside) != 0;
}

void NativeSolver::WallWithin(const std::vector<Sample>& samples, double radius,
  std::vector<double>& wall, std::vector<int>& face, unsigned threads) const
{
  wall.assign(samples.size(), std::numeric_limits<double>::quiet_NaN());
  face.assign(samples.size(), -1);
  if (!P->K.HasBoxes())
    return;
  KernelScalars s = GetKernelScalars<double>(P->Model, P->Data, SolverOptions());
  s.Certify = 1;
  const kernel::Model view = P->View(s);
  const double depth = std::max(s.Clearance, s.Slack);
  ParallelFor(samples.size(), threads, [&](size_t i) {
    const SampleFrame f = Frame(P->Data, samples[i]);
    kernel::PointInside inside;
    if (!kernel::find_point_inside(&view, samples[i].Face, f.Ohi, f.Olo, f.d, radius, depth,
          &inside))
      return;
    const double t = kernel::sphere_radius(f.d, inside.w, 0.0);
    if (t < std::numeric_limits<double>::max())
    {
      wall[i] = 2.0 * t;
      face[i] = inside.face;
    }
  });
}

double NativeSolver::ThinWallAcross(const Sample& sample) const
{
  if (P->Data.Nodes.empty())
    return std::numeric_limits<double>::infinity();
  KernelScalars s = GetKernelScalars<double>(P->Model, P->Data, SolverOptions());
  s.Certify = 1;
  const kernel::Model view = P->View(s);
  const SampleFrame f = Frame(P->Data, sample);
  const kernel::real3 Ohi = f.Ohi, Olo = f.Olo, d = f.d;
  const double t = kernel::thin_wall_across(&view, sample.Face, Ohi, Olo, d, s.Scale);
  return t < std::numeric_limits<double>::max() ? t : std::numeric_limits<double>::infinity();
}

void NativeSolver::PatchBounds(const Sample& sample, double t, int patch, double& faceBound,
  double& patchBound, double* hullBound, double* ahead) const
{
  const kernel::Model view = P->View(GetKernelScalars<double>(P->Model, P->Data, SolverOptions()));
  const SampleFrame f = Frame(P->Data, sample);
  const kernel::real3 Ohi = f.Ohi, Olo = f.Olo, d = f.d;
  const kernel::real3 mr = t * d;
  const int face = view.patchFace[patch];
  faceBound = kernel::exact_gap(&view, face, Ohi, Olo, mr, t);
  const int kind = view.faceInfo[FACE_INTS * face + 8];
  patchBound = kind == EXACT_CYLINDER ? kernel::cylinder_patch_gap(&view, patch, face, Ohi, Olo, mr, t, DBL_MAX)
    : kind == EXACT_TORUS           ? kernel::torus_patch_gap(&view, patch, face, Ohi, Olo, mr, t, DBL_MAX)
    : kind == EXACT_SPHERE          ? kernel::sphere_patch_gap(&view, patch, face, Ohi, Olo, mr, t)
                                    : -1.0;
  double far = 0.0;
  const double hull = kernel::patch_gap(&view, patch,
    kernel::anchor_minus(view.patchAnchor + 6 * patch, Ohi, Olo) - mr, mr, d, &far);
  if (hullBound)
    *hullBound = hull;
  if (ahead)
    *ahead = far;
}

double NativeSolver::FaceBound(const Sample& sample, double t, int face, double need) const
{
  const kernel::Model view = P->View(GetKernelScalars<double>(P->Model, P->Data, SolverOptions()));
  const SampleFrame f = Frame(P->Data, sample);
  const kernel::real3 mr = t * f.d;
  return kernel::plane_trim_gap(&view, face, f.Ohi, f.Olo, mr, t,
    kernel::exact_gap(&view, face, f.Ohi, f.Olo, mr, t), need);
}

void NativeSolver::Classify(int face, double u, double v, bool& inside, int& segment,
  double& parameter, double& distance) const
{
  const kernel::Model view = P->View(GetKernelScalars<double>(P->Model, P->Data, SolverOptions()));
  inside = kernel::classify(&view, face, kernel::real2{ u, v }, &segment, &parameter, &distance) != 0;
}

bool NativeSolver::InsideByCrossings(int face, double u, double v) const
{
  const kernel::Model view = P->View(GetKernelScalars<double>(P->Model, P->Data, SolverOptions()));
  return kernel::inside_by_crossings(&view, face, u, v) != 0;
}

int NativeSolver::SegmentClearOf(const std::array<double, 8>& cp, double u, double v, double r)
{
  return kernel::segment_clear_of(cp.data(), kernel::real2{ u, v }, r);
}

void NativeSolver::Polish(const SolverOptions& options, const Sample& sample, SampleResult& r) const
{
  if (r.Type == ContactType::Failed || r.Type == ContactType::OtherSolid || P->Data.Nodes.empty())
    return;
  const KernelScalars s = GetKernelScalars<double>(P->Model, P->Data, options);
  const kernel::Model view = P->View(s);
  const SampleFrame f = Frame(P->Data, sample);
  const kernel::real3 Ohi = f.Ohi, Olo = f.Olo, d = f.d;
  kernel::Result k = ToKernel(sample, r, s.Clearance);
  int iterations = 0;
  if (r.Type == ContactType::Osculating)
  {
    // An osculating sphere has no contact to polish: it is checked again in double, at its
    // double radius, as the device's finish does (brt_finish).
    const KernelModel<double>& K = P->K;
    kernel::recheck_osculating(&view, K.S1Point.data(), K.S1Face.data(), K.NodeBox.data(),
      K.NodeInfo.data(), sample.Face, kernel::real2{ sample.U, sample.V }, Ohi, Olo, d, s.Scale,
      s.NewtonTol, s.MaxIterations, s.MaxEdgeIterations, sample.Curvature[0], &iterations, &k);
  }
  else
  {
    kernel::polish_result(&view, sample.Face, Ohi, Olo, d, s.Scale, s.StepTol, s.NewtonTol,
      s.MaxIterations, s.MaxEdgeIterations, &iterations, &k);
    kernel::exact_finish(&view, sample.Face, Ohi, Olo, d, s.StepTol, &k);
    kernel::reject_contact_from_outside(&view, sample.Face, Ohi, Olo, d, s.Scale, &k);
  }
  // Back through the kernel's own output layout, so that one function reads results; a contact
  // the polish kept gets its radius from its foot in double, as brt_finish gives it.
  double outR[KernelOutReals];
  int outI[KernelOutInts];
  kernel::write_result(&k, d, r.Iterations + iterations, 0, outR, outI);
  UnpackResult(sample, outR, outI, r);
}

void NativeSolver::RayThickness(const std::vector<Sample>& samples,
  std::vector<double>& thickness, std::vector<int>* face, unsigned threads) const
{
  thickness.assign(samples.size(), std::numeric_limits<double>::quiet_NaN());
  if (face)
    face->assign(samples.size(), -1);
  if (!P->K.HasBoxes())
    return;
  KernelScalars s = GetKernelScalars<double>(P->Model, P->Data, SolverOptions());
  s.Certify = 1;
  const kernel::Model view = P->View(s);
  ParallelFor(samples.size(), threads, [&](size_t i) {
    const SampleFrame f = Frame(P->Data, samples[i]);
    const kernel::real3 Ohi = f.Ohi, Olo = f.Olo, d = f.d;
    int hit = -1;
#if BRT_NATIVE_WIDE
    const double hi[3] = { Ohi.x, Ohi.y, Ohi.z }, lo[3] = { Olo.x, Olo.y, Olo.z },
                 dir[3] = { d.x, d.y, d.z };
    const double t = P->Wide
      ? RayThicknessWide(P->K, s, P->PatchCount(), hi, lo, dir, samples[i].Face, &hit)
      : kernel::ray_thickness(&view, samples[i].Face, Ohi, Olo, d, s.StepTol, &hit);
#else
    const double t = kernel::ray_thickness(&view, samples[i].Face, Ohi, Olo, d, s.StepTol, &hit);
#endif
    if (hit >= 0 && t < std::numeric_limits<double>::max())
    {
      thickness[i] = t;
      if (face)
        (*face)[i] = hit;
    }
  });
}

double FarthestFromExactSurface(const BRepModel& model, int face, const double* points,
  size_t count)
{
  std::array<double, 12> e{};
  const int kind = PackExactSurface(model, face, { 0.0, 0.0, 0.0 }, e);
  if (kind == 0)
    return -1.0;
  double worst = 0.0;
  for (size_t i = 0; i < count; ++i)
  {
    const double* p = points + 3 * i;
    const kernel::real3 X{ p[0] - e[0], p[1] - e[1], p[2] - e[2] };
    kernel::real3 g{ 0.0, 0.0, 0.0 };
    int ok = 0;
    const double f = kernel::exact_distance(kind, e.data(), X, &g, &ok);
    if (!ok)
      return -1.0;
    worst = std::max(worst, std::fabs(f));
  }
  return worst;
}

std::size_t NameThinWalls(const NativeSolver& solver, const std::vector<Sample>& samples,
  std::vector<SampleResult>& results)
{
  std::size_t named = 0;
  for (size_t i = 0; i < samples.size() && i < results.size(); ++i)
    if (results[i].Reason == FailReason::Unbounded &&
      std::isfinite(solver.ThinWallAcross(samples[i])))
    {
      results[i].Reason = FailReason::ThinWall;
      ++named;
    }
  return named;
}

bool PatchesAreTheSurface(const BRepModel& model, int face)
{
  const Face& F = model.Faces[face];
  return !F.Rational && F.DegreeU >= 1 && F.DegreeU <= 3 && F.DegreeV >= 1 && F.DegreeV <= 3 &&
    F.MaxDeviation >= 0.0 && F.MaxDeviation <= 1e-3 * model.Tolerance;
}

bool ExactSurfaceFitsPatches(const BRepModel& model, int face)
{
  return CheckExactSurface(model, face).Kind != 0;
}

bool ExactSurfaceFitsPatches(const BRepModel& model, int face, int kind,
  const std::array<double, 12>& e, const std::array<double, 3>& c)
{
  if (kind == 0)
    return false;
  const Face& F = model.Faces[static_cast<size_t>(face)];
  const double allowed = std::max(10.0 * F.MaxDeviation, model.Tolerance);
  const double o[3] = { c[0] + e[0], c[1] + e[1], c[2] + e[2] };
  for (int p = F.FirstPatch; p < F.FirstPatch + F.PatchCount; ++p)
    for (const int i : { 0, 3, 12, 15 })
    {
      const double* q = &model.Patches[static_cast<size_t>(p)].ControlPoints[3 * i];
      const kernel::real3 X{ q[0] - o[0], q[1] - o[1], q[2] - o[2] };
      kernel::real3 g{ 0.0, 0.0, 0.0 };
      int ok = 0; // (no gradient on an axis; the distance still holds there)
      if (!(std::fabs(kernel::exact_distance(kind, e.data(), X, &g, &ok)) <= allowed))
        return false;
    }
  return true;
}

CheckedExactSurface CheckExactSurface(const BRepModel& model, int face)
{
  CheckedExactSurface s;
  s.Kind = PackExactSurface(model, face, { 0.0, 0.0, 0.0 }, s.E);
  if (s.Kind != 0 && !ExactSurfaceFitsPatches(model, face, s.Kind, s.E, { 0.0, 0.0, 0.0 }))
    s = CheckedExactSurface();
  return s;
}

bool ProjectOnExactSurface(const CheckedExactSurface& s, std::array<double, 3>& point,
  std::array<double, 3>& normal, double maxMove)
{
  if (s.Kind == 0)
    return false;
  const std::array<double, 12>& e = s.E;
  const kernel::real3 X{ point[0] - e[0], point[1] - e[1], point[2] - e[2] };
  kernel::real3 g{ 0.0, 0.0, 0.0 };
  int ok = 0;
  const double f = kernel::exact_distance(s.Kind, e.data(), X, &g, &ok);
  if (!ok || !(std::fabs(f) <= maxMove))
    return false;
  const double side = g.x * normal[0] + g.y * normal[1] + g.z * normal[2] < 0.0 ? -1.0 : 1.0;
  point = { point[0] - f * g.x, point[1] - f * g.y, point[2] - f * g.z };
  normal = { side * g.x, side * g.y, side * g.z };
  return true;
}

void SolveReference(const BRepModel& model, const SolverData& data, const SolverOptions& options,
  const std::vector<Sample>& samples, std::vector<SampleResult>& results, unsigned threads)
{
  NativeSolver(model, data).Solve(options, samples, results, nullptr, threads);
}

} // namespace brt
