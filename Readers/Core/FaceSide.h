#pragma once
// BRepThickness: which side of a face's boundary a point of its parameter plane lies on, as
// OpenCASCADE's polygon classifier says, with its answers kept by cells that no trimming curve
// comes near (the display mesh's refinement asks it for every midpoint it adds).

#include <BRepTopAdaptor_FClass2d.hxx>
#include <TopoDS_Face.hxx>
#include <gp_Pnt2d.hxx>

#include <vector>

namespace brt
{
/// Whether a UV point lies outside a face, as BRepTopAdaptor_FClass2d (at a UV tolerance of
/// 1e-9) says: Perform(p) == TopAbs_OUT. Its answers are kept by the cells of a Cells x Cells
/// grid over the face's UV box (BRepTools::UVBounds) that no pcurve comes near: within such a cell
/// every point lies on one side of the face's boundary, and the classifier decides points within
/// its polygons' deflection of a wire with OpenCASCADE's exact face classifier, so its first
/// answer in the cell is every point's. A cell is near a pcurve where it meets the box of one of
/// the pcurve's pieces (BndLib_Add2dCurve: a B-spline's poles, a conic's own box; eight pieces,
/// a line one) grown by half a cell each way. The cells near a pcurve, the points outside the
/// grid, every point of a face on a surface periodic over less than the face's UV box, and of a
/// face with an edge that has no pcurve or a pcurve BndLib cannot bound (it throws), ask the
/// classifier each time. On a face with many holes each of the classifier's answers tests the
/// point against every wire: the refinement's midpoints took 2.9 s of a perforated card guide's
/// 4.6 s display mesh (docs/Design.md, "Every vertex on its face").
class FaceSide
{
public:
  explicit FaceSide(const TopoDS_Face& face);
  bool Outside(const gp_Pnt2d& p);
  /// Whether the answers are kept (false: every point asks the classifier).
  bool Cached() const { return !State.empty(); }
  /// How many times the classifier has been asked (the answers not kept).
  long Asked() const { return Calls; }

  static constexpr int Cells = 64;

private:
  static constexpr signed char Unknown = -1, Near = -2, In = 0, Out = 1;
  BRepTopAdaptor_FClass2d Classifier;
  double U0 = 0.0, V0 = 0.0, DU = 0.0, DV = 0.0;
  std::vector<signed char> State; ///< per cell (i * Cells + j); empty: no cache
  long Calls = 0;
};
} // namespace brt
