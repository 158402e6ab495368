#include "vtkShellDeckWriter.h"

#include "Midsurface.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkIdList.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"

#include <algorithm>

vtkStandardNewMacro(vtkShellDeckWriter);

int vtkShellDeckWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

void vtkShellDeckWriter::WriteData()
{
  vtkPolyData* input = vtkPolyData::SafeDownCast(this->GetInput());
  if (!this->FileName || !*this->FileName)
  {
    vtkErrorMacro("Shell deck: no FileName");
    return;
  }
  vtkDataArray* thickness = input ? input->GetPointData()->GetArray("Thickness") : nullptr;
  if (!input || !thickness || input->GetNumberOfPolys() == 0)
  {
    vtkErrorMacro("Shell deck '" << this->FileName
                                 << "': the input is not a midsurface (triangles with a Thickness "
                                    "point array: B-Rep Midsurface's output)");
    return;
  }
  brt::Midsurface m;
  const vtkIdType n = input->GetNumberOfPoints();
  m.Points.resize(static_cast<size_t>(3 * n));
  m.Thickness.resize(static_cast<size_t>(n));
  for (vtkIdType i = 0; i < n; ++i)
  {
    input->GetPoint(i, &m.Points[static_cast<size_t>(3 * i)]);
    m.Thickness[static_cast<size_t>(i)] = thickness->GetComponent(i, 0);
  }
  vtkDataArray* sheet = input->GetCellData()->GetArray("SheetId");
  vtkNew<vtkIdList> ids;
  vtkCellArray* polys = input->GetPolys();
  const vtkIdType offset = input->GetNumberOfVerts() + input->GetNumberOfLines();
  vtkIdType cell = 0;
  int skipped = 0;
  for (polys->InitTraversal(); polys->GetNextCell(ids); ++cell)
  {
    if (ids->GetNumberOfIds() != 3)
    {
      ++skipped;
      continue;
    }
    for (int k = 0; k < 3; ++k)
      m.Triangles.push_back(static_cast<int>(ids->GetId(k)));
    const int s = sheet ? static_cast<int>(sheet->GetComponent(offset + cell, 0)) : 0;
    m.TriangleSheet.push_back(std::max(s, 0));
    if (m.Sheets.size() <= static_cast<size_t>(std::max(s, 0)))
      m.Sheets.resize(static_cast<size_t>(std::max(s, 0)) + 1);
    m.Sheets[static_cast<size_t>(std::max(s, 0))].Triangles += 1;
  }
  if (skipped > 0)
    vtkWarningMacro("Shell deck '" << this->FileName << "': " << skipped
                                   << " polygons that are not triangles were left out");
  brt::ShellDeckOptions o;
  o.Quadratic = this->Quadratic;
  o.YoungsModulus = this->YoungsModulus;
  o.PoissonRatio = this->PoissonRatio;
  o.Density = this->Density;
  const std::string error = brt::WriteShellDeck(m, this->FileName, o);
  if (!error.empty())
    vtkErrorMacro("Shell deck '" << this->FileName << "': " << error);
}

void vtkShellDeckWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "Quadratic: " << this->Quadratic << "\n";
}
