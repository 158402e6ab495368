// BRepThickness: the native device. The solver's kernel source (Kernels/thickness.cl) compiled as
// C++ in double precision and run on every core: the solver's reference and the CPU device a
// machine without OpenCL runs at full speed (docs/Solver.md, "One source"). VTK-free,
// OpenCL-free.
#pragma once

#include "KernelData.h"
#include "Solver.h"

#include <array>
#include <functional>
#include <memory>
#include <cstddef>
#include <vector>

namespace brt
{

class NativeSolver
{
public:
  /// Packs the model and its solver data (KernelData.h); both must outlive this object.
  NativeSolver(
    const BRepModel& model, const SolverData& data, const PackOptions& pack = PackOptions());
  ~NativeSolver();
  NativeSolver(const NativeSolver&) = delete;
  NativeSolver& operator=(const NativeSolver&) = delete;

  /// Solves samples[i] into results[i] for every i in `which` (all samples when null; results
  /// sized to the samples first), on `threads` threads (0: one per core), the calling thread one
  /// of them, in blocks of samples taken in turn. exactPass, when given, gets 1 at i where the
  /// pass without clearance found the contact. progress, when given, is called on the calling
  /// thread between its blocks with the number of samples solved so far; returning false stops
  /// the solve (the samples not yet taken keep their results as they were). Returns false where
  /// stopped.
  bool Solve(const SolverOptions& options, const std::vector<Sample>& samples,
    std::vector<SampleResult>& results, const std::vector<size_t>* which = nullptr,
    unsigned threads = 0, std::vector<unsigned char>* exactPass = nullptr,
    const std::function<bool(size_t)>& progress = {}) const;

  /// Copies the solver data's WallPartners into the packed model: for a solver made before
  /// BuildWallPartners(model, data, *this) filled them (the filter's native device, which packs
  /// the model once for the partners' probes and the solve).
  void SetWallPartners();

  /// The build of the kernel source this solver runs: "x86-64-v3" (AVX2, BMI2; chosen where the
  /// CPU has them and the environment variable BRT_NATIVE_BASELINE is unset) or "baseline". Both
  /// give the same results bit for bit (docs/Solver.md, "The native device's instruction sets").
  const char* KernelBuild() const;
  /// Runs the baseline build even where the CPU has x86-64-v3 (for tests and comparisons).
  void UseBaselineBuild();

  /// True when a point of the trimmed faces of the sample's solid lies inside r's sphere deeper
  /// than the verification allows (the larger of `options`' clearance and twice the conversion
  /// tolerance): the certification (SolverOptions::Certify) of a result found elsewhere (the
  /// float kernels). False for a failed result.
  bool HoldsBoundary(const SolverOptions& options, const Sample& sample, const SampleResult& r) const;

  /// The distance along the sample's normal to the first point of another face of its solid
  /// within 4 conversion tolerances where the ray leaves the material (the kernels'
  /// thin_wall_across); infinity where there is none. Finite: a wall below what the conversion
  /// resolves (FailReason ThinWall).
  double ThinWallAcross(const Sample& sample) const;

  /// The certification's lower bounds of the distance from the centre of the sphere of radius t
  /// tangent at the sample to `patch` (find_point_inside in Kernels/thickness.cl): faceBound from
  /// its face's exact surface (exact_gap), patchBound from the patch's piece of a cylinder
  /// (cylinder_patch_gap) or its arc of a torus's tube (torus_patch_gap); -1 where one does not
  /// apply; *hullBound (where given) from the patch's control net (patch_gap), and *ahead its
  /// control points' farthest offset along the sample's direction from the sample. For tests
  /// against OpenCASCADE's distance to the patch.
  void PatchBounds(const Sample& sample, double t, int patch, double& faceBound,
    double& patchBound, double* hullBound = nullptr, double* ahead = nullptr) const;

  /// The certification's lower bound of the distance from the centre of the sphere of radius t
  /// tangent at the sample to `face` (find_point_inside): its exact surface's (exact_gap), and on
  /// a plane whose patches are its isometric parametrisation, where the disk in which the sphere
  /// of radius `need` meets the plane lies off the trimmed face, `need` (plane_trim_gap); -1
  /// where the face has no exact surface. For tests against OpenCASCADE's distance to the face.
  double FaceBound(const Sample& sample, double t, int face, double need) const;

  /// The kernel's point-in-face test at (u, v) on `face` (classify in Kernels/thickness.cl, the
  /// per-face segment tree included): inside, and the nearest trimming segment (-1: none), the
  /// local parameter on it and the distance. The same steps as brt::ClassifyPoint (the reader's),
  /// so the two must agree; for tests.
  void Classify(int face, double u, double v, bool& inside, int& segment, double& parameter,
    double& distance) const;

  /// The kernel's even-odd test at (u, v) on `face` (inside_by_crossings, through the per-face
  /// segment tree where the face has one); the same chords as brt::InsideByCrossings; for tests.
  bool InsideByCrossings(int face, double u, double v) const;

  /// The kernel's test that the cubic trimming segment with (u, v) control points cp lies at
  /// least r from (u, v) (segment_clear_of, the certification's trim proof on planes): 1 where
  /// proven, 0 where a point of it lies nearer or the proof did not close; for tests.
  static int SegmentClearOf(const std::array<double, 8>& cp, double u, double v, double r);

  /// Refines in double a contact found in lower precision (the float kernels), `options` being
  /// those it was found with (the clearance of its pass): the same contact's Newton from its foot
  /// (eq. 4 on its face from the foot's (u, v), or the minimum along its edge from T), then the
  /// local part of the second look (the edge, faces and vertex next to the contact), and the
  /// radius of eq. 1 at the new foot. Keeps r where that Newton fails or lands farther than the
  /// second look's reach from r's foot.
  void Polish(const SolverOptions& options, const Sample& sample, SampleResult& r) const;

  /// The ray thickness of every sample: the distance from O along the inward normal to the first
  /// point of the trimmed faces of its solid (thickness[i], NaN where the ray meets nothing: an
  /// open solid; face[i] the face hit, -1 then), on `threads` threads (0: one per core). Needs
  /// the certification's boxes (PrepareSolver builds them).
  void RayThickness(const std::vector<Sample>& samples, std::vector<double>& thickness,
    std::vector<int>* face = nullptr, unsigned threads = 0) const;

  /// For each sample, the diameter of eq. 1's sphere through the deepest point of the trimmed
  /// faces of its solid inside the sphere of radius `radius` tangent at it (the certification's
  /// query, find_point_inside, at the verification's depth), and that point's face; NaN and -1
  /// where none lies that deep. An upper bound of the thickness wherever the wall across is
  /// thinner than 2 radius: the probe of thin walls (BuildWallPartners).
  void WallWithin(const std::vector<Sample>& samples, double radius, std::vector<double>& wall,
    std::vector<int>& face, unsigned threads = 0) const;

private:
  struct Impl;
  std::unique_ptr<Impl> P;
};

/// A face's exact surface as the kernels read it (PackExactSurface about the origin). Kind 0
/// where the face has none, or where the description misses the face's own patches
/// (ExactSurfaceFitsPatches), as the packing decides.
struct CheckedExactSurface
{
  int Kind = 0;
  std::array<double, 12> E{};
};
CheckedExactSurface CheckExactSurface(const BRepModel& model, int face);

/// Moves `point`, near a face, onto the face's exact surface `s` along that surface's normal (the
/// kernel's exact_distance), and sets `normal` to the exact unit normal on the side of the given
/// one. False, and both unchanged, where s has no surface (Kind 0) or the move would exceed
/// maxMove.
bool ProjectOnExactSurface(const CheckedExactSurface& s, std::array<double, 3>& point,
  std::array<double, 3>& normal, double maxMove);

/// The largest distance of `count` points (x, y, z each) from `face`'s exact surface (the
/// kernels' exact_distance); -1 where the face has none or a point lies on its axis.
double FarthestFromExactSurface(const BRepModel& model, int face, const double* points,
  size_t count);

/// Whether face f's exact surface, as the kernels read it (PackExactSurface, exact_distance),
/// passes through its patches: every patch corner (on the face's surface within the conversion's
/// deviation) within max(10 x the face's measured deviation, the model's tolerance) of it. A
/// description the kernels misread (a cone's other nappe, a spindle torus's lemon, before either
/// was known) fails by millimetres; the packing then gives the face no exact surface, so that the
/// certification bounds it by its patches alone and the exact finish leaves it.
bool ExactSurfaceFitsPatches(const BRepModel& model, int face);
/// The same for a description already packed by PackExactSurface(model, face, c, e) (kind its
/// result), as the packing has it.
bool ExactSurfaceFitsPatches(const BRepModel& model, int face, int kind,
  const std::array<double, 12>& e, const std::array<double, 3>& c);

/// The samples CheckResults flagged Unbounded whose ray meets a wall thinner than 4 conversion
/// tolerances (NativeSolver::ThinWallAcross) get FailReason ThinWall instead: their spheres
/// passed through it to the solid's far side. Returns how many.
std::size_t NameThinWalls(const NativeSolver& solver, const std::vector<Sample>& samples,
  std::vector<SampleResult>& results);

/// Whether face f's patches are its surface: a polynomial (not rational) B-spline or Bezier
/// surface of degree 1 to 3 both ways, which the conversion splits into bicubic patches exactly
/// (knot insertion and degree elevation), and whose measured deviation says so (within a
/// thousandth of the tolerance). There O, on the face's surface, lies on its patches, and the
/// certification asks a point of O's own face to lie no deeper than another face's
/// (own_face_margin in Kernels/thickness.cl).
bool PatchesAreTheSurface(const BRepModel& model, int face);

} // namespace brt
