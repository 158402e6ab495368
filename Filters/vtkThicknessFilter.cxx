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
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"
#include "vtkTable.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
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
  std::vector<double> Areas; ///< per sample (mesh vertex): a third of its triangles' area
  double PrepareSeconds = 0.0, SolveSeconds = 0.0;
  size_t S1Points = 0;
  std::string DeviceUsed;
  std::string LengthUnit = "mm", SourceFile;
  // The OpenCL solver (its built kernel) stays while the device and the precision do.
  std::unique_ptr<brt::OpenCLSolver> CL;
  std::string CLKey;
};

vtkThicknessFilter::vtkThicknessFilter()
  : Internal(new Internals)
{
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(4);
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
  if (port == RESIDUALS || port == SUMMARY)
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
            << (this->Device ? this->Device : "") << ' ' << this->Precision << ' ' << this->Method;
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
  Stats stats = Accumulate(R, area, this->MinimumThickness, this->MaximumThickness);
  std::vector<double>& sums = stats.Sums;
  std::vector<double>& residualHist = stats.ResidualHistogram;
  double times[2] = { ok ? I.PrepareSeconds : 0.0, ok ? I.SolveSeconds : 0.0 };
  // The ray thickness's statistics: hits, missed, area of the hits, area x thickness; min; max.
  const bool withRay = this->Method == SPHERE_AND_RAY;
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
    ctrl->AllReduce(&rayMin, &v, 1, vtkCommunicator::MIN_OP);
    rayMin = v;
    ctrl->AllReduce(&rayMax, &v, 1, vtkCommunicator::MAX_OP);
    rayMax = v;
    double t[2];
    ctrl->AllReduce(times, t, 2, vtkCommunicator::MAX_OP);
    times[0] = t[0];
    times[1] = t[1];
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
  if (!okFlag)
  {
    thickness->Initialize();
    medial->Initialize();
    residuals->Initialize();
    summary->Initialize();
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
  vtkNew<vtkIntArray> type, reason, iterations, opposite;
  pointArray(thick.Get(), "Thickness", 1);
  pointArray(radius.Get(), "Radius", 1);
  pointArray(centre.Get(), "SphereCenter", 3);
  pointArray(foot.Get(), "FootPoint", 3);
  pointArray(type.Get(), "ContactType", 1);
  pointArray(reason.Get(), "FailReason", 1);
  pointArray(residual.Get(), "Residual", 1);
  pointArray(iterations.Get(), "Iterations", 1);
  pointArray(opposite.Get(), "OppositeFaceId", 1);
  vtkNew<vtkDoubleArray> rayThick;
  if (withRay)
  {
    pointArray(rayThick.Get(), "RayThickness", 1);
    for (size_t i = 0; i < R.size(); ++i)
      rayThick->SetValue(static_cast<vtkIdType>(i), i < I.Ray.size() ? I.Ray[i] : NaN);
  }
  vtkNew<vtkPoints> centres;
  centres->SetDataTypeToDouble();
  vtkNew<vtkDoubleArray> mRadius, mThick;
  vtkNew<vtkIntArray> mType, mFace;
  vtkNew<vtkIdTypeArray> mId;
  mRadius->SetName("Radius");
  mThick->SetName("Thickness");
  mType->SetName("ContactType");
  mFace->SetName("FaceId");
  mId->SetName("SampleId");
  vtkDataArray* faceIds = input->GetPointData()->GetArray("FaceId");
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
    if (!solved)
      continue;
    centres->InsertNextPoint(r.Center.data());
    mRadius->InsertNextValue(r.Radius);
    mThick->InsertNextValue(r.Thickness);
    mType->InsertNextValue(static_cast<int>(r.Type));
    mFace->InsertNextValue(faceIds ? static_cast<int>(faceIds->GetComponent(id, 0)) : -1);
    mId->InsertNextValue(static_cast<vtkIdType>(offset) + id);
  }
  thickness->GetPointData()->SetActiveScalars("Thickness");
  // ParaView titles a scalar bar with the array name and its component name: "Thickness (mm)".
  const std::string unitTitle = "(" + I.LengthUnit + ")";
  thick->SetComponentName(0, unitTitle.c_str());
  if (withRay)
    rayThick->SetComponentName(0, unitTitle.c_str());
  radius->SetComponentName(0, unitTitle.c_str());

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
  medial->GetPointData()->AddArray(mId);
  medial->GetPointData()->SetActiveScalars("Thickness");

  // --- port 2: residual histogram (rows on process 0 only, the others add none) ----------------
  auto* rLow = NewColumn<vtkDoubleArray>(residuals, "Log10Stats::ResidualLower");
  auto* rHigh = NewColumn<vtkDoubleArray>(residuals, "Log10ResidualUpper");
  auto* rSS = NewColumn<vtkIdTypeArray>(residuals, "SurfaceSurface");
  auto* rSE = NewColumn<vtkIdTypeArray>(residuals, "SurfaceEdge");
  auto* rSV = NewColumn<vtkIdTypeArray>(residuals, "SurfaceVertex");
  if (rank == 0)
    for (int b = 0; b < Stats::ResidualBins; ++b)
    {
      const double w = (Stats::ResidualHigh - Stats::ResidualLow) / Stats::ResidualBins;
      rLow->InsertNextValue(Stats::ResidualLow + b * w);
      rHigh->InsertNextValue(Stats::ResidualLow + (b + 1) * w);
      rSS->InsertNextValue(static_cast<vtkIdType>(residualHist[1 * Stats::ResidualBins + b]));
      rSE->InsertNextValue(static_cast<vtkIdType>(residualHist[2 * Stats::ResidualBins + b]));
      rSV->InsertNextValue(static_cast<vtkIdType>(residualHist[3 * Stats::ResidualBins + b]));
    }

  // --- port 3: summary -------------------------------------------------------------------------
  auto* quantity = NewColumn<vtkStringArray>(summary, "Quantity");
  auto* value = NewColumn<vtkDoubleArray>(summary, "Value");
  auto* binLow = NewColumn<vtkDoubleArray>(summary, "BinLower");
  auto* binHigh = NewColumn<vtkDoubleArray>(summary, "BinUpper");
  auto row = [&](const std::string& name, double v, double lo = NaN, double hi = NaN) {
    quantity->InsertNextValue(name);
    value->InsertNextValue(v);
    binLow->InsertNextValue(lo);
    binHigh->InsertNextValue(hi);
  };
  if (rank == 0)
  {
    const double solvedArea = sums[Stats::SolvedArea];
    row("Samples", sums[Stats::Samples]);
    row("SurfaceSurface", sums[Stats::PerType + 1]);
    row("SurfaceEdge", sums[Stats::PerType + 2]);
    row("SurfaceVertex", sums[Stats::PerType + 3]);
    row("Failed", sums[Stats::PerType + 0]);
    // One row per failure reason (brt::FailReason 1..10), named for scripts.
    static const char* const reasonRows[Stats::FailReasons] = { "", "FailedNoOppositePoint",
      "FailedNotConverged", "FailedEdgeNotConverged", "FailedNoEdge", "FailedSingular",
      "FailedLeftModel", "FailedNotMaximal", "FailedOpenShell", "FailedNonManifold",
      "FailedUnbounded" };
    for (int k = 1; k < Stats::FailReasons; ++k)
      row(reasonRows[k], sums[Stats::PerReason + k]);
    row("ThicknessMin", anySolved ? stats.Min : NaN);
    row("ThicknessMax", anySolved ? stats.Max : NaN);
    row("ThicknessMean", stats.Mean());
    row("TotalArea", sums[Stats::TotalArea]);
    row("SolvedArea", solvedArea);
    row("MinimumThickness", this->MinimumThickness);
    row("AreaShareBelowMinimum",
      this->MinimumThickness > 0.0 && solvedArea > 0.0 ? sums[Stats::AreaBelow] / solvedArea : NaN);
    row("MaximumThickness", this->MaximumThickness);
    row("AreaShareAboveMaximum",
      this->MaximumThickness > 0.0 && solvedArea > 0.0 ? sums[Stats::AreaAbove] / solvedArea : NaN);
    if (withRay)
    {
      row("RayThicknessMin", raySums[0] > 0.0 ? rayMin : NaN);
      row("RayThicknessMax", raySums[0] > 0.0 ? rayMax : NaN);
      row("RayThicknessMean", raySums[2] > 0.0 ? raySums[3] / raySums[2] : NaN);
      row("RayMissed", raySums[1]);
    }
    row("S1Points", static_cast<double>(I.S1Points));
    row("PrepareSeconds", times[0]);
    row("SolveSeconds", times[1]);
    row("SolvingProcesses", sums[Stats::SolvingProcesses]);
    for (int b = 0; b < bins; ++b)
      row("AreaHistogram", solvedArea > 0.0 ? areaHist[b] / solvedArea : 0.0,
        histMax * b / bins, histMax * (b + 1) / bins);
  }
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

  if (rank == 0)
    vtkLogF(INFO,
      "vtkThicknessFilter: %s: %.0f samples on %s: %.0f surface/surface, %.0f surface/edge, %.0f "
      "surface/vertex, %.0f failed; thickness %.4g .. %.4g %s (area-weighted mean %.4g); prepare "
      "%.3f s, solve %.3f s",
      I.SourceFile.c_str(), sums[Stats::Samples], I.DeviceUsed.c_str(), sums[Stats::PerType + 1],
      sums[Stats::PerType + 2], sums[Stats::PerType + 3], sums[Stats::PerType + 0], anySolved ? stats.Min : NaN,
      anySolved ? stats.Max : NaN, I.LengthUnit.c_str(),
      stats.Mean(), times[0], times[1]);
  return 1;
}

bool vtkThicknessFilter::Solve(vtkPolyData* input)
{
  Internals& I = *this->Internal;
  const auto t0 = std::chrono::steady_clock::now();
  const brt::BRepModel model = brt::ModelFromPolyData(input);
  I.LengthUnit = model.LengthUnit;
  I.SourceFile = model.SourceFile;
  brt::SolverOptions options;
  options.S1Spacing = this->S1Spacing;
  options.Clearance = this->Clearance;
  options.NewtonTolerance = this->NewtonTolerance;
  options.MaxIterations = this->MaxIterations;
  options.MaxEdgeIterations = this->MaxIterations;
  const brt::SolverData data = brt::PrepareSolver(model, options);
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
        I.CL = std::make_unique<brt::OpenCLSolver>(clDevice, useDouble);
        I.CLKey = clKey;
      }
      I.CL->Upload(model, data);
    }
    catch (const brt::OpenCLError& e)
    {
      I.CL.reset();
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
    cpu = std::make_unique<brt::NativeSolver>(model, data);
  I.DeviceUsed = native
    ? "native CPU (double, " + std::to_string(std::max(1u, std::thread::hardware_concurrency())) +
      " threads)"
    : std::string("OpenCL ") + (useDouble ? "double" : "float") + ": " + I.CL->DeviceName();
  I.PrepareSeconds = Seconds(t0);

  // Solve in chunks: progress and abort between them.
  const auto t1 = std::chrono::steady_clock::now();
  const size_t n = samples.size();
  I.Results.assign(n, brt::SampleResult());
  const size_t chunk = std::max<size_t>(2048, (n + 49) / 50);
  for (size_t first = 0; first < n; first += chunk)
  {
    const size_t last = std::min(n, first + chunk);
    if (native)
    {
      std::vector<size_t> which(last - first);
      std::iota(which.begin(), which.end(), first);
      cpu->Solve(options, samples, I.Results, &which);
    }
    else
    {
      const std::vector<brt::Sample> part(samples.begin() + first, samples.begin() + last);
      std::vector<brt::SampleResult> out;
      I.CL->Solve(model, data, options, part, out);
      std::copy(out.begin(), out.end(), I.Results.begin() + first);
    }
    this->UpdateProgress(0.05 + 0.95 * static_cast<double>(last) / n);
    // CheckAbort (VTK 9.2 as bundled with ParaView 5.11) sees this filter's AbortExecute (set by
    // ParaView's Abort) and an abort upstream, and makes the executive mark the outputs aborted,
    // so that the next update solves again.
    if (this->CheckAbort())
    {
      vtkWarningMacro(<< "Thickness solve aborted after " << last << " of " << n << " samples.");
      return false;
    }
  }
  if (this->Method == SPHERE_AND_RAY)
  {
    // The ray thickness (the kernel source's ray_thickness) on the same device.
    if (native)
      cpu->RayThickness(samples, I.Ray);
    else
      I.CL->RayThickness(model, data, samples, I.Ray);
  }
  else
    I.Ray.clear();
  I.SolveSeconds = Seconds(t1);
  // Open or non-manifold solids and impossible values are flagged, never shown as thickness.
  const brt::ResultCheckSummary check = brt::CheckResults(model, samples, I.Results);
  if (check.OpenShell > 0)
    vtkWarningMacro(<< I.SourceFile << ": " << check.OpenShell
                    << " samples lie on open shells (no inside, no thickness): flagged failed "
                       "(FailReason 8)");
  if (check.NonManifold > 0)
    vtkWarningMacro(<< I.SourceFile << ": " << check.NonManifold
                    << " samples lie on non-manifold solids: flagged failed (FailReason 9)");
  if (check.Unbounded > 0)
    vtkWarningMacro(<< I.SourceFile << ": " << check.Unbounded
                    << " samples had a thickness that was not finite or exceeded their solid's "
                       "bounding-box diagonal: flagged failed (FailReason 10)");
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
  os << indent << "Method: " << (this->Method == SPHERE_AND_RAY ? "sphere and ray" : "sphere") << "\n";
  os << indent << "MinimumThickness: " << this->MinimumThickness << "\n";
  os << indent << "MaximumThickness: " << this->MaximumThickness << "\n";
  os << indent << "HistogramBins: " << this->HistogramBins << "\n";
  os << indent << "Controller: " << this->Controller << "\n";
  os << indent << "DeviceUsed: " << this->Internal->DeviceUsed << "\n";
}
