#include "vtkThicknessFilter.h"

#include "Statistics.h"

#include "BRepFieldData.h"
#include "NativeSolver.h"
#include "OpenCLSolver.h"
#include "ResultCheck.h"
#include "Solver.h"

#include "vtkCellArray.h"
#include "vtkCommunicator.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkLogger.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkOutputWindow.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

vtkStandardNewMacro(vtkThicknessFilter);
vtkCxxSetObjectMacro(vtkThicknessFilter, Controller, vtkMultiProcessController);

namespace
{
// Residual histogram (brt::ThicknessStatistics): log10 |R| from -16 to 0 in quarter decades;
// the first bin also holds smaller residuals (and 0), the last one larger.
using Stats = brt::ThicknessStatistics;
constexpr double NaN = std::numeric_limits<double>::quiet_NaN();

std::string Lower(std::string s)
{
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

double Seconds(std::chrono::steady_clock::time_point t0)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

template <class ArrayT>
ArrayT* NewColumn(vtkTable* t, const char* name)
{
  vtkNew<ArrayT> a;
  a->SetName(name);
  t->AddColumn(a);
  return a;
}

} // namespace

struct vtkThicknessFilter::Internals
{
  // The last solve, kept while the input and the solver settings stay the same, so that
  // changing the Summary's limits does not solve again.
  std::string Key;
  std::vector<brt::SampleResult> Results;
  std::vector<double> Ray; ///< per sample, with Method SPHERE_AND_RAY: the ray thickness (NaN: no hit)
  /// Per sample, with Measure THICKNESS_AND_GAP: the exterior gap's sphere, and 1 where the gap is
  /// infinite (no wall faces the sample).
  std::vector<brt::SampleResult> Gap;
  std::vector<unsigned char> GapInfinite;
  std::vector<double> Areas; ///< per sample (mesh vertex): a third of its triangles' area
  double PrepareSeconds = 0.0, SolveSeconds = 0.0;
  size_t S1Points = 0;
  std::string DeviceUsed;
  std::string LengthUnit = "mm", SourceFile;
  std::vector<int> FaceSolid; ///< per face of the B-Rep: its solid (the per-solid table)
  int Solids = 0;
  // The OpenCL solver (its built kernel) stays while the device and the precision do.
  std::unique_ptr<brt::OpenCLSolver> CL;
  std::string CLKey;
};

vtkThicknessFilter::vtkThicknessFilter()
  : Internal(new Internals)
{
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(7);
  this->SetProgressText("B-Rep Thickness");
  this->SetDevice("auto");
  this->SetController(vtkMultiProcessController::GetGlobalController());
}

vtkThicknessFilter::~vtkThicknessFilter()
{
  this->SetDevice(nullptr);
  this->SetController(nullptr);
}

const char* vtkThicknessFilter::GetDeviceUsed() const
{
  return this->Internal->DeviceUsed.c_str();
}

int vtkThicknessFilter::FillOutputPortInformation(int port, vtkInformation* info)
{
  if (port >= RESIDUALS)
  {
    info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkTable");
    return 1;
  }
  return this->Superclass::FillOutputPortInformation(port, info);
}

int vtkThicknessFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* thickness = vtkPolyData::GetData(outputVector, THICKNESS);
  vtkPolyData* medial = vtkPolyData::GetData(outputVector, MEDIAL_POINTS);
  vtkTable* residuals = vtkTable::GetData(outputVector, RESIDUALS);
  vtkTable* summary = vtkTable::GetData(outputVector, SUMMARY);
  Internals& I = *this->Internal;
  vtkMultiProcessController* ctrl =
    this->Controller && this->Controller->GetNumberOfProcesses() > 1 ? this->Controller : nullptr;
  const int rank = ctrl ? ctrl->GetLocalProcessId() : 0;

  // --- solve (local; every process goes on to the collective part, also after an error) ------
  bool ok = true;
  const vtkIdType n = input->GetNumberOfPoints();
  const bool empty = n == 0 && !brt::HasBRepFieldData(input);
  std::ostringstream keyStream;
  keyStream.precision(17);
  keyStream << input << ' ' << input->GetMTime() << ' ' << this->S1Spacing << ' '
            << this->Clearance << ' ' << this->NewtonTolerance << ' ' << this->MaxIterations << ' '
            << (this->Device ? this->Device : "") << ' ' << this->Precision << ' ' << this->Method
            << ' ' << this->Measure << ' ' << this->GapScope;
  if (empty)
  {
    // Nothing upstream (a reader that failed has already said why): empty outputs.
    I.Key.clear();
    I.Results.clear();
    I.Areas.clear();
    I.Ray.clear();
  }
  else if (keyStream.str() != I.Key)
  {
    I.Key.clear();
    try
    {
      ok = this->Solve(input);
    }
    catch (const std::exception& e)
    {
      vtkErrorMacro(<< e.what());
      ok = false;
    }
    if (ok)
      I.Key = keyStream.str();
  }
  if (!ok)
  {
    I.Results.clear();
    I.Areas.clear();
    I.Ray.clear();
  }

  // --- local statistics ------------------------------------------------------------------------
  const std::vector<brt::SampleResult>& R = I.Results;
  const std::vector<double>& area = I.Areas;
  // Measure Gap: R holds the gap's spheres (Solve), an infinite gap as a failed sample; Method Ray:
  // R holds the ray thickness. Either way there are no thickness spheres, no edge zones.
  const bool gapOnly = this->Measure == GAP;
  const bool rayOnly = this->Method == RAY && !gapOnly;
  const bool noSpheres = rayOnly || gapOnly;
  // Edge zones and classes: from the sample points and the spheres, without solving again.
  std::vector<unsigned char> zone(R.size(), 0);
  std::vector<double> angle(R.size(), NaN);
  std::vector<int> sampleFace(R.size(), -1), sampleSolid(R.size(), -1);
  vtkDataArray* faceIds = input->GetPointData()->GetArray("FaceId");
  for (size_t i = 0; i < R.size(); ++i)
  {
    double O[3];
    input->GetPoint(static_cast<vtkIdType>(i), O);
    angle[i] = noSpheres ? NaN : brt::ContactAngle(O, R[i]);
    zone[i] = !noSpheres && brt::IsEdgeZone(O, R[i], this->EdgeZoneAngle) ? 1 : 0;
    const int f =
      faceIds ? static_cast<int>(faceIds->GetComponent(static_cast<vtkIdType>(i), 0)) : -1;
    sampleFace[i] = f;
    sampleSolid[i] = f >= 0 && f < static_cast<int>(I.FaceSolid.size()) ? I.FaceSolid[f] : -1;
  }
  const bool countZones = this->CountEdgeZones != 0;
  Stats stats =
    Accumulate(R, area, this->MinimumThickness, this->MaximumThickness, &zone, countZones);
  // Per solid and per face. Every process holds the whole B-Rep, so the group counts agree.
  int faceCount = static_cast<int>(I.FaceSolid.size()), solidCount = I.Solids;
  if (ctrl)
  {
    int v = 0;
    ctrl->AllReduce(&faceCount, &v, 1, vtkCommunicator::MAX_OP);
    faceCount = v;
    ctrl->AllReduce(&solidCount, &v, 1, vtkCommunicator::MAX_OP);
    solidCount = v;
  }
  brt::GroupStatistics perSolid = brt::AccumulateGroups(
    R, area, sampleSolid, solidCount, this->MinimumThickness, &zone, countZones);
  brt::GroupStatistics perFace = brt::AccumulateGroups(
    R, area, sampleFace, faceCount, this->MinimumThickness, &zone, countZones);
  std::vector<double>& sums = stats.Sums;
  std::vector<double>& residualHist = stats.ResidualHistogram;
  double times[2] = { ok ? I.PrepareSeconds : 0.0, ok ? I.SolveSeconds : 0.0 };
  // The ray thickness's statistics: hits, missed, area of the hits, area x thickness; min; max.
  const bool withRay = this->Method == SPHERE_AND_RAY && !gapOnly; // the ray beside the sphere
  double raySums[4] = { 0.0, 0.0, 0.0, 0.0 }, rayMin = std::numeric_limits<double>::max(),
         rayMax = -std::numeric_limits<double>::max();
  for (size_t i = 0; withRay && i < I.Ray.size() && i < area.size(); ++i)
  {
    if (!std::isfinite(I.Ray[i]))
    {
      raySums[1] += 1.0;
      continue;
    }
    raySums[0] += 1.0;
    raySums[2] += area[i];
    raySums[3] += area[i] * I.Ray[i];
    rayMin = std::min(rayMin, I.Ray[i]);
    rayMax = std::max(rayMax, I.Ray[i]);
  }
  // The exterior gap: per sample its value (+inf: infinite, with the cap; NaN: failed) and its
  // statistics (brt::AccumulateGap).
  const bool withGap = this->Measure != MEASURE_THICKNESS && I.Gap.size() == R.size();
  using GapStats = brt::GapStatistics;
  GapStats gapStats = withGap
    ? brt::AccumulateGap(I.Gap, I.GapInfinite, area, this->MinimumGap, this->MaximumGap)
    : GapStats();
  std::vector<double>& gapSums = gapStats.Sums;
  const std::vector<double>& gapValue = gapStats.Value;
  const std::vector<unsigned char>& gapInfinite = gapStats.Infinite;
  long long localCount = static_cast<long long>(R.size()), offset = 0;

  // --- collective part: every process, in the same order -------------------------------------
  int okFlag = ok ? 1 : 0;
  if (ctrl)
  {
    int all = 0;
    ctrl->AllReduce(&okFlag, &all, 1, vtkCommunicator::MIN_OP);
    okFlag = all;
    std::vector<double> buffer(sums.size());
    ctrl->AllReduce(sums.data(), buffer.data(), static_cast<vtkIdType>(sums.size()),
      vtkCommunicator::SUM_OP);
    sums.swap(buffer);
    buffer.resize(residualHist.size());
    ctrl->AllReduce(residualHist.data(), buffer.data(),
      static_cast<vtkIdType>(residualHist.size()), vtkCommunicator::SUM_OP);
    residualHist.swap(buffer);
    double v = 0.0;
    ctrl->AllReduce(&stats.Min, &v, 1, vtkCommunicator::MIN_OP);
    stats.Min = v;
    ctrl->AllReduce(&stats.Max, &v, 1, vtkCommunicator::MAX_OP);
    stats.Max = v;
    double rs[4];
    ctrl->AllReduce(raySums, rs, 4, vtkCommunicator::SUM_OP);
    std::copy(rs, rs + 4, raySums);
    std::vector<double> gs(gapSums.size());
    ctrl->AllReduce(gapSums.data(), gs.data(), static_cast<vtkIdType>(gs.size()),
      vtkCommunicator::SUM_OP);
    gapSums.swap(gs);
    ctrl->AllReduce(&gapStats.Min, &v, 1, vtkCommunicator::MIN_OP);
    gapStats.Min = v;
    ctrl->AllReduce(&gapStats.Max, &v, 1, vtkCommunicator::MAX_OP);
    gapStats.Max = v;
    ctrl->AllReduce(&rayMin, &v, 1, vtkCommunicator::MIN_OP);
    rayMin = v;
    ctrl->AllReduce(&rayMax, &v, 1, vtkCommunicator::MAX_OP);
    rayMax = v;
    double t[2];
    ctrl->AllReduce(times, t, 2, vtkCommunicator::MAX_OP);
    times[0] = t[0];
    times[1] = t[1];
    for (brt::GroupStatistics* g : { &perSolid, &perFace })
    {
      std::vector<double> b(g->Sums.size());
      ctrl->AllReduce(g->Sums.data(), b.data(), static_cast<vtkIdType>(b.size()),
        vtkCommunicator::SUM_OP);
      g->Sums.swap(b);
      b.resize(g->Min.size());
      ctrl->AllReduce(g->Min.data(), b.data(), static_cast<vtkIdType>(b.size()),
        vtkCommunicator::MIN_OP);
      g->Min.swap(b);
      b.resize(g->Max.size());
      ctrl->AllReduce(g->Max.data(), b.data(), static_cast<vtkIdType>(b.size()),
        vtkCommunicator::MAX_OP);
      g->Max.swap(b);
    }
    std::vector<long long> counts(ctrl->GetNumberOfProcesses());
    ctrl->AllGather(&localCount, counts.data(), 1);
    for (int p = 0; p < rank; ++p)
      offset += counts[p];
  }
  const bool anySolved = stats.AnySolved();
  const int bins = this->HistogramBins;
  const double histMax = anySolved && stats.Max > 0.0 ? stats.Max : 1.0;
  std::vector<double> areaHist = brt::AreaHistogram(R, area, bins, histMax);
  if (ctrl)
  {
    std::vector<double> buffer(areaHist.size());
    ctrl->AllReduce(areaHist.data(), buffer.data(), bins, vtkCommunicator::SUM_OP);
    areaHist.swap(buffer);
  }
  vtkTable* histogram = vtkTable::GetData(outputVector, AREA_HISTOGRAM);
  vtkTable* solidTable = vtkTable::GetData(outputVector, PER_SOLID);
  vtkTable* faceTable = vtkTable::GetData(outputVector, PER_FACE);
  if (!okFlag)
  {
    thickness->Initialize();
    medial->Initialize();
    residuals->Initialize();
    summary->Initialize();
    histogram->Initialize();
    solidTable->Initialize();
    faceTable->Initialize();
    return 1;
  }

  // --- port 0: the mesh with the thickness arrays ----------------------------------------------
  thickness->ShallowCopy(input);
  auto pointArray = [&](auto array, const char* name, int comps) {
    array->SetName(name);
    array->SetNumberOfComponents(comps);
    array->SetNumberOfTuples(static_cast<vtkIdType>(R.size()));
    thickness->GetPointData()->AddArray(array);
    return array;
  };
  vtkNew<vtkDoubleArray> thick, radius, centre, foot, residual;
  vtkNew<vtkIntArray> type, reason, iterations, opposite, sampleClass, solidId;
  vtkNew<vtkDoubleArray> contactAngle;
  vtkNew<vtkUnsignedCharArray> edgeZone;
  pointArray(thick.Get(), "Thickness", 1);
  pointArray(radius.Get(), "Radius", 1);
  pointArray(centre.Get(), "SphereCenter", 3);
  pointArray(foot.Get(), "FootPoint", 3);
  pointArray(type.Get(), "ContactType", 1);
  pointArray(reason.Get(), "FailReason", 1);
  pointArray(residual.Get(), "Residual", 1);
  pointArray(iterations.Get(), "Iterations", 1);
  pointArray(opposite.Get(), "OppositeFaceId", 1);
  pointArray(contactAngle.Get(), "ContactAngle", 1);
  pointArray(edgeZone.Get(), "EdgeZone", 1);
  pointArray(sampleClass.Get(), "ThicknessClass", 1);
  pointArray(solidId.Get(), "SolidId", 1);
  vtkNew<vtkDoubleArray> rayThick;
  if (withRay || rayOnly)
  {
    pointArray(rayThick.Get(), "RayThickness", 1);
    for (size_t i = 0; i < R.size(); ++i)
      rayThick->SetValue(static_cast<vtkIdType>(i), i < I.Ray.size() ? I.Ray[i] : NaN);
  }
  if (withGap)
  {
    vtkNew<vtkDoubleArray> gap, gapCentre;
    vtkNew<vtkIntArray> gapType, gapReason;
    vtkNew<vtkUnsignedCharArray> gapInf;
    pointArray(gap.Get(), "Gap", 1);
    pointArray(gapInf.Get(), "GapInfinite", 1);
    pointArray(gapType.Get(), "GapContactType", 1);
    pointArray(gapReason.Get(), "GapFailReason", 1);
    pointArray(gapCentre.Get(), "GapSphereCenter", 3);
    for (size_t i = 0; i < R.size(); ++i)
    {
      const vtkIdType id = static_cast<vtkIdType>(i);
      const brt::SampleResult& g = I.Gap[i];
      const bool finite = std::isfinite(gapValue[i]);
      gap->SetValue(id, gapValue[i]);
      gapInf->SetValue(id, gapInfinite[i]);
      gapType->SetValue(id, finite ? static_cast<int>(g.Type) : 0);
      // An infinite gap is not a failure: reason 0 unless the solve failed otherwise.
      gapReason->SetValue(id, gapInfinite[i] ? 0 : static_cast<int>(g.Reason));
      for (int k = 0; k < 3; ++k)
        gapCentre->SetComponent(id, k, finite ? g.Center[k] : NaN);
    }
  }
  vtkNew<vtkPoints> centres;
  centres->SetDataTypeToDouble();
  vtkNew<vtkDoubleArray> mRadius, mThick, mAngle;
  vtkNew<vtkIntArray> mType, mFace;
  vtkNew<vtkUnsignedCharArray> mZone;
  mAngle->SetName("ContactAngle");
  mZone->SetName("EdgeZone");
  vtkNew<vtkIdTypeArray> mId;
  mRadius->SetName("Radius");
  mThick->SetName("Thickness");
  mType->SetName("ContactType");
  mFace->SetName("FaceId");
  mId->SetName("SampleId");
  for (size_t i = 0; i < R.size(); ++i)
  {
    const brt::SampleResult& r = R[i];
    const vtkIdType id = static_cast<vtkIdType>(i);
    const bool solved = r.Type != brt::ContactType::Failed;
    thick->SetValue(id, solved ? r.Thickness : NaN);
    radius->SetValue(id, solved ? r.Radius : NaN);
    for (int k = 0; k < 3; ++k)
    {
      centre->SetComponent(id, k, solved ? r.Center[k] : NaN);
      foot->SetComponent(id, k, solved ? r.Foot[k] : NaN);
    }
    type->SetValue(id, static_cast<int>(r.Type));
    reason->SetValue(id, static_cast<int>(r.Reason));
    residual->SetValue(id, r.Residual);
    iterations->SetValue(id, r.Iterations);
    opposite->SetValue(id, r.OppositeFace);
    contactAngle->SetValue(id, angle[i]);
    edgeZone->SetValue(id, zone[i]);
    sampleClass->SetValue(id, static_cast<int>(brt::Classify(r, zone[i] != 0,
                                this->MinimumThickness, this->MaximumThickness, countZones)));
    solidId->SetValue(id, sampleSolid[i]);
    if (!solved || noSpheres)
      continue;
    centres->InsertNextPoint(r.Center.data());
    mRadius->InsertNextValue(r.Radius);
    mThick->InsertNextValue(r.Thickness);
    mType->InsertNextValue(static_cast<int>(r.Type));
    mFace->InsertNextValue(sampleFace[i]);
    mAngle->InsertNextValue(angle[i]);
    mZone->InsertNextValue(zone[i]);
    mId->InsertNextValue(static_cast<vtkIdType>(offset) + id);
  }
  thickness->GetPointData()->SetActiveScalars("Thickness");
  if (noSpheres)
  {
    // No thickness spheres: the ray thickness (with its classes) or the gap, the failure
    // reasons and the solids.
    for (const char* name : { "Thickness", "Radius", "SphereCenter", "FootPoint", "ContactType",
           "Residual", "Iterations", "OppositeFaceId", "ContactAngle", "EdgeZone" })
      thickness->GetPointData()->RemoveArray(name);
    if (gapOnly)
    {
      thickness->GetPointData()->RemoveArray("ThicknessClass");
      thickness->GetPointData()->RemoveArray("FailReason"); // GapFailReason says it
    }
    thickness->GetPointData()->SetActiveScalars(gapOnly ? "Gap" : "RayThickness");
  }

  // --- port 1: medial points -------------------------------------------------------------------
  medial->SetPoints(centres);
  vtkNew<vtkCellArray> verts;
  const vtkIdType nm = centres->GetNumberOfPoints();
  verts->AllocateExact(nm, nm);
  for (vtkIdType i = 0; i < nm; ++i)
    verts->InsertNextCell(1, &i);
  medial->SetVerts(verts);
  medial->GetPointData()->AddArray(mRadius);
  medial->GetPointData()->AddArray(mThick);
  medial->GetPointData()->AddArray(mType);
  medial->GetPointData()->AddArray(mFace);
  medial->GetPointData()->AddArray(mAngle);
  medial->GetPointData()->AddArray(mZone);
  medial->GetPointData()->AddArray(mId);
  medial->GetPointData()->SetActiveScalars("Thickness");

  // --- port 2: residual histogram (rows on process 0 only, the others add none) ----------------
  // bin_extents is the column ParaView's charts take for X by themselves (and do not draw).
  auto* rX = NewColumn<vtkDoubleArray>(residuals, "bin_extents");
  auto* rSS = NewColumn<vtkIdTypeArray>(residuals, "SurfaceSurface");
  auto* rSE = NewColumn<vtkIdTypeArray>(residuals, "SurfaceEdge");
  auto* rSV = NewColumn<vtkIdTypeArray>(residuals, "SurfaceVertex");
  if (rank == 0 && !noSpheres)
    for (int b = 0; b < Stats::ResidualBins; ++b)
    {
      const double w = (Stats::ResidualHigh - Stats::ResidualLow) / Stats::ResidualBins;
      rX->InsertNextValue(Stats::ResidualLow + (b + 0.5) * w);
      rSS->InsertNextValue(static_cast<vtkIdType>(residualHist[1 * Stats::ResidualBins + b]));
      rSE->InsertNextValue(static_cast<vtkIdType>(residualHist[2 * Stats::ResidualBins + b]));
      rSV->InsertNextValue(static_cast<vtkIdType>(residualHist[3 * Stats::ResidualBins + b]));
    }
  vtkNew<vtkStringArray> rUnit;
  rUnit->SetName("XAxis");
  rUnit->InsertNextValue("log10 |R| (R in " + I.LengthUnit + ")");
  residuals->GetFieldData()->AddArray(rUnit);

  // --- port 3: summary -------------------------------------------------------------------------
  const std::string mm = I.LengthUnit, mm2 = I.LengthUnit + "^2";
  auto* quantity = NewColumn<vtkStringArray>(summary, "Quantity");
  auto* value = NewColumn<vtkDoubleArray>(summary, "Value");
  auto* unitColumn = NewColumn<vtkStringArray>(summary, "Unit");
  auto row = [&](const std::string& name, double v, const std::string& u = std::string()) {
    quantity->InsertNextValue(name);
    value->InsertNextValue(v);
    unitColumn->InsertNextValue(u);
  };
  const double solvedArea = sums[Stats::SolvedArea];
  const double totalArea = sums[Stats::TotalArea];
  const double minimum = this->MinimumThickness, maximum = this->MaximumThickness;
  auto share = [&](double part, double limit, double whole) {
    return limit > 0.0 && whole > 0.0 ? part / whole : NaN;
  };
  // What the limits, classes, histogram and tables measure: the sphere, or the ray (Method Ray).
  const std::string measure = gapOnly ? "Gap" : rayOnly ? "RayThickness" : "Thickness";
  if (rank == 0 && !gapOnly)
  {
    row(measure + "Min", anySolved ? stats.Min : NaN, mm);
    row(measure + "Max", anySolved ? stats.Max : NaN, mm);
    row(measure + "Mean", stats.Mean(), mm);
    // The limits: the share beyond each as the option says, with and without edge zones.
    const struct
    {
      const char *Limit, *Share;
      double Value;
      int Sum, All, Walls;
    } limits[2] = { { "MinimumThickness", "AreaShareBelowMinimum", minimum, Stats::AreaBelow,
                      Stats::AreaBelowAll, Stats::AreaBelowWalls },
      { "MaximumThickness", "AreaShareAboveMaximum", maximum, Stats::AreaAbove, Stats::AreaAboveAll,
        Stats::AreaAboveWalls } };
    for (const auto& l : limits)
    {
      row(l.Limit, l.Value, mm);
      row(l.Share, share(sums[l.Sum], l.Value, solvedArea), "fraction");
      row(std::string(l.Share) + "WithEdgeZones", share(sums[l.All], l.Value, solvedArea),
        "fraction");
      row(std::string(l.Share) + "WithoutEdgeZones", share(sums[l.Walls], l.Value, solvedArea),
        "fraction");
    }
    row("CountEdgeZones", countZones ? 1.0 : 0.0, "boolean");
    row("EdgeZoneAngle", this->EdgeZoneAngle, "degree");
    // Classes (ThicknessClass) as shares of the whole area, failed samples included.
    static const char* const classRows[brt::SampleClasses] = { "AreaShareFailed",
      "AreaShareThin", "AreaShareOk", "AreaShareThick", "AreaShareEdgeZone" };
    for (int k = 0; k < brt::SampleClasses; ++k)
      row(classRows[k], totalArea > 0.0 ? sums[Stats::ClassArea + k] / totalArea : NaN,
        "fraction");
    row("EdgeZoneArea", sums[Stats::EdgeZoneArea], mm2);
  }
  if (rank == 0)
  {
    row("TotalArea", totalArea, mm2);
    if (!gapOnly)
      row("SolvedArea", solvedArea, mm2);
    if (withRay)
    {
      row("RayThicknessMin", raySums[0] > 0.0 ? rayMin : NaN, mm);
      row("RayThicknessMax", raySums[0] > 0.0 ? rayMax : NaN, mm);
      row("RayThicknessMean", raySums[2] > 0.0 ? raySums[3] / raySums[2] : NaN, mm);
      row("RayMissed", raySums[1], "samples");
    }
    if (withGap)
    {
      const bool anyGap = gapStats.Max >= gapStats.Min;
      const double withArea = gapSums[GapStats::AreaWithGap];
      row("GapMin", anyGap ? gapStats.Min : NaN, mm);
      row("GapMax", anyGap ? gapStats.Max : NaN, mm);
      row("GapMean",
        gapSums[GapStats::FiniteArea] > 0.0
          ? gapSums[GapStats::AreaGap] / gapSums[GapStats::FiniteArea]
          : NaN,
        mm);
      row("MinimumGap", this->MinimumGap, mm);
      row("AreaShareBelowMinimumGap",
        this->MinimumGap > 0.0 && withArea > 0.0 ? gapSums[GapStats::AreaBelow] / withArea : NaN,
        "fraction");
      row("MaximumGap", this->MaximumGap, mm);
      row("AreaShareInfiniteGap",
        withArea > 0.0 ? gapSums[GapStats::InfiniteArea] / withArea : NaN, "fraction");
      row("AreaShareOnOtherSolid",
        withArea > 0.0 ? gapSums[GapStats::OtherSolidArea] / withArea : NaN, "fraction");
      row("GapFailed", gapSums[GapStats::Failed], "samples");
      row("GapScope", this->GapScope, "0 own solid, 1 all solids");
    }
    row("Samples", sums[Stats::Samples], "samples");
    if (rayOnly)
      row("RayMissed",
        sums[Stats::PerReason + static_cast<int>(brt::FailReason::NoOppositePoint)], "samples");
    else if (!gapOnly)
    {
      row("SurfaceSurface", sums[Stats::PerType + 1], "samples");
      row("SurfaceEdge", sums[Stats::PerType + 2], "samples");
      row("SurfaceVertex", sums[Stats::PerType + 3], "samples");
      row("Osculating", sums[Stats::PerType + 5], "samples");
    }
    if (!gapOnly)
      row("Failed", sums[Stats::PerType + 0], "samples");
    // One row per failure reason (brt::FailReason 1..12), named for scripts.
    static const char* const reasonRows[Stats::FailReasons] = { "", "FailedNoOppositePoint",
      "FailedNotConverged", "FailedEdgeNotConverged", "FailedNoEdge", "FailedSingular",
      "FailedLeftModel", "FailedNotMaximal", "FailedOpenShell", "FailedNonManifold",
      "FailedUnbounded", "FailedThinWall", "FailedFileGap" };
    for (int k = 1; k < Stats::FailReasons && !gapOnly; ++k)
      row(reasonRows[k], sums[Stats::PerReason + k], "samples");
    row("Solids", solidCount, "solids");
    row("Faces", faceCount, "faces");
    row("S1Points", static_cast<double>(I.S1Points), "points");
    row("PrepareSeconds", times[0], "s");
    row("SolveSeconds", times[1], "s");
    row("SolvingProcesses", sums[Stats::SolvingProcesses], "processes");
  }

  // --- port 4: the area histogram --------------------------------------------------------------
  auto* hX = NewColumn<vtkDoubleArray>(histogram, "bin_extents");
  auto* hShare = NewColumn<vtkDoubleArray>(histogram, "AreaShare");
  if (rank == 0)
    for (int b = 0; b < bins; ++b)
    {
      hX->InsertNextValue(histMax * (b + 0.5) / bins);
      hShare->InsertNextValue(solvedArea > 0.0 ? areaHist[b] / solvedArea : 0.0);
    }
  vtkNew<vtkDoubleArray> binWidth;
  binWidth->SetName("BinWidth");
  binWidth->InsertNextValue(histMax / bins);
  histogram->GetFieldData()->AddArray(binWidth);

  // --- ports 5 and 6: per solid, per face ------------------------------------------------------
  auto groupTable = [&](vtkTable* t, const brt::GroupStatistics& g, bool faces) {
    using G = brt::GroupStatistics;
    auto* idColumn = NewColumn<vtkIntArray>(t, faces ? "FaceId" : "SolidId");
    auto* solidColumn = faces ? NewColumn<vtkIntArray>(t, "SolidId") : nullptr;
    auto* nColumn = NewColumn<vtkIntArray>(t, "Samples");
    auto* fColumn = NewColumn<vtkIntArray>(t, "Failed");
    auto* aColumn = NewColumn<vtkDoubleArray>(t, "Area");
    auto* minColumn = NewColumn<vtkDoubleArray>(t, (measure + "Min").c_str());
    auto* maxColumn = NewColumn<vtkDoubleArray>(t, (measure + "Max").c_str());
    auto* meanColumn = NewColumn<vtkDoubleArray>(t, (measure + "Mean").c_str());
    auto* belowColumn = NewColumn<vtkDoubleArray>(t, "AreaShareBelowMinimum");
    auto* zoneColumn = NewColumn<vtkDoubleArray>(t, "AreaShareEdgeZone");
    if (rank != 0)
      return;
    for (int k = 0; k < g.Groups; ++k)
    {
      if (g.Get(k, G::Samples) == 0)
        continue; // a solid or face without display vertices
      const bool any = g.Max[k] >= g.Min[k];
      const double solved = g.Get(k, G::SolvedArea);
      idColumn->InsertNextValue(k);
      if (solidColumn)
        solidColumn->InsertNextValue(k < static_cast<int>(I.FaceSolid.size()) ? I.FaceSolid[k] : -1);
      nColumn->InsertNextValue(static_cast<int>(g.Get(k, G::Samples)));
      fColumn->InsertNextValue(static_cast<int>(g.Get(k, G::Failed)));
      aColumn->InsertNextValue(g.Get(k, G::TotalArea));
      minColumn->InsertNextValue(any ? g.Min[k] : NaN);
      maxColumn->InsertNextValue(any ? g.Max[k] : NaN);
      meanColumn->InsertNextValue(g.Mean(k));
      belowColumn->InsertNextValue(share(g.Get(k, G::AreaBelow), minimum, solved));
      zoneColumn->InsertNextValue(solved > 0.0 ? g.Get(k, G::EdgeZoneArea) / solved : NaN);
    }
  };
  groupTable(solidTable, perSolid, false);
  groupTable(faceTable, perFace, true);

  vtkNew<vtkStringArray> device, unit, source;
  device->SetName("Device");
  device->InsertNextValue(I.DeviceUsed);
  unit->SetName("LengthUnit");
  unit->InsertNextValue(I.LengthUnit);
  source->SetName("SourceFile");
  source->InsertNextValue(I.SourceFile);
  summary->GetFieldData()->AddArray(device);
  summary->GetFieldData()->AddArray(unit);
  summary->GetFieldData()->AddArray(source);
  for (vtkTable* t : { histogram, solidTable, faceTable })
    t->GetFieldData()->AddArray(unit);

  if (rank == 0)
  {
    // One screen for ParaView's Output Messages (and stderr in pvpython): what ran, on what, how
    // long, and the answer.
    char counts[512], answer[512];
    if (rayOnly)
      std::snprintf(counts, sizeof(counts), "%.0f samples (method Ray): %.0f rays met nothing",
        sums[Stats::Samples], sums[Stats::PerType + 0]);
    else
    {
      // The gap with all solids adds the samples on another solid (ContactType::OtherSolid).
      // Osculating spheres (ContactType::Osculating), where there are any.
      char other[96] = "";
      if (sums[Stats::PerType + 5] > 0.0)
        std::snprintf(other, sizeof(other), "%.0f osculating, ", sums[Stats::PerType + 5]);
      if (sums[Stats::PerType + 4] > 0.0)
        std::snprintf(other + std::strlen(other), sizeof(other) - std::strlen(other),
          "%.0f on another solid (gap 0), ", sums[Stats::PerType + 4]);
      std::snprintf(counts, sizeof(counts),
        "%.0f samples: %.0f surface/surface, %.0f surface/edge, %.0f surface/vertex, %s%.0f "
        "failed%s",
        sums[Stats::Samples], sums[Stats::PerType + 1], sums[Stats::PerType + 2],
        sums[Stats::PerType + 3], other, sums[Stats::PerType + 0],
        gapOnly ? " (gap: failed includes the infinite gaps)" : "");
    }
    std::snprintf(answer, sizeof(answer),
      "%s %.4g .. %.4g %s, area-weighted mean %.4g %s; edge zones %.1f%% of the area (corner "
      "angle %g deg)",
      rayOnly ? "ray thickness" : "thickness", anySolved ? stats.Min : NaN,
      anySolved ? stats.Max : NaN, mm.c_str(), stats.Mean(), mm.c_str(),
      solvedArea > 0.0 ? 100.0 * sums[Stats::EdgeZoneArea] / solvedArea : NaN,
      this->EdgeZoneAngle);
    // The limits that are set (0 is off): the share of the area beyond each; none where neither
    // is set (a share of "nan%" said nothing to the user). The gap alone has its own rows.
    std::string limitsText;
    const struct
    {
      const char* What;
      double Value;
      int Walls, All;
    } setLimits[2] = { { "below minimum", minimum, Stats::AreaBelowWalls, Stats::AreaBelowAll },
      { "above maximum", maximum, Stats::AreaAboveWalls, Stats::AreaAboveAll } };
    for (const auto& l : setLimits)
    {
      if (gapOnly || !(l.Value > 0.0))
        continue;
      char line[256];
      std::snprintf(line, sizeof(line),
        "  %s %g %s: %.2f%% of the area without edge zones, %.2f%% with them\n", l.What, l.Value,
        mm.c_str(), 100.0 * share(sums[l.Walls], l.Value, solvedArea),
        100.0 * share(sums[l.All], l.Value, solvedArea));
      limitsText += line;
    }
    if (!gapOnly && limitsText.empty())
      limitsText = "  no thickness limits set (MinimumThickness, MaximumThickness)\n";
    char text[2048];
    std::snprintf(text, sizeof(text),
      "B-Rep Thickness: %s\n  device: %s\n  %s\n  %s\n%s"
      "  prepare %.3f s, solve %.3f s\n",
      I.SourceFile.c_str(), I.DeviceUsed.c_str(), counts, answer, limitsText.c_str(), times[0],
      times[1]);
    vtkOutputWindowDisplayText(text);
  }
  return 1;
}

bool vtkThicknessFilter::Solve(vtkPolyData* input)
{
  Internals& I = *this->Internal;
  const auto t0 = std::chrono::steady_clock::now();
  const brt::BRepModel model = brt::ModelFromPolyData(input);
  I.LengthUnit = model.LengthUnit;
  I.SourceFile = model.SourceFile;
  I.FaceSolid.resize(model.Faces.size());
  I.Solids = 0;
  for (size_t f = 0; f < model.Faces.size(); ++f)
  {
    I.FaceSolid[f] = model.Faces[f].Solid;
    I.Solids = std::max(I.Solids, model.Faces[f].Solid + 1);
  }
  brt::SolverOptions options;
  options.S1Spacing = this->S1Spacing;
  options.Clearance = this->Clearance;
  options.NewtonTolerance = this->NewtonTolerance;
  options.MaxIterations = this->MaxIterations;
  options.MaxEdgeIterations = this->MaxIterations;
  // The wall partners (SolverData::WallPartners) after the device is chosen: the native
  // device's own packing of the model answers their probes, which then need none of their own.
  brt::SolverData data = brt::PrepareSolver(model, options, false);
  bool partnersBuilt = false;
  const std::vector<brt::Sample> samples = brt::SamplesFromMesh(model, data);
  I.S1Points = data.S1.size();
  I.Areas = brt::VertexAreas(model.Mesh.Points, model.Mesh.Triangles);
  this->UpdateProgress(0.05);

  // Device: "native" (the kernel source compiled for this CPU, double, every core; "reference"
  // is its old name), an OpenCL device, or "auto": the first OpenCL GPU, else native.
  const std::string device = Lower(this->Device ? this->Device : "auto");
  const bool useDouble = this->Precision == DOUBLE;
  bool native = device == "native" || device == "reference";
  if (device == "auto")
  {
    bool gpu = false;
    for (const auto& label : brt::OpenCLSolver::ListDevices())
      gpu = gpu || (label.size() >= 5 && label.compare(label.size() - 5, 5, "(GPU)") == 0);
    native = !gpu;
  }
  if (!native)
  {
    const std::string clDevice = device == "auto" ? "gpu" : device;
    const std::string clKey = clDevice + (useDouble ? " double" : " float");
    try
    {
      if (!I.CL || I.CLKey != clKey)
      {
        I.CL.reset();
        // The programs are built once per device and process; on a GPU that is the driver's
        // compiler at work for tens of seconds (docs/Solver.md, "Compile time on GPUs").
        this->SetProgressText("B-Rep Thickness: building the OpenCL programs");
        this->UpdateProgress(0.05);
        I.CL = std::make_unique<brt::OpenCLSolver>(clDevice, useDouble);
        I.CLKey = clKey;
        this->SetProgressText("B-Rep Thickness");
      }
      if (!partnersBuilt)
        brt::BuildWallPartners(model, data);
      partnersBuilt = true;
      I.CL->Upload(model, data);
    }
    catch (const brt::OpenCLError& e)
    {
      I.CL.reset();
      this->SetProgressText("B-Rep Thickness");
      if (device != "auto")
      {
        vtkErrorMacro(<< "Device '" << this->Device << "': " << e.what());
        return false;
      }
      vtkWarningMacro(<< e.what() << "\nSolving with the native CPU device instead.");
      native = true;
    }
  }
  std::unique_ptr<brt::NativeSolver> cpu;
  if (native)
  {
    // (Where OpenCL failed after its partners were made, the packing holds them already.)
    cpu = std::make_unique<brt::NativeSolver>(model, data);
    if (!partnersBuilt)
    {
      brt::BuildWallPartners(model, data, *cpu);
      cpu->SetWallPartners();
    }
  }
  I.DeviceUsed = native
    ? "native CPU (double, " + std::string(cpu->KernelBuild()) + ", " +
      std::to_string(std::max(1u, std::thread::hardware_concurrency())) + " threads)"
    : std::string("OpenCL ") + (useDouble ? "double" : "float") + ": " + I.CL->DeviceName();
  I.PrepareSeconds = Seconds(t0);

  // Progress and abort between blocks or chunks of samples (below). The gap, when asked for, is
  // the second half of the progress.
  const auto t1 = std::chrono::steady_clock::now();
  const size_t n = samples.size();
  const bool gapOnly = this->Measure == GAP;
  const bool rayOnly = this->Method == RAY && !gapOnly;
  const bool withGap = this->Measure != MEASURE_THICKNESS;
  // Progress steps of a fiftieth (at least 512 samples) on the native device, where only the
  // calling thread reports, between its blocks; an OpenCL device reports between its chunks
  // (OpenCLSolver::Solve: at least 65,536 work-items each on a GPU, 16,384 samples on a CPU
  // device; chunks of 2,048 cost PoCL a third of its rate on NIST_MBE_PMI_11's 10,644 samples).
  // Samples on open or non-manifold solids are flagged failed by CheckResults below whatever
  // the solve gives them, and theirs is the slowest solve of all (spheres that find no wall):
  // they are not solved. On a part with an open surface model beside its solid that was most of
  // the time (docs/Robustness.md).
  const std::vector<size_t> measured = brt::MeasuredSamples(model, samples);
  const size_t m = measured.size();
  const bool every = m == n;
  const size_t step = std::max<size_t>(512, (m + 49) / 50);
  auto solveAll = [&](const brt::SolverOptions& o, const std::vector<brt::Sample>& in,
                    std::vector<brt::SampleResult>& out, double from, double to, const char* what) {
    // (The native device sizes and clears the results itself where it solves every sample: a
    // clearing here first wrote the 1.4 MB of NIST_MBE_PMI_11's results once more.)
    if (!native || !every || m == 0)
      out.assign(n, brt::SampleResult());
    if (m == 0)
      return true;
    // Progress every `step` samples; CheckAbort (VTK 9.2 as bundled with ParaView 5.11) sees
    // this filter's AbortExecute (set by ParaView's Abort) and an abort upstream, and makes the
    // executive mark the outputs aborted, so that the next update solves again.
    size_t reported = 0;
    auto progress = [&](size_t done) {
      if (done < m && done - reported < step)
        return true;
      reported = done;
      this->UpdateProgress(from + (to - from) * static_cast<double>(done) / m);
      if (!this->CheckAbort())
        return true;
      vtkWarningMacro(<< what << " solve aborted after " << done << " of " << m << " samples.");
      return false;
    };
    if (native)
    {
      // One call: its threads take blocks of samples until none is left (chunks, each started
      // and waited for, cost 3-4% of the solve on the FRAMEWORK tile); the progress and the
      // abort come between the calling thread's blocks.
      return cpu->Solve(o, in, out, every ? nullptr : &measured, 0, nullptr, progress);
    }
    // One call, its progress and abort between its chunks: the device solves one chunk while
    // the host packs the next (a call per progress step left a GPU idle between them, and
    // underfilled with 16,384-sample launches).
    return I.CL->Solve(model, data, o, in, out, 0, every ? nullptr : &measured, progress);
  };
  if (rayOnly || gapOnly)
    I.Results.assign(n, brt::SampleResult()); // (solveAll sizes them where it runs on them)
  if (!rayOnly && !gapOnly &&
    !solveAll(options, samples, I.Results, 0.05, withGap ? 0.55 : 1.0, "Thickness"))
    return false;
  if (this->Method != SPHERE && !gapOnly)
  {
    // The ray thickness (the kernel source's ray_thickness) on the same device.
    if (native)
      cpu->RayThickness(samples, I.Ray);
    else
      I.CL->RayThickness(model, data, samples, I.Ray);
    this->UpdateProgress(1.0);
  }
  else
    I.Ray.clear();
  if (rayOnly)
  {
    // Method Ray: the results carry the ray thickness (a ray that meets nothing is a failed
    // sample, NoOppositePoint), so that the checks below, the classes and the tables treat it
    // like the sphere's.
    for (size_t i = 0; i < n; ++i)
    {
      brt::SampleResult& r = I.Results[i];
      if (std::isfinite(I.Ray[i]))
      {
        r.Type = brt::ContactType::SurfaceSurface;
        r.Thickness = I.Ray[i];
        r.Radius = I.Ray[i] / 2;
      }
      else
        r.Reason = brt::FailReason::NoOppositePoint;
    }
  }
  I.Gap.clear();
  I.GapInfinite.clear();
  if (withGap)
  {
    // The exterior gap (docs/Solver.md, "Exterior gap"): the same solve from the outward normal,
    // the sphere in the air. A sample that no wall faces has an infinite gap (NoOppositePoint,
    // or a sphere beyond its solid's bounding box), flagged, never a value.
    std::vector<brt::Sample> outward = samples;
    for (brt::Sample& sample : outward)
      brt::ReverseSample(sample);
    brt::SolverOptions gapOptions = options;
    gapOptions.Exterior = true;
    gapOptions.AllSolids = this->GapScope == ALL_SOLIDS;
    if (!solveAll(gapOptions, outward, I.Gap, gapOnly ? 0.05 : 0.55, 1.0, "Gap"))
      return false;
    I.GapInfinite.assign(n, 0);
    for (size_t i = 0; i < n; ++i)
      if (I.Gap[i].Type == brt::ContactType::Failed &&
        I.Gap[i].Reason == brt::FailReason::NoOppositePoint)
        I.GapInfinite[i] = 1;
    // Open shells and non-manifold solids are flagged as for the thickness; a sphere beyond its
    // solid's bounding box (Unbounded) is an open gap, not a failure.
    brt::CheckResults(model, outward, I.Gap);
    for (size_t i = 0; i < n; ++i)
      if (I.Gap[i].Reason == brt::FailReason::Unbounded)
        I.GapInfinite[i] = 1;
  }
  I.SolveSeconds = Seconds(t1);
  if (gapOnly)
  {
    // Measure Gap: the results carry the gap (an infinite gap as a failed sample), so that the
    // histogram and the tables measure the finite gaps; the gap's checks ran above.
    I.Results = I.Gap;
    return true;
  }
  // Open or non-manifold solids and impossible values are flagged, never shown as thickness.
  brt::ResultCheckSummary check = brt::CheckResults(model, samples, I.Results);
  if (check.Unbounded > 0)
  {
    // A sphere that passed through a wall below the conversion's accuracy to the solid's far
    // side says so (the kernels flag only the samples they fail; docs/Robustness.md, item 8).
    std::unique_ptr<brt::NativeSolver> local;
    const brt::NativeSolver* ns = cpu.get();
    if (!ns)
      ns = (local = std::make_unique<brt::NativeSolver>(model, data)).get();
    check.Unbounded -= brt::NameThinWalls(*ns, samples, I.Results);
  }
  if (check.OpenShell > 0)
    vtkWarningMacro(<< I.SourceFile << ": " << check.OpenShell
                    << " samples lie on open shells (no inside, no thickness): flagged failed "
                       "(FailReason 8)");
  if (check.NonManifold > 0)
    vtkWarningMacro(<< I.SourceFile << ": " << check.NonManifold
                    << " samples lie on non-manifold solids: flagged failed (FailReason 9)");
  if (check.FileGap > 0)
    vtkWarningMacro(<< I.SourceFile << ": " << check.FileGap
                    << " samples lie where the file's faces and edges miss each other (the "
                       "reader's warnings name the places): flagged failed (FailReason 12)");
  if (check.Unbounded > 0)
    vtkWarningMacro(<< I.SourceFile << ": " << check.Unbounded
                    << " samples had a thickness that was not finite or exceeded their solid's "
                       "bounding-box diagonal: flagged failed (FailReason 10)");
  const auto thin = std::count_if(I.Results.begin(), I.Results.end(),
    [](const brt::SampleResult& r) { return r.Reason == brt::FailReason::ThinWall; });
  if (thin > 0)
    vtkWarningMacro(<< I.SourceFile << ": " << thin << " samples lie on walls thinner than 4 times "
                    << "the conversion tolerance (" << 4.0 * model.Tolerance
                    << " model units), below what the conversion resolves: flagged failed "
                       "(FailReason 11). Read the model with a smaller Tolerance to measure them; "
                       "where two faces meet tangentially with material between them (a knife "
                       "edge), the wall there is thinner than any tolerance resolves, and where "
                       "a face of the file folds over at its border, its normal pointing out of "
                       "the part, no tolerance mends it.");
  return true;
}

void vtkThicknessFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "S1Spacing: " << this->S1Spacing << "\n";
  os << indent << "Clearance: " << this->Clearance << "\n";
  os << indent << "NewtonTolerance: " << this->NewtonTolerance << "\n";
  os << indent << "MaxIterations: " << this->MaxIterations << "\n";
  os << indent << "Device: " << (this->Device ? this->Device : "(none)") << "\n";
  os << indent << "Precision: " << (this->Precision == DOUBLE ? "double" : "float") << "\n";
  static const char* const methods[] = { "sphere", "sphere and ray", "ray" };
  os << indent << "Method: " << methods[this->Method] << "\n";
  os << indent << "MinimumThickness: " << this->MinimumThickness << "\n";
  os << indent << "MaximumThickness: " << this->MaximumThickness << "\n";
  os << indent << "HistogramBins: " << this->HistogramBins << "\n";
  os << indent << "Controller: " << this->Controller << "\n";
  os << indent << "DeviceUsed: " << this->Internal->DeviceUsed << "\n";
}
