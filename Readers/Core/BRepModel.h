// BRepThickness: the converted B-Rep, as the thickness solver consumes it.
//
// This header is free of VTK and OpenCASCADE. It is the C++ side of the reader output
// contract documented in docs/DataContract.md; vtkSTEPReader maps it 1:1 onto field arrays.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace brt
{

/// Kind of the original (pre-conversion) surface of a face, for statistics and tests.
enum class SurfaceKind : int
{
  Plane = 0,
  Cylinder,
  Cone,
  Sphere,
  Torus,
  BezierSurface,
  BSplineSurface,
  SurfaceOfRevolution,
  SurfaceOfExtrusion,
  OffsetSurface,
  Other
};
const char* SurfaceKindName(SurfaceKind kind);

/// One face of the healed shape.
struct Face
{
  int Solid = -1;         ///< index of the solid (or free shell) the face belongs to
  bool Reversed = false;  ///< true: outward normal = -(Su x Sv); false: +(Su x Sv)
  /// The kind of the face's surface; a B-spline or Bezier face that is a plane, cylinder, cone,
  /// sphere or torus within a thousandth of the tolerance gets that kind and its FaceExact row
  /// (ConversionStatistics::AnalyticFromSpline; DegreeU/V, non-zero, still tell the file's).
  SurfaceKind Kind = SurfaceKind::Other;
  bool Rational = false;        ///< the surface is rational (NURBS, or an extruded rational curve)
  /// The surface's degrees: a B-spline or Bezier surface's, and an extrusion of a B-spline or
  /// Bezier curve (the curve's along u, 1 along v); 0 for every other surface.
  int DegreeU = 0, DegreeV = 0;
  std::array<double, 4> Domain{}; ///< u0, u1, v0, v1 : the face's UV bounds
  int FirstPatch = 0, PatchCount = 0;
  int PatchesU = 0, PatchesV = 0; ///< patches form a PatchesU x PatchesV grid, u fastest
  int FirstLoop = 0, LoopCount = 0;
  /// Measured max |Bezier(u,v) - S(u,v)| on this face (random points and a grid on every patch);
  /// negative: not measured (a model built by hand, a field without FaceMaxDeviation).
  double MaxDeviation = -1.0;
  double UVTolerance = 0.0;  ///< parametric tolerance used for the trimming curves
  /// Period of the surface in u and v when the face closes on itself across a seam in that
  /// direction (its domain spans the whole period), else 0. The solver wraps across seams.
  std::array<double, 2> Period{ 0.0, 0.0 };
};

/// Bicubic Bezier patch covering [Domain[0],Domain[1]] x [Domain[2],Domain[3]] of its face's
/// parameters. Local parameters s=(u-u0)/(u1-u0), r=(v-v0)/(v1-v0).
/// Control point P_ij (i along u, j along v) is at ControlPoints[(4*i + j)*3 + k], k = x,y,z.
struct BezierPatch
{
  std::array<double, 48> ControlPoints{};
  int Face = -1;
  std::array<double, 4> Domain{};
};

/// Cubic 2D Bezier segment of a trimming loop, in the face's (u,v).
/// Loops are oriented so that the face material lies on the left: outer loops counter-clockwise,
/// holes clockwise, whatever the face orientation (Face::Reversed carries that separately).
struct TrimSegment
{
  std::array<double, 8> ControlPoints{}; ///< (u,v) of 4 control points
  int Face = -1;
  int Loop = -1;        ///< index into BRepModel::Loops
  int Edge = -1;        ///< index into BRepModel::Edges, -1 for a degenerated edge (pole)
  bool Reversed = false; ///< the loop runs along the edge against the edge's parameter
  /// Edge parameters at the segment's start (local 0) and end (local 1); T0 > T1 when Reversed.
  double T0 = 0.0, T1 = 0.0;
};

struct TrimLoop
{
  int Face = -1;
  int FirstSegment = 0, SegmentCount = 0;
  bool Outer = false;
  double RawGap = 0.0;   ///< largest UV gap between consecutive pcurves before welding
  double RawGap3D = 0.0; ///< the same gap measured in 3D on the surface (model units)
  bool Open = false;     ///< a gap exceeded the model's vertex tolerance and was not welded
  double Area = 0.0;     ///< signed UV area after orientation (>0 outer, <0 holes)
};

/// A 3D edge of the shape, shared by up to two faces.
struct Edge
{
  std::array<int, 2> Faces{ -1, -1 }; ///< faces that share it; equal for a seam; -1 free
  int FaceCount = 0;                  ///< number of faces sharing it (>2: non-manifold)
  double T0 = 0.0, T1 = 0.0;          ///< parameter range of the edge
  int FirstSegment = 0, SegmentCount = 0;
  bool Seam = false;
  double MaxDeviation = 0.0; ///< measured max |Bezier(t) - C(t)|
};

/// Cubic 3D Bezier segment of an edge, covering edge parameters [T0, T1] (T0 < T1).
struct EdgeSegment
{
  std::array<double, 12> ControlPoints{};
  int Edge = -1;
  double T0 = 0.0, T1 = 0.0;
};

/// Display tessellation. Every vertex lies on the exact surface of its face.
struct DisplayMesh
{
  std::vector<double> Points;    ///< xyz per vertex
  std::vector<double> Normals;   ///< outward unit normal per vertex
  std::vector<double> UV;        ///< (u,v) on the vertex's face
  /// The principal curvatures of the face's exact surface at each vertex (1 / model units), two
  /// per vertex, the largest first, positive where the face bends away from its outward normal
  /// (convex seen from outside: towards the material); on the face's boundary taken just inside
  /// it (the smallest largest and the largest smallest of the points 1e-2 of the way to each of
  /// the vertex's triangles' centroids), zeros at a singular point. Empty where not known (a mesh
  /// built by hand, a poly data without the PrincipalCurvatures array): the solver then has no
  /// osculating bound (docs/Solver.md, item 21).
  std::vector<double> Curvatures;
  std::vector<int> FaceIds;      ///< per vertex
  std::vector<int> Triangles;    ///< 3 vertex ids per triangle, counter-clockwise seen from outside
  std::vector<int> TriangleFace; ///< per triangle
  std::size_t NumberOfPoints() const { return FaceIds.size(); }
};

/// Principal curvatures (c[0] >= c[1], positive bending away from a normal) as seen from the
/// other side: the normal reversed.
inline void TurnCurvatures(double* c)
{
  const double largest = c[0];
  c[0] = -c[1];
  c[1] = -largest;
}

struct ConversionStatistics
{
  int Solids = 0;
  int Faces = 0;
  int Patches = 0;
  int TrimSegments = 0;
  int Loops = 0;
  int Edges = 0;
  int EdgeSegments = 0;
  double MaxPatchDeviation = 0.0; ///< max over faces of Face::MaxDeviation
  double MaxEdgeDeviation = 0.0;
  double MaxLoopGap = 0.0;        ///< max over loops of TrimLoop::RawGap (UV units)
  double MaxLoopGap3D = 0.0;      ///< max over loops of TrimLoop::RawGap3D (model units)
  int OpenLoops = 0;              ///< loops left open (gap beyond the vertex tolerance)
  /// faces whose display mesh is the flipped one because bisection would exceed
  /// ConversionOptions::SliverRatio times its vertices
  int FlippedFaces = 0;
  /// faces that BRepMesh left without a triangulation and that got one when meshed again alone
  /// (MeshFacesLeftWithoutTriangulation, BRepConverter.h)
  int RemeshedFaces = 0;
  /// B-spline or Bezier faces found to be a plane, cylinder, cone, sphere or torus within a
  /// thousandth of the tolerance (their Face::Kind says which; DegreeU/V stay the file's)
  int AnalyticFromSpline = 0;
  double ReadSeconds = 0.0;
  double HealSeconds = 0.0;
  double ConvertSeconds = 0.0;
  double MeshSeconds = 0.0;
  std::vector<std::string> Warnings;
};

struct BRepModel
{
  std::string SourceFile;
  std::string Schema;   ///< the STEP file's FILE_SCHEMA (e.g. AUTOMOTIVE_DESIGN for AP214)
  std::string LengthUnit = "mm";
  double Tolerance = 1e-4;
  std::vector<Face> Faces;
  /// The exact surface of each analytic face (Face::Kind Plane, Cylinder, Cone, Sphere, Torus;
  /// zeros for every other kind), one row per face or none at all (a model built by hand): a
  /// point (3), a unit direction (3) and two sizes. Plane: a point on it, its normal. Cylinder: a
  /// point on the axis, the axis, the radius. Cone: the point on the axis where the radius is the
  /// reference radius, the axis, that radius, the semi-angle (radius R + z tan(angle) at height
  /// z along the axis). Sphere: the centre, any axis, the radius. Torus: the centre, the axis,
  /// the major and the minor radius. The solver's exact finish (docs/Solver.md) moves contacts
  /// on these faces onto the surface itself. Kept apart from Face so that solve files written
  /// before it stay readable (it follows the rest of a file).
  std::vector<std::array<double, 8>> FaceExact;
  std::vector<BezierPatch> Patches;
  std::vector<TrimLoop> Loops;
  std::vector<TrimSegment> TrimSegments;
  std::vector<Edge> Edges;
  std::vector<EdgeSegment> EdgeSegments;
  DisplayMesh Mesh;
  ConversionStatistics Stats;
  /// Places where the file's faces and edges miss each other by far more than the tolerance: a
  /// vertex whose tolerance the translation or the healing grew to cover a gap, or a trimming
  /// loop bridged across one (the converter warns of each, with the place). Each a point (3)
  /// and a radius (the tolerance or the gap) within which CheckResults flags the samples
  /// (FailReason::FileGap). Follows the rest of a model file.
  std::vector<std::array<double, 4>> LooseVertices;
  /// Faces whose extent the file does not settle: a surface lying off most of its own vertices
  /// by as much (a face whose surface was moved off its edges), or a trimming loop that winds
  /// round its periodic surface instead of enclosing a region. CheckResults flags the samples on
  /// them, the spheres touching them and the spheres reaching the box of their patches' control
  /// points (FailReason::FileGap). Follows LooseVertices in a model file.
  std::vector<int> LooseFaces;
  /// Faces of a solid that lie on another of its faces, their outer sides the same way (a face
  /// written twice, or two faces covering one region: FindCoincidentFaces, CoincidentFaces.h; the
  /// converter warns of them). Which of them bounds the part there is not known: CheckResults
  /// flags the samples on them (FailReason::FileGap). The spheres touching them are kept: where
  /// they overlap, the faces agree on where the surface is. Follows the mesh's curvatures in a
  /// model file.
  std::vector<int> OverlappingFaces;
};

} // namespace brt
