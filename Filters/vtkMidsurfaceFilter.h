/**
 * @class   vtkMidsurfaceFilter
 * @brief   The midsurface of a thin-walled part from its maximal spheres (docs/Midsurface.md).
 *
 * Input: port 0 of vtkThicknessFilter (the display mesh with FaceId, Normals, Thickness,
 * ContactType, OppositeFaceId, ContactAngle and EdgeZone). The core (brt::BuildMidsurface) pairs
 * the faces across thin walls, meshes each pair's medial sheet from one face's mesh (vertices at
 * the sphere centres, the edge zones of the outline carried to it), prunes the branches that run
 * into corners, and joins the sheets at their junction lines (shared vertices: a non-manifold
 * surface where three or more sheets meet).
 *
 * Outputs:
 * - port 0 "Midsurface": triangles; point arrays Thickness (2t) and PointKind (0 sphere centre,
 *   1 carried to the outline, 2 junction); cell arrays SheetId, FaceId (the face the sheet is
 *   meshed from) and OppositeFaceId. Field data: the counts of the Summary.
 * - port 1 "Not Thin": the input's triangles on faces whose walls are not thin (a block), which
 *   are reported rather than forced into a sheet.
 * - port 2 "Summary": vtkTable of Quantity / Value rows (sheets, junctions, non-manifold and
 *   boundary edges, sample counts, pruned branches, areas).
 */
#ifndef vtkMidsurfaceFilter_h
#define vtkMidsurfaceFilter_h

#include "BRepThicknessFiltersModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

class BREPTHICKNESSFILTERS_EXPORT vtkMidsurfaceFilter : public vtkPolyDataAlgorithm
{
public:
  static vtkMidsurfaceFilter* New();
  vtkTypeMacro(vtkMidsurfaceFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum OutputPorts
  {
    MIDSURFACE = 0,
    NOT_THIN = 1,
    SUMMARY = 2
  };

  ///@{
  /// A sample is on a sheet when its contact angle is at least this (degrees; default 150).
  vtkSetClampMacro(SheetAngle, double, 90.0, 180.0);
  vtkGetMacro(SheetAngle, double);
  ///@}

  ///@{
  /// A face pair is thin when its median thickness is at most this times the square root of its
  /// sheet area (default 0.5).
  vtkSetClampMacro(MaximumSlenderness, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MaximumSlenderness, double);
  ///@}

  ///@{
  /// A sheet is extended by at most this many thicknesses to its junction (default 1.5).
  vtkSetClampMacro(JunctionReach, double, 0.0, 100.0);
  vtkGetMacro(JunctionReach, double);
  ///@}

protected:
  vtkMidsurfaceFilter();
  ~vtkMidsurfaceFilter() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double SheetAngle = 150.0;
  double MaximumSlenderness = 0.5;
  double JunctionReach = 1.5;

private:
  vtkMidsurfaceFilter(const vtkMidsurfaceFilter&) = delete;
  void operator=(const vtkMidsurfaceFilter&) = delete;
};

#endif
