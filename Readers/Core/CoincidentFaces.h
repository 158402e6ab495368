#pragma once
// Faces of one solid lying on one another with their outer sides the same way
// (docs/Robustness.md, "Faces of one solid lying on one another"). A valid solid's faces meet
// only along their edges. Some files write a face twice, or two faces covering one region with
// the same outward normal (AngelLM/Thor's FreeCAD exports: two planes of 2,810 mm^2 at z = 29,
// twenty planes of a gear's foot each covering most of its disk). Which of them bounds the part
// is not known, and the solve fails at their samples without saying why.
#include "BRepModel.h"

#include <TopoDS_Face.hxx>

#include <utility>
#include <vector>

namespace brt
{
/// The pairs (a, b) of faces of one solid where `a` lies on `b` with the same outward normal:
/// at least 3, and at least half, of up to 9 of a's display-mesh vertices off a's boundary
/// (spread over the face) lie within `tolerance` (or the two faces' own tolerances) of b's
/// surface, inside b's boundary (OpenCASCADE's 2D classifier, not on it), where b's outward
/// normal is within 8 degrees of a's. Found first on the display mesh alone (a vertex over one
/// of b's triangles, within twice the mesh's deflection of it, the triangle's normal within 30
/// degrees), then confirmed on the exact faces: OpenCASCADE's projection and classifier run
/// only for the pairs the mesh finds. `faces[i]` is model.Faces[i]'s face, forward.
std::vector<std::pair<int, int>> FindCoincidentFaces(const BRepModel& model,
  const std::vector<TopoDS_Face>& faces, double tolerance, double deflection);
} // namespace brt
