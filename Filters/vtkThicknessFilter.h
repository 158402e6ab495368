/**
 * @class   vtkThicknessFilter
 * @brief   Exact wall thickness of a B-Rep by maximal inscribed spheres (Lemasson et al. 2014).
 *
 * Input: the output of vtkSTEPReader (docs/DataContract.md): the display mesh, whose vertices are
 * the thickness samples, and the converted B-Rep (Bezier patches, trimming loops, edges) in its
 * field data. For every vertex O with inward normal d the filter finds the largest sphere tangent
 * to the surface at O that stays inside the solid; its diameter 2t is the thickness at O and its
 * centre a sample of the medial axis. The solve runs in OpenCL (any GPU, or the CPU through
 * PoCL) or on the native CPU device, the same solver source compiled as C++ (docs/Solver.md).
 *
 * Outputs:
 * - port 0 "Thickness": the input mesh with point arrays Thickness (2t; NaN where the sample
 *   failed), Radius, SphereCenter, FootPoint, ContactType (0 failed, 1 surface/surface,
 *   2 surface/edge, 3 surface/vertex), FailReason, Residual, Iterations, OppositeFaceId,
 *   ContactAngle, EdgeZone, ThicknessClass (brt::SampleClass: 0 failed, 1 thin, 2 ok, 3 thick,
 *   4 edge zone) and SolidId (RayThickness with the ray method).
 * - port 1 "Medial Points": one vertex per solved sample at its sphere centre, with Radius,
 *   Thickness, ContactType, ContactAngle, EdgeZone, FaceId and SampleId (the sample's index in
 *   port 0, across all pieces).
 * - port 2 "Residuals": histogram (vtkTable) of log10 |R| per contact type; its column
 *   bin_extents (the bin centres) is the X axis ParaView's charts pick by themselves.
 * - port 3 "Summary": vtkTable of Quantity / Value / Unit rows (min, max and area-weighted mean
 *   thickness, area shares per class and outside the limits with and without edge zones, counts
 *   per contact type and failure reason, times).
 * - port 4 "Area Histogram": the area share per thickness bin (bin_extents: the bin centres).
 * - port 5 "Per Solid" and port 6 "Per Face": one row per solid and per face with SolidId /
 *   FaceId, samples, failed, area, min, max and area-weighted mean thickness, area shares below
 *   MinimumThickness and in edge zones.
 *
 * Under MPI every piece solves only its own vertices against the whole B-Rep (which each piece
 * carries in its field data); the tables are reduced over the controller and filled on process 0,
 * so the gathered result equals a single-process run.
 */
#ifndef vtkThicknessFilter_h
#define vtkThicknessFilter_h

#include "BRepThicknessFiltersModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <memory> // for std::unique_ptr

class vtkMultiProcessController;

class BREPTHICKNESSFILTERS_EXPORT vtkThicknessFilter : public vtkPolyDataAlgorithm
{
public:
  static vtkThicknessFilter* New();
  vtkTypeMacro(vtkThicknessFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum OutputPorts
  {
    THICKNESS = 0,
    MEDIAL_POINTS = 1,
    RESIDUALS = 2,
    SUMMARY = 3,
    AREA_HISTOGRAM = 4,
    PER_SOLID = 5,
    PER_FACE = 6
  };

  enum PrecisionTypes
  {
    FLOAT = 0,
    DOUBLE = 1
  };

  enum MethodTypes
  {
    SPHERE = 0,       ///< the maximal inscribed sphere (Thickness and its arrays)
    SPHERE_AND_RAY = 1, ///< the sphere, and the ray thickness (RayThickness)
    RAY = 2             ///< the ray thickness alone: no spheres (docs/DataContract.md)
  };

  ///@{
  /// Spacing of the coarse sample set s1 on the patches, in model units (a third of it along the
  /// edges); 0 (default) picks 1/150 of the bounding-box diagonal on the patches and a third of
  /// 1/300 along the edges. Smaller is slower and starts each sphere nearer its answer.
  vtkSetClampMacro(S1Spacing, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(S1Spacing, double);
  ///@}

  ///@{
  /// Boundary points less than this deep inside a sphere do not limit it (model units): the
  /// sphere at a sample is the largest one tangent there that nothing enters deeper than the
  /// clearance, so patch noise and sub-tolerance steps in the CAD data do not read as walls
  /// (docs/Solver.md, step 0). Negative (default -1): twice the reader's conversion tolerance;
  /// 0: the paper's eq. 1 exactly. Next to a convex edge the thickness drops towards 0 without a
  /// clearance and stays at about the clearance with one (hole plate: thinnest sample 0.0103 mm
  /// at a clearance of 0.01 mm, 6.3e-4 mm at 0).
  vtkSetClampMacro(Clearance, double, -1.0, VTK_DOUBLE_MAX);
  vtkGetMacro(Clearance, double);
  ///@}

  ///@{
  /// Newton stops when |R| (in model units) is at most this. Default 1e-4.
  vtkSetClampMacro(NewtonTolerance, double, 1e-12, 1.0);
  vtkGetMacro(NewtonTolerance, double);
  ///@}

  ///@{
  /// Iteration cap of the surface/surface and of the surface/edge Newton. Default 50.
  vtkSetClampMacro(MaxIterations, int, 1, 10000);
  vtkGetMacro(MaxIterations, int);
  ///@}

  ///@{
  /// Where to solve: "auto" (default: the first OpenCL GPU, else the native device), "native"
  /// (the solver compiled for this CPU, double, all cores; "reference" is its old name), "gpu",
  /// "cpu" (an OpenCL device of that type, e.g. PoCL), or part of an OpenCL device or platform
  /// name. A named device that is not found is an error listing the devices.
  vtkSetStringMacro(Device);
  vtkGetStringMacro(Device);
  ///@}

  ///@{
  /// Arithmetic of the OpenCL kernels: FLOAT (default, the paper's) or DOUBLE (needs
  /// cl_khr_fp64). The native device is always double.
  vtkSetClampMacro(Precision, int, FLOAT, DOUBLE);
  vtkGetMacro(Precision, int);
  ///@}

  ///@{
  /// SPHERE (default): the maximal-sphere thickness. SPHERE_AND_RAY: also the ray thickness, the
  /// distance from each sample along its inward normal to the first point of the exact trimmed
  /// faces of its solid (point array RayThickness, NaN where the ray meets nothing; Summary rows
  /// RayThicknessMin/Max/Mean, RayMissed), on the same device as the sphere. RAY: the ray
  /// thickness alone (on ExpansionCard_SelfTapping it takes longer than the sphere); the classes, limits, histogram and tables then measure it, the
  /// sphere arrays and the medial points are absent, and a ray that meets nothing is a failed
  /// sample (FailReason 1).
  vtkSetClampMacro(Method, int, SPHERE, RAY);
  vtkGetMacro(Method, int);
  ///@}

  enum MeasureTypes
  {
    MEASURE_THICKNESS = 0, ///< the wall thickness (Method says how)
    GAP = 1,               ///< the exterior gap alone: the air between walls (arrays Gap...)
    THICKNESS_AND_GAP = 2  ///< both
  };

  enum GapScopes
  {
    OWN_SOLID = 0, ///< the gap between walls of the sample's own solid
    ALL_SOLIDS = 1 ///< and the clearance to every other solid of the file (an assembly)
  };

  ///@{
  /// MEASURE_THICKNESS (default), GAP or THICKNESS_AND_GAP: the exterior gap (docs/Solver.md, "Exterior
  /// gap"), the largest sphere tangent at each sample from outside that holds no material; its
  /// diameter is the gap. Point arrays Gap (+inf where no wall faces the sample, NaN where the
  /// solve failed), GapInfinite, GapContactType, GapFailReason, GapSphereCenter; Summary rows
  /// GapMin/Max/Mean, AreaShareBelowMinimumGap, AreaShareInfiniteGap, GapFailed. With GAP alone
  /// no thickness is solved: port 0 has the gap arrays only, the medial points and residuals are
  /// empty, and the histogram and the per-solid and per-face tables measure the finite gaps.
  vtkSetClampMacro(Measure, int, MEASURE_THICKNESS, THICKNESS_AND_GAP);
  vtkGetMacro(Measure, int);
  ///@}

  ///@{
  /// Which walls bound the gap's sphere: OWN_SOLID (default) or ALL_SOLIDS.
  vtkSetClampMacro(GapScope, int, OWN_SOLID, ALL_SOLIDS);
  vtkGetMacro(GapScope, int);
  ///@}

  ///@{
  /// Gaps wider than MaximumGap count as infinite (flagged GapInfinite; 0, the default: no cap);
  /// the Summary gives the area share with a gap below MinimumGap (0: off). Model units. Changing
  /// them does not solve again.
  vtkSetClampMacro(MaximumGap, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MaximumGap, double);
  vtkSetClampMacro(MinimumGap, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MinimumGap, double);
  ///@}

  ///@{
  /// Thickness limits for the Summary: the share of the area thinner than MinimumThickness and
  /// thicker than MaximumThickness (model units; 0 disables a limit). They do not change the
  /// solve, so changing them does not solve again.
  vtkSetClampMacro(MinimumThickness, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MinimumThickness, double);
  vtkSetClampMacro(MaximumThickness, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MaximumThickness, double);
  ///@}

  ///@{
  /// Edge zones (docs/Solver.md): a sample whose sphere touches the boundary at a contact angle
  /// (at the centre, between the sample and the contact) of at most 180 - EdgeZoneAngle degrees
  /// is bounded by a corner of at least that material angle, not by the opposite wall. Default
  /// 60: right-angled edges are corners; sharper wedges (knife edges) count as thin material.
  vtkSetClampMacro(EdgeZoneAngle, double, 0.0, 180.0);
  vtkGetMacro(EdgeZoneAngle, double);
  ///@}

  ///@{
  /// Whether edge-zone samples count against MinimumThickness and MaximumThickness (the classes
  /// and AreaShareBelowMinimum / AboveMaximum). Default off, as CAD checkers leave corners out;
  /// the Summary gives both shares either way.
  vtkSetMacro(CountEdgeZones, vtkTypeBool);
  vtkGetMacro(CountEdgeZones, vtkTypeBool);
  vtkBooleanMacro(CountEdgeZones, vtkTypeBool);
  ///@}

  ///@{
  /// Bins of the area-weighted thickness histogram (port 4; from 0 to the maximum). Default 20.
  vtkSetClampMacro(HistogramBins, int, 1, 100000);
  vtkGetMacro(HistogramBins, int);
  ///@}

  ///@{
  /// Controller for the reductions of the tables under MPI; the global controller by default.
  void SetController(vtkMultiProcessController*);
  vtkGetObjectMacro(Controller, vtkMultiProcessController);
  ///@}

  /// What the last solve ran on (e.g. "OpenCL float: Portable Computing Language: cpu-...").
  const char* GetDeviceUsed() const;

protected:
  vtkThicknessFilter();
  ~vtkThicknessFilter() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double S1Spacing = 0.0;
  double Clearance = -1.0;
  double NewtonTolerance = 1e-4;
  int MaxIterations = 50;
  char* Device = nullptr;
  int Precision = FLOAT;
  int Method = SPHERE;
  double MinimumThickness = 0.0;
  double MaximumThickness = 0.0;
  int HistogramBins = 20;
  int Measure = MEASURE_THICKNESS;
  int GapScope = OWN_SOLID;
  double MaximumGap = 0.0;
  double MinimumGap = 0.0;
  double EdgeZoneAngle = 60.0;
  vtkTypeBool CountEdgeZones = false;
  vtkMultiProcessController* Controller = nullptr;

private:
  vtkThicknessFilter(const vtkThicknessFilter&) = delete;
  void operator=(const vtkThicknessFilter&) = delete;

  /// Reads the B-Rep, prepares s1 and the BVH, picks the device and solves every vertex of
  /// `input` into Internal->Results. False after an error (reported) or an abort.
  bool Solve(vtkPolyData* input);

  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
