#include "vtkSkeletonFilter.h"

#include "BRepFieldData.h"
#include "Skeleton.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <exception>
#include <string>

vtkStandardNewMacro(vtkSkeletonFilter);

int vtkSkeletonFilter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

int vtkSkeletonFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  if (!input || input->GetNumberOfPoints() == 0)
    return 1;
  brt::MidsurfaceInput in;
  std::string missing;
  if (!brt::BRepMidsurfaceInput(input, in, missing))
  {
    vtkErrorMacro("B-Rep Skeleton: the input has no point array '"
      << missing << "'; connect port 0 of B-Rep Thickness (Measure: Thickness).");
    return 1; // one error, empty outputs (no second message from the executive)
  }
  brt::SkeletonOptions options;
  options.ClusterSize = this->ClusterSize;
  options.MinimumBranchLength = this->MinimumBranchLength;
  options.MaximumAreaRatio = this->MaximumAreaRatio;
  brt::Skeleton s;
  try
  {
    s = brt::BuildSkeleton(in, options);
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro("B-Rep Skeleton: " << e.what());
    return 1; // one error, empty outputs (no second message from the executive)
  }
  const vtkIdType n = static_cast<vtkIdType>(s.Radius.size());
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(n);
  vtkNew<vtkDoubleArray> radius;
  radius->SetName("Radius");
  radius->SetNumberOfTuples(n);
  vtkNew<vtkIntArray> samples, degree;
  samples->SetName("Samples");
  samples->SetNumberOfTuples(n);
  degree->SetName("Degree");
  degree->SetNumberOfTuples(n);
  degree->Fill(0);
  for (vtkIdType i = 0; i < n; ++i)
  {
    points->SetPoint(i, &s.Points[static_cast<size_t>(3 * i)]);
    radius->SetValue(i, s.Radius[static_cast<size_t>(i)]);
    samples->SetValue(i, s.Samples[static_cast<size_t>(i)]);
  }
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkIntArray> branch;
  branch->SetName("BranchId");
  for (size_t l = 0; l < s.Polylines.size(); ++l)
  {
    const auto& line = s.Polylines[l];
    lines->InsertNextCell(static_cast<vtkIdType>(line.size()));
    for (int v : line)
      lines->InsertCellPoint(v);
    for (size_t k = 0; k + 1 < line.size(); ++k)
    {
      degree->SetValue(line[k], degree->GetValue(line[k]) + 1);
      degree->SetValue(line[k + 1], degree->GetValue(line[k + 1]) + 1);
    }
    branch->InsertNextValue(static_cast<int>(l));
  }
  output->SetPoints(points);
  output->SetLines(lines);
  output->GetPointData()->AddArray(radius);
  output->GetPointData()->SetActiveScalars("Radius");
  output->GetPointData()->AddArray(samples);
  output->GetPointData()->AddArray(degree);
  output->GetCellData()->AddArray(branch);
  auto field = [&](const char* name, double v) {
    vtkNew<vtkDoubleArray> f;
    f->SetName(name);
    f->InsertNextValue(v);
    output->GetFieldData()->AddArray(f);
  };
  field("Branches", static_cast<double>(s.Polylines.size()));
  field("JunctionNodes", s.JunctionNodes);
  field("EndNodes", s.EndNodes);
  field("RodSamples", s.RodSamples);
  field("NoiseClusters", s.NoiseClusters);
  field("ShortCycles", s.ShortCycles);
  field("RemovedSpurs", s.RemovedSpurs);
  return 1;
}

void vtkSkeletonFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ClusterSize: " << this->ClusterSize << "\n";
  os << indent << "MinimumBranchLength: " << this->MinimumBranchLength << "\n";
  os << indent << "MaximumAreaRatio: " << this->MaximumAreaRatio << "\n";
}
