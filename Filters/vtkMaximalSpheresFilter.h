/**
 * @class   vtkMaximalSpheresFilter
 * @brief   The maximal spheres of chosen samples of a thickness map, to look at in 3D.
 *
 * Input 0: port 0 of vtkThicknessFilter (or any data set with its point arrays SphereCenter,
 * Radius, FootPoint and Thickness, e.g. an Extract Selection of it). Input 1 (optional): a
 * vtkSelection of those points; in ParaView the active selection (points picked in the render
 * view) is connected when the filter is created. Without a selection, SampleIds chooses the
 * samples (point ids of port 0, which are the SampleId of the Medial Points port); without
 * either, every point of the input, up to MaximumSpheres.
 *
 * Output: per chosen sample, the sphere's surface (triangles), the polyline O - M - P from the
 * sample to the centre to the contact point, and vertices at O, M and P. Cell arrays: SampleId,
 * Thickness, Radius, ContactType (where the input has it) and Part (0 sphere, 1 segment O-M-P,
 * 2 sample O, 3 centre M, 4 contact P), so the spreadsheet lists the values and a threshold on
 * Part shows one kind. Failed samples (no sphere) are skipped and counted in a warning.
 */
#ifndef vtkMaximalSpheresFilter_h
#define vtkMaximalSpheresFilter_h

#include "BRepThicknessFiltersModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <vector> // for the sample ids

class BREPTHICKNESSFILTERS_EXPORT vtkMaximalSpheresFilter : public vtkPolyDataAlgorithm
{
public:
  static vtkMaximalSpheresFilter* New();
  vtkTypeMacro(vtkMaximalSpheresFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum Parts
  {
    SPHERE = 0,
    SEGMENT = 1,
    SAMPLE = 2,
    CENTER = 3,
    CONTACT = 4
  };

  /// The selection (optional input 1).
  void SetSelectionConnection(vtkAlgorithmOutput* algOutput)
  {
    this->SetInputConnection(1, algOutput);
  }

  ///@{
  /// Samples to show when no selection is connected: point ids of the thickness map (port 0).
  void AddSampleId(vtkIdType id);
  void RemoveAllSampleIds();
  ///@}

  ///@{
  /// At most this many spheres (default 1000): more would hide the part and take long.
  vtkSetClampMacro(MaximumSpheres, int, 1, 1000000);
  vtkGetMacro(MaximumSpheres, int);
  ///@}

  ///@{
  /// Theta and phi resolution of each sphere's surface (default 32).
  vtkSetClampMacro(SphereResolution, int, 4, 512);
  vtkGetMacro(SphereResolution, int);
  ///@}

protected:
  vtkMaximalSpheresFilter();
  ~vtkMaximalSpheresFilter() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  std::vector<vtkIdType> SampleIds;
  int MaximumSpheres = 1000;
  int SphereResolution = 32;

private:
  vtkMaximalSpheresFilter(const vtkMaximalSpheresFilter&) = delete;
  void operator=(const vtkMaximalSpheresFilter&) = delete;
};

#endif
