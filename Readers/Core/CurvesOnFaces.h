#pragma once
// Curves of edges on faces that miss their edge (docs/Robustness.md, "Curves on faces off their
// edges"). A face's trimming loops are its edges' curves in the face's parameters (pcurves).
// Most STEP exporters write none; OpenCASCADE's transfer then makes them by projecting the 3D
// edge onto the surface, and on a sphere near its pole that projection can miss the edge by far
// more than the edge's tolerance while the edge still says it is within it: a SolidWorks part's
// pcurve lay 0.93 mm off its circle of tolerance 1e-7. The face's boundary is then wrong (a
// sliver of face where there is none, or a bite out of it) for every user of the shape: the
// conversion's trims, the display mesh, OpenCASCADE's own distances.
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>

#include <string>
#include <vector>

namespace brt
{
struct CurvesOnFacesResult
{
  int Checked = 0;           ///< edge uses on faces measured
  int Rebuilt = 0;           ///< pcurves replaced by a projection of their edge
  double WorstRebuilt = 0.0; ///< the largest distance of a replaced pcurve from its edge
  int Left = 0;              ///< pcurves still off their edge beyond its tolerance
  double WorstLeft = 0.0;    ///< the largest distance of one of those from its edge
};

/// The largest distance of the image of `edge`'s curve on `face` from the edge's 3D curve, over
/// `samples` + 1 points evenly spread in the edge's parameter. Each point is compared with the
/// 3D curve at the same parameter and, where that is farther than `threshold`, with the nearest
/// point of the 3D curve near there (an edge whose two curves agree in shape but not in
/// parameter is not off). 0 for an edge without either curve.
double CurveOnFaceDistance(const TopoDS_Edge& edge, const TopoDS_Face& face, double threshold,
  int samples);

/// Measures every edge's pcurve on every face of `faces` against the edge's 3D curve; where one
/// lies off by more than twice the edge's tolerance and more than a tenth of `tolerance` (the
/// conversion's), it is projected again from the 3D curve (OpenCASCADE's GeomProjLib, then
/// ShapeConstruct_ProjectCurveOnSurface) and replaced in the shape where the projection is
/// nearer by half, moved by periods of the surface onto the old one's ends and ending where the
/// old one ends. Seam edges (two pcurves on one face) are measured, never replaced. The edge's
/// tolerance is raised to the new pcurve's distance where that exceeds it. One warning in
/// `warnings` for the replaced ones and one for those left, naming the face of the worst.
CurvesOnFacesResult RepairCurvesOnFaces(
  const std::vector<TopoDS_Face>& faces, double tolerance, std::vector<std::string>& warnings);
} // namespace brt
