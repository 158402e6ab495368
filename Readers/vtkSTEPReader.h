/**
 * @class   vtkSTEPReader
 * @brief   Reads a STEP (AP203/AP214/AP242) solid as bicubic Bezier patches, cubic trimming
 *          loops, cubic edges and a display mesh, for the thickness solver.
 *
 * The output vtkPolyData is the display tessellation: every vertex lies on the exact surface and
 * carries the point arrays FaceId, SolidId, FaceUV and Normals (outward). Its field data holds the
 * converted B-Rep (BezierPatches, PatchFace, PatchDomain, TrimSegments, TrimSegmentInfo, ...)
 * and the conversion statistics; docs/DataContract.md lists every array. Lengths are in mm.
 *
 * Under MPI, every piece holds whole faces of the display mesh (contiguous ranges of faces with
 * about the same number of vertices) and the complete B-Rep in its field data.
 *
 * Bad input (missing, empty, non-STEP, truncated or damaged file, no closed solid) gives one
 * error message naming the file and the reason, and an empty output. OpenCASCADE reads the file
 * in a separate process, so a file that crashes it or makes it loop cannot take ParaView down.
 */
#ifndef vtkSTEPReader_h
#define vtkSTEPReader_h

#include "BRepThicknessReadersModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

class BREPTHICKNESSREADERS_EXPORT vtkSTEPReader : public vtkPolyDataAlgorithm
{
public:
  static vtkSTEPReader* New();
  vtkTypeMacro(vtkSTEPReader, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The STEP file to read.
  vtkSetFilePathMacro(FileName);
  vtkGetFilePathMacro(FileName);
  ///@}

  ///@{
  /// Max distance between the Bezier patches (and edge segments) and the exact geometry, in
  /// model units (mm). Default 1e-4.
  vtkSetClampMacro(Tolerance, double, 1e-9, 1.0);
  vtkGetMacro(Tolerance, double);
  ///@}

  ///@{
  /// Heal the shape with OpenCASCADE's ShapeFix before converting. Default on.
  vtkSetMacro(Heal, bool);
  vtkGetMacro(Heal, bool);
  vtkBooleanMacro(Heal, bool);
  ///@}

  ///@{
  /// Display mesh: chordal deviation (0: 1e-3 of the bounding-box diagonal), angular deflection
  /// in radians, and the longest edge allowed (0: 1/50 of the diagonal). The mesh vertices are
  /// the thickness samples, so MaxEdgeLength sets the sample density.
  vtkSetClampMacro(LinearDeflection, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(LinearDeflection, double);
  vtkSetClampMacro(AngularDeflection, double, 0.01, 1.5);
  vtkGetMacro(AngularDeflection, double);
  vtkSetClampMacro(MaxEdgeLength, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MaxEdgeLength, double);
  ///@}

  ///@{
  /// Display mesh: refine with Delaunay flips after each split (well-shaped triangles, far fewer
  /// samples on cylinders and long faces at the same MaxEdgeLength) instead of bisection alone.
  /// Default off (docs/Design.md, "Display mesh").
  vtkSetMacro(DelaunayRefinement, bool);
  vtkGetMacro(DelaunayRefinement, bool);
  vtkBooleanMacro(DelaunayRefinement, bool);
  ///@}

  ///@{
  /// Seconds that reading, healing and converting may take (0: no limit). Default 300.
  /// OpenCASCADE runs in the worker process brt_step_worker (StepIsolation.h): a crash or a
  /// time-out there is an error naming the file, never a crash of this process.
  vtkSetClampMacro(TimeLimit, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(TimeLimit, double);
  ///@}

  /// 1 if the file looks like a STEP file (header and terminator present), else 0.
  static int CanReadFile(const char* filename);

protected:
  vtkSTEPReader();
  ~vtkSTEPReader() override;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* FileName = nullptr;
  double Tolerance = 1e-4;
  bool Heal = true;
  double LinearDeflection = 0.0;
  double AngularDeflection = 0.35;
  double MaxEdgeLength = 0.0;
  bool DelaunayRefinement = false;
  double TimeLimit = 300.0;

private:
  vtkSTEPReader(const vtkSTEPReader&) = delete;
  void operator=(const vtkSTEPReader&) = delete;
};

#endif
