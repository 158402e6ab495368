/**
 * @class   vtkShellDeckWriter
 * @brief   Writes a midsurface as a CalculiX/Abaqus shell input deck (.inp).
 *
 * Input: port 0 of vtkMidsurfaceFilter (triangles, point array Thickness, cell array SheetId).
 * Writes *NODE, *ELEMENT (S6 by default, S3 with Quadratic off) in one element set per sheet
 * (SHEET1, ...) and EALL, the node set NBOUNDARY of the free edges, the material, *SHELL SECTION
 * with NODAL THICKNESS and *NODAL THICKNESS from the Thickness array (brt::WriteShellDeck). No
 * step: boundary conditions and loads are the analyst's (docs/Midsurface.md).
 */
#ifndef vtkShellDeckWriter_h
#define vtkShellDeckWriter_h

#include "BRepThicknessFiltersModule.h" // for export macro
#include "vtkWriter.h"

class BREPTHICKNESSFILTERS_EXPORT vtkShellDeckWriter : public vtkWriter
{
public:
  static vtkShellDeckWriter* New();
  vtkTypeMacro(vtkShellDeckWriter, vtkWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);

  ///@{
  /// S6 elements (midside nodes on the chords; default) or S3.
  vtkSetMacro(Quadratic, bool);
  vtkGetMacro(Quadratic, bool);
  ///@}

  ///@{
  /// Material: Young's modulus (MPa), Poisson's ratio, density (t/mm^3); default steel.
  vtkSetMacro(YoungsModulus, double);
  vtkGetMacro(YoungsModulus, double);
  vtkSetMacro(PoissonRatio, double);
  vtkGetMacro(PoissonRatio, double);
  vtkSetMacro(Density, double);
  vtkGetMacro(Density, double);
  ///@}

protected:
  vtkShellDeckWriter() = default;
  ~vtkShellDeckWriter() override { this->SetFileName(nullptr); }

  int FillInputPortInformation(int port, vtkInformation* info) override;
  void WriteData() override;

  char* FileName = nullptr;
  bool Quadratic = true;
  double YoungsModulus = 210000.0;
  double PoissonRatio = 0.3;
  double Density = 7.85e-9;

private:
  vtkShellDeckWriter(const vtkShellDeckWriter&) = delete;
  void operator=(const vtkShellDeckWriter&) = delete;
};

#endif
