#ifndef BRT_EXACT_DISTANCE_H
#define BRT_EXACT_DISTANCE_H
// The distance from a point to a part's exact faces by a second way, beside OpenCASCADE's
// BRepExtrema_DistShapeShape (which can miss the nearest point of a face: docs/Solver.md, item
// 14). Shared by brt_exact_check and the tests that measure spheres against the exact B-Rep.
// Not for several threads at once: each face's polygon classifier is built once and kept.
#include <Bnd_Box.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <gp_Dir.hxx>
#include <gp_Pnt.hxx>

class IntCurvesFace_ShapeIntersector;

#include <functional>
#include <vector>

namespace brt
{
namespace exact
{
/// The nearest point to X of the faces `use` accepts (all where it is empty) whose box (`boxes`,
/// one per face, from BRepBndLib) comes within `reach` of X: every local extremum of the distance
/// to each face's surface (GeomAPI_ProjectPointOnSurf over the face's parameter box) that the
/// face's classifier puts on the face, and every extremum along its edges' curves and their ends.
/// Returns that distance (the largest double where there is none); *at gets the point and
/// *atFace its face's index (-1: on an edge or at a vertex). With grid > 0 also a third opinion
/// on each such face (GridDistance), for points both extremum searches miss.
double ExtremaDistance(const std::vector<TopoDS_Face>& faces, const std::vector<Bnd_Box>& boxes,
  const gp_Pnt& X, double reach, const std::function<bool(size_t)>& use = {},
  gp_Pnt* at = nullptr, int* atFace = nullptr, int grid = 0);

/// The nearest point to X of face F's surface among the cell centres of an n x n grid over its
/// parameter box that both of OpenCASCADE's face classifiers keep (BRepClass_FaceClassifier and
/// BRepTopAdaptor_FClass2d), refined three times by a 9 x 9 grid over the neighbouring cells of
/// the best, and likewise around up to 8 more cells on the face whose distance is a local minimum
/// of the grid within a cell's reach of the best (another basin, narrower than a cell);
/// independent of OpenCASCADE's extremum searches, which can
/// both miss a face's nearest point (a round's saddle: docs/Solver.md, Open items, "Their failed
/// samples"). An upper bound of the face's distance (the largest double where no grid point lies
/// on the face); *at gets the point.
double GridDistance(const TopoDS_Face& F, const gp_Pnt& X, int n, gp_Pnt* at = nullptr);

/// BRepExtrema_DistShapeShape's distance from X to the faces of `shape`, its in-face solutions
/// checked: one whose (u, v) either face classifier puts off its face (BRepClass_FaceClassifier
/// and BRepTopAdaptor_FClass2d, at the face's tolerance) is not taken; that face is measured by
/// ExtremaDistance instead (grid as there) and the other faces by BRepExtrema again, up to eight
/// such faces. BRepExtrema returned the corner of a sliver face's parameter box, 0.3 mm off the
/// face, as its nearest point (Bastardkb's Charybdis3 case, face 271: a sphere "0.13 into the
/// faces" that our solver has clear; BRepClass_FaceClassifier, on which BRepExtrema relies, has
/// the corner in, the polygon classifier out). Returns -1 where BRepExtrema fails, where no
/// point is found, or where more than eight rounds drop faces; *at gets the point and *onFace
/// its face (null on an edge or vertex).
double CheckedDistance(const TopoDS_Shape& shape, const gp_Pnt& X, int grid = 0,
  gp_Pnt* at = nullptr, TopoDS_Face* onFace = nullptr);

/// The faces' boxes for ExtremaDistance.
std::vector<Bnd_Box> FaceBoxes(const std::vector<TopoDS_Face>& faces);

/// How a ray thickness of ours compares with OpenCASCADE's first intersection of the same ray
/// with the exact faces (CompareRay).
enum class RayAgreement
{
  Within,        ///< both hit, within 1e-4 relative
  Glancing,      ///< the same hit within twice the tolerance across the face (and ours within
                 ///< it of the faces): the patches' accuracy over the cosine at a glancing angle
  Grazing,       ///< ours nearer, its point within twice the tolerance of a face: a graze of a
                 ///< face or an edge, which ours counts and the intersector (crossings) does not
  ExactOff,      ///< OpenCASCADE's point lies off the faces by more than the tolerance
  ExactTouch,    ///< OpenCASCADE's nearer hit touches (tangent, or on a face's boundary: a ray
                 ///< along a face or tangent to a round), which ours does not count
  Other,         ///< none of these: a miss or a false hit of ours
  OursAlone,     ///< ours hit, OpenCASCADE's nothing
  ExactAlone,    ///< OpenCASCADE's hit, ours nothing
  Neither,       ///< neither hit
  ExactFailed    ///< OpenCASCADE's intersector threw
};
const char* RayAgreementName(RayAgreement a);

/// Ours (`ours`: NaN or infinite where the ray met nothing) against OpenCASCADE's first
/// intersection of the line from O along the unit direction d with the faces of `shape` beyond
/// sMin (IntCurvesFace_ShapeIntersector loaded with `shape` by the caller, its faces' tolerance
/// `tolerance`). *exactOut gets OpenCASCADE's distance (NaN where none).
RayAgreement CompareRay(double ours, IntCurvesFace_ShapeIntersector& intersector,
  const TopoDS_Shape& shape, const gp_Pnt& O, const gp_Dir& d, double sMin, double tolerance,
  double* exactOut = nullptr);
} // namespace exact
} // namespace brt

#endif
