#include "vtkMidsurfaceFilter.h"

#include "BRepFieldData.h"
#include "Midsurface.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkInformation.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"
#include "vtkTable.h"

#include <cmath>
#include <exception>
#include <set>
#include <string>

vtkStandardNewMacro(vtkMidsurfaceFilter);

vtkMidsurfaceFilter::vtkMidsurfaceFilter()
{
  this->SetNumberOfOutputPorts(3);
}

int vtkMidsurfaceFilter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

int vtkMidsurfaceFilter::FillOutputPortInformation(int port, vtkInformation* info)
{
  if (port == SUMMARY)
  {
    info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkTable");
    return 1;
  }
  return this->Superclass::FillOutputPortInformation(port, info);
}

int vtkMidsurfaceFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, MIDSURFACE);
  vtkPolyData* notThin = vtkPolyData::GetData(outputVector, NOT_THIN);
  vtkTable* summary = vtkTable::GetData(outputVector, SUMMARY);
  if (!input || input->GetNumberOfPoints() == 0)
    return 1;

  vtkPointData* pd = input->GetPointData();
  brt::MidsurfaceInput in;
  std::string missing;
  if (!brt::BRepMidsurfaceInput(input, in, missing))
  {
    vtkErrorMacro("B-Rep Midsurface: the input has no point array '"
      << missing << "'; connect port 0 of B-Rep Thickness (Measure: Thickness).");
    return 1; // one error, empty outputs (no second message from the executive)
  }
  const vtkIdType nP = input->GetNumberOfPoints();

  brt::MidsurfaceOptions options;
  options.SheetAngle = this->SheetAngle;
  options.MaximumSlenderness = this->MaximumSlenderness;
  options.JunctionReach = this->JunctionReach;
  brt::Midsurface m;
  try
  {
    m = brt::BuildMidsurface(in, options);
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro("B-Rep Midsurface: " << e.what());
    return 1; // one error, empty outputs (no second message from the executive)
  }

  // Port 0.
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  const vtkIdType nOut = static_cast<vtkIdType>(m.Points.size() / 3);
  points->SetNumberOfPoints(nOut);
  vtkNew<vtkDoubleArray> thickness;
  thickness->SetName("Thickness");
  thickness->SetNumberOfTuples(nOut);
  vtkNew<vtkIntArray> kind;
  kind->SetName("PointKind");
  kind->SetNumberOfTuples(nOut);
  for (vtkIdType i = 0; i < nOut; ++i)
  {
    points->SetPoint(i, &m.Points[static_cast<size_t>(3 * i)]);
    thickness->SetValue(i, m.Thickness[static_cast<size_t>(i)]);
    kind->SetValue(i, m.PointKind[static_cast<size_t>(i)]);
  }
  vtkNew<vtkCellArray> tris;
  vtkNew<vtkIntArray> sheetId, faceId, oppositeId;
  sheetId->SetName("SheetId");
  faceId->SetName("FaceId");
  oppositeId->SetName("OppositeFaceId");
  for (size_t t = 0; t < m.TriangleSheet.size(); ++t)
  {
    const vtkIdType v[3] = { m.Triangles[3 * t], m.Triangles[3 * t + 1], m.Triangles[3 * t + 2] };
    tris->InsertNextCell(3, v);
    const auto& s = m.Sheets[static_cast<size_t>(m.TriangleSheet[t])];
    sheetId->InsertNextValue(m.TriangleSheet[t]);
    faceId->InsertNextValue(s.Face);
    oppositeId->InsertNextValue(s.OppositeFace);
  }
  output->SetPoints(points);
  output->SetPolys(tris);
  output->GetPointData()->AddArray(thickness);
  output->GetPointData()->SetActiveScalars("Thickness");
  output->GetPointData()->AddArray(kind);
  output->GetCellData()->AddArray(sheetId);
  output->GetCellData()->AddArray(faceId);
  output->GetCellData()->AddArray(oppositeId);

  // Port 1: the input's triangles on faces that are not thin, with the input's point arrays.
  {
    const std::set<int> faces(m.NotThinFaces.begin(), m.NotThinFaces.end());
    std::vector<vtkIdType> map(static_cast<size_t>(nP), -1);
    vtkNew<vtkPoints> np;
    np->SetDataTypeToDouble();
    vtkNew<vtkCellArray> cells;
    vtkPointData* opd = notThin->GetPointData();
    opd->CopyAllocate(pd);
    for (size_t t = 0; t < in.Triangles.size() / 3; ++t)
    {
      if (!faces.count(in.FaceIds[static_cast<size_t>(in.Triangles[3 * t])]))
        continue;
      vtkIdType v[3];
      for (int k = 0; k < 3; ++k)
      {
        const vtkIdType old = in.Triangles[3 * t + static_cast<size_t>(k)];
        if (map[static_cast<size_t>(old)] < 0)
        {
          map[static_cast<size_t>(old)] = np->InsertNextPoint(input->GetPoint(old));
          opd->CopyData(pd, old, map[static_cast<size_t>(old)]);
        }
        v[k] = map[static_cast<size_t>(old)];
      }
      cells->InsertNextCell(3, v);
    }
    notThin->SetPoints(np);
    notThin->SetPolys(cells);
  }

  // Port 2 and port 0's field data: the counts.
  vtkNew<vtkStringArray> quantity;
  quantity->SetName("Quantity");
  vtkNew<vtkDoubleArray> value;
  value->SetName("Value");
  double sheetArea = 0.0;
  for (const auto& s : m.Sheets)
    sheetArea += s.Area;
  auto row = [&](const char* name, double v) {
    quantity->InsertNextValue(name);
    value->InsertNextValue(v);
    vtkNew<vtkDoubleArray> f;
    f->SetName(name);
    f->InsertNextValue(v);
    output->GetFieldData()->AddArray(f);
  };
  row("Sheets", static_cast<double>(m.Sheets.size()));
  row("SheetArea", sheetArea);
  row("Junctions", m.Junctions);
  row("NonManifoldEdges", m.NonManifoldEdges);
  row("FoldEdges", m.FoldEdges);
  row("BoundaryEdges", m.BoundaryEdges);
  row("OpenJunctionEdges", m.OpenJunctionEdges);
  row("CollapsedTriangles", m.CollapsedTriangles);
  row("FoldedStripTriangles", m.FoldedStripTriangles);
  row("SheetSamples", m.SheetSamples);
  row("OppositeSideSamples", m.OppositeSideSamples);
  row("ExtendedVertices", m.ExtendedVertices);
  row("JunctionVertices", m.JunctionVertices);
  row("PrunedSamples", m.PrunedSamples);
  row("PrunedBranches", m.PrunedBranches);
  row("NotThinFaces", static_cast<double>(m.NotThinFaces.size()));
  row("NotThinArea", m.NotThinArea);
  summary->AddColumn(quantity);
  summary->AddColumn(value);
  if (!m.NotThinFaces.empty())
    vtkWarningMacro("B-Rep Midsurface: " << m.NotThinFaces.size() << " faces ("
      << m.NotThinArea << " mm^2) are not thin walls; they are in the Not Thin output");
  return 1;
}

void vtkMidsurfaceFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SheetAngle: " << this->SheetAngle << "\n";
  os << indent << "MaximumSlenderness: " << this->MaximumSlenderness << "\n";
  os << indent << "JunctionReach: " << this->JunctionReach << "\n";
}
