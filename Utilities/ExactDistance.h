#ifndef BRT_EXACT_DISTANCE_H
#define BRT_EXACT_DISTANCE_H
// The distance from a point to a part's exact faces by a second way, beside OpenCASCADE's
// BRepExtrema_DistShapeShape (which can miss the nearest point of a face: docs/Solver.md, item
// 14). Shared by brt_exact_check and the tests that measure spheres against the exact B-Rep.
#include <Bnd_Box.hxx>
#include <TopoDS_Face.hxx>
#include <gp_Pnt.hxx>

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
/// *atFace its face's index (-1: on an edge or at a vertex).
double ExtremaDistance(const std::vector<TopoDS_Face>& faces, const std::vector<Bnd_Box>& boxes,
  const gp_Pnt& X, double reach, const std::function<bool(size_t)>& use = {},
  gp_Pnt* at = nullptr, int* atFace = nullptr);

/// The faces' boxes for ExtremaDistance.
std::vector<Bnd_Box> FaceBoxes(const std::vector<TopoDS_Face>& faces);
} // namespace exact
} // namespace brt

#endif
