#include "vtkMaximalSpheresFilter.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkExtractSelection.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSelection.h"
#include "vtkSmartPointer.h"
#include "vtkSphereSource.h"

#include <cmath>
#include <unordered_map>

vtkStandardNewMacro(vtkMaximalSpheresFilter);

vtkMaximalSpheresFilter::vtkMaximalSpheresFilter()
{
  this->SetNumberOfInputPorts(2);
}

void vtkMaximalSpheresFilter::AddSampleId(vtkIdType id)
{
  this->SampleIds.push_back(id);
  this->Modified();
}

void vtkMaximalSpheresFilter::RemoveAllSampleIds()
{
  if (!this->SampleIds.empty())
  {
    this->SampleIds.clear();
    this->Modified();
  }
}

int vtkMaximalSpheresFilter::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 1)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkSelection");
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
    return 1;
  }
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  return 1;
}

int vtkMaximalSpheresFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataSet* input = vtkDataSet::GetData(inputVector[0], 0);
  vtkSelection* selection =
    inputVector[1]->GetNumberOfInformationObjects() > 0 ? vtkSelection::GetData(inputVector[1], 0) : nullptr;
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  if (!input)
    return 1;

  // The points to draw: the selected ones, else SampleIds, else all.
  vtkSmartPointer<vtkDataSet> points = input;
  if (selection)
  {
    vtkNew<vtkExtractSelection> extract;
    extract->SetInputData(0, input);
    extract->SetInputData(1, selection);
    extract->Update();
    points = vtkDataSet::SafeDownCast(extract->GetOutputDataObject(0));
    if (!points)
      return 1;
  }
  vtkPointData* pd = points->GetPointData();
  vtkDataArray* centre = pd->GetArray("SphereCenter");
  vtkDataArray* radius = pd->GetArray("Radius");
  vtkDataArray* foot = pd->GetArray("FootPoint");
  vtkDataArray* thickness = pd->GetArray("Thickness");
  vtkDataArray* contact = pd->GetArray("ContactType");
  vtkDataArray* original = pd->GetArray("vtkOriginalPointIds");
  if (!centre || centre->GetNumberOfComponents() != 3 || !radius || !foot ||
    foot->GetNumberOfComponents() != 3 || !thickness)
  {
    vtkErrorMacro(<< "the input has no sphere arrays (SphereCenter, Radius, FootPoint, Thickness):"
                     " connect port 0 of B-Rep Thickness (Method Sphere or Sphere and ray)");
    return 1;
  }
  // Sample id of point k: its id in the thickness map (vtkOriginalPointIds after a selection).
  auto sampleId = [&](vtkIdType k) {
    return original ? static_cast<vtkIdType>(original->GetComponent(k, 0)) : k;
  };
  std::vector<vtkIdType> chosen;
  const vtkIdType n = points->GetNumberOfPoints();
  if (!selection && !this->SampleIds.empty())
  {
    std::unordered_map<vtkIdType, vtkIdType> index;
    for (vtkIdType k = 0; k < n; ++k)
      index.emplace(sampleId(k), k);
    for (vtkIdType id : this->SampleIds)
    {
      const auto it = index.find(id);
      if (it == index.end())
      {
        vtkErrorMacro(<< "sample id " << id << " is not a point of the input (" << n
                      << " points)");
        return 1;
      }
      chosen.push_back(it->second);
    }
  }
  else
    for (vtkIdType k = 0; k < n; ++k)
      chosen.push_back(k);
  if (static_cast<vtkIdType>(chosen.size()) > this->MaximumSpheres)
  {
    vtkWarningMacro(<< chosen.size() << " samples chosen: drawing the first " << this->MaximumSpheres
                    << " (MaximumSpheres)");
    chosen.resize(this->MaximumSpheres);
  }

  vtkNew<vtkPoints> outPoints;
  outPoints->SetDataTypeToDouble();
  vtkNew<vtkCellArray> verts, lines, polys;
  vtkNew<vtkIdTypeArray> idArray;
  vtkNew<vtkDoubleArray> thickArray, radiusArray;
  vtkNew<vtkIntArray> partArray, typeArray;
  idArray->SetName("SampleId");
  thickArray->SetName("Thickness");
  radiusArray->SetName("Radius");
  partArray->SetName("Part");
  typeArray->SetName("ContactType");
  // Cells are stored verts, lines, polys: the cell arrays are filled in that order below.
  struct Row
  {
    vtkIdType Id;
    double T, R;
    int Part, Type;
  };
  std::vector<Row> vertRows, lineRows, polyRows;
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(this->SphereResolution);
  sphere->SetPhiResolution(this->SphereResolution);
  size_t skipped = 0;
  for (vtkIdType k : chosen)
  {
    double O[3], M[3], P[3];
    points->GetPoint(k, O);
    centre->GetTuple(k, M);
    foot->GetTuple(k, P);
    const double t = radius->GetComponent(k, 0), T = thickness->GetComponent(k, 0);
    if (!std::isfinite(t) || !std::isfinite(M[0]) || !(t > 0.0))
    {
      ++skipped;
      continue;
    }
    const vtkIdType id = sampleId(k);
    const int type = contact ? static_cast<int>(contact->GetComponent(k, 0)) : -1;
    const vtkIdType o = outPoints->InsertNextPoint(O), m = outPoints->InsertNextPoint(M),
                    p = outPoints->InsertNextPoint(P);
    const vtkIdType segment[3] = { o, m, p };
    lines->InsertNextCell(3, segment);
    lineRows.push_back({ id, T, t, SEGMENT, type });
    for (const auto& [pid, part] : { std::pair<vtkIdType, int>{ o, SAMPLE }, { m, CENTER }, { p, CONTACT } })
    {
      verts->InsertNextCell(1, &pid);
      vertRows.push_back({ id, T, t, part, type });
    }
    sphere->SetCenter(M);
    sphere->SetRadius(t);
    sphere->Update();
    vtkPolyData* s = sphere->GetOutput();
    const vtkIdType first = outPoints->GetNumberOfPoints();
    for (vtkIdType j = 0; j < s->GetNumberOfPoints(); ++j)
      outPoints->InsertNextPoint(s->GetPoint(j));
    const vtkIdType* ids = nullptr;
    vtkIdType count = 0;
    vtkCellArray* triangles = s->GetPolys();
    for (triangles->InitTraversal(); triangles->GetNextCell(count, ids);)
    {
      std::vector<vtkIdType> shifted(ids, ids + count);
      for (vtkIdType& x : shifted)
        x += first;
      polys->InsertNextCell(count, shifted.data());
      polyRows.push_back({ id, T, t, SPHERE, type });
    }
  }
  if (skipped > 0)
    vtkWarningMacro(<< skipped << " of the chosen samples failed (no sphere): skipped");
  for (const auto* rows : { &vertRows, &lineRows, &polyRows })
    for (const Row& r : *rows)
    {
      idArray->InsertNextValue(r.Id);
      thickArray->InsertNextValue(r.T);
      radiusArray->InsertNextValue(r.R);
      partArray->InsertNextValue(r.Part);
      typeArray->InsertNextValue(r.Type);
    }
  output->SetPoints(outPoints);
  output->SetVerts(verts);
  output->SetLines(lines);
  output->SetPolys(polys);
  vtkCellData* cd = output->GetCellData();
  cd->AddArray(idArray);
  cd->AddArray(thickArray);
  cd->AddArray(radiusArray);
  cd->AddArray(partArray);
  if (contact)
    cd->AddArray(typeArray);
  cd->SetActiveScalars("Thickness");
  return 1;
}

void vtkMaximalSpheresFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SampleIds: " << this->SampleIds.size() << "\n";
  os << indent << "MaximumSpheres: " << this->MaximumSpheres << "\n";
  os << indent << "SphereResolution: " << this->SphereResolution << "\n";
}
