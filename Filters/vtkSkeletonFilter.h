/**
 * @class   vtkSkeletonFilter
 * @brief   The skeleton of the rod-like regions of a part, from its maximal spheres.
 *
 * Input: port 0 of vtkThicknessFilter. Samples whose face triangles' images on the medial axis
 * collapse onto a curve (a rod, not a wall) are clustered, linked by their neighbourhood on the
 * surface, and simplified after Ferley et al. 1996: noise clusters dropped, short cycles broken,
 * short spurs removed, branches joined at the junctions of rods (brt::BuildSkeleton,
 * docs/Midsurface.md).
 *
 * Output: polylines (vtkPolyData lines) through the cluster centres; point arrays Radius (the
 * mean sphere radius t), Samples (samples per node) and Degree (branches at the node); cell
 * array BranchId. Field data: the counts.
 */
#ifndef vtkSkeletonFilter_h
#define vtkSkeletonFilter_h

#include "BRepThicknessFiltersModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

class BREPTHICKNESSFILTERS_EXPORT vtkSkeletonFilter : public vtkPolyDataAlgorithm
{
public:
  static vtkSkeletonFilter* New();
  vtkTypeMacro(vtkSkeletonFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Cluster size in median rod radii (default 0.5).
  vtkSetClampMacro(ClusterSize, double, 0.01, 100.0);
  vtkGetMacro(ClusterSize, double);
  ///@}

  ///@{
  /// Spurs shorter than this many radii of their junction are removed (default 2).
  vtkSetClampMacro(MinimumBranchLength, double, 0.0, 1000.0);
  vtkGetMacro(MinimumBranchLength, double);
  ///@}

  ///@{
  /// A sample is on a rod when its triangles' images keep less than this share of their area
  /// (default 0.2).
  vtkSetClampMacro(MaximumAreaRatio, double, 0.0, 1.0);
  vtkGetMacro(MaximumAreaRatio, double);
  ///@}

protected:
  vtkSkeletonFilter() = default;
  ~vtkSkeletonFilter() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double ClusterSize = 0.5;
  double MinimumBranchLength = 2.0;
  double MaximumAreaRatio = 0.2;

private:
  vtkSkeletonFilter(const vtkSkeletonFilter&) = delete;
  void operator=(const vtkSkeletonFilter&) = delete;
};

#endif
