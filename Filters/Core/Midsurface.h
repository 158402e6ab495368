// The midsurface of a thin-walled part, built from its maximal inscribed spheres, and its export
// as a CalculiX/Abaqus shell deck (docs/Midsurface.md). Free of VTK: vtkMidsurfaceFilter and
// vtkShellDeckWriter are its adapters.
#pragma once

#include <string>
#include <vector>

namespace brt
{
/// What BuildMidsurface reads: the display mesh (vertices not shared between faces, as the reader
/// makes it) and, per vertex, the result of its thickness sample (vtkThicknessFilter's port 0).
struct MidsurfaceInput
{
  std::vector<double> Points;       ///< xyz per vertex
  std::vector<double> Normals;      ///< outward unit normal per vertex
  std::vector<int> FaceIds;         ///< per vertex
  std::vector<int> Triangles;       ///< 3 vertex ids per triangle, one face per triangle
  std::vector<double> Thickness;    ///< 2t per vertex; NaN where the sample failed
  std::vector<int> ContactType;     ///< brt::ContactType per vertex
  std::vector<int> OppositeFace;    ///< the face the sphere touches
  std::vector<double> ContactAngle; ///< degrees (brt::ContactAngle)
  std::vector<unsigned char> EdgeZone;
};

struct MidsurfaceOptions
{
  /// A sample lies on a sheet when its sphere touches one opposite face (surface/surface), is not
  /// in an edge zone and its contact angle is at least this (degrees): the two walls are within
  /// 180 - SheetAngle degrees of parallel.
  double SheetAngle = 150.0;
  /// A face pair is thin when its median thickness is at most this times the square root of the
  /// larger of its two sheet areas; thicker pairs are reported (NotThin*), not made into sheets.
  double MaximumSlenderness = 0.5;
  /// Edge-zone vertices of a sheet's face (next to a convex rim) take the thickness of the nearest
  /// sheet sample within this many thicknesses (straight distance; the path runs through edge zones
  /// of the face), so the sheet reaches the outline.
  double ExtrapolationLimit = 1.5;
  /// A sheet's free boundary that is not an outline is extended along the sheet to the plane of
  /// another sheet's boundary, by at most this many thicknesses (the larger of the two sheets'):
  /// the junction (docs/Midsurface.md). 1.5 covers a concave corner's fillet up to one thickness.
  double JunctionReach = 1.5;
  /// A face triangle whose image on the sheet keeps less than this share of its area (or turns
  /// over) is left out: the sheet collapses there towards a line (a rod, not a wall).
  double MinimumAreaRatio = 0.2;
};

/// One sheet: the medial surface between two faces, meshed from the display mesh of one of them.
struct MidsurfaceSheet
{
  int Face = -1;         ///< the face whose mesh the sheet is made of
  int OppositeFace = -1; ///< the face across the wall
  double Thickness = 0.0; ///< median thickness of its sheet samples
  double Area = 0.0;      ///< area of the sheet's triangles
  int Triangles = 0;
};

struct Midsurface
{
  std::vector<double> Points;    ///< xyz per vertex
  std::vector<double> Thickness; ///< per vertex: 2t
  /// Per vertex: 0 a sheet sample's sphere centre, 1 an edge-zone vertex carried to the outline
  /// (O + d h/2 with the nearest sheet sample's h), 2 a junction vertex.
  std::vector<int> PointKind;
  std::vector<int> Triangles;     ///< 3 ids per triangle, oriented as the sheet's face
  std::vector<int> TriangleSheet; ///< index into Sheets
  std::vector<MidsurfaceSheet> Sheets;

  /// Faces with wall samples whose pairs are not thin (a block), and their area.
  std::vector<int> NotThinFaces;
  double NotThinArea = 0.0;

  int SheetSamples = 0;     ///< samples whose sphere centre is a vertex of the midsurface
  int ExtendedVertices = 0; ///< edge-zone vertices carried to the outline
  int JunctionVertices = 0;
  /// Sheet samples on the other face of a sheet's pair (the sheet is made of one side)
  int OppositeSideSamples = 0;
  /// Solved samples of the part that are not on the midsurface: edge zones at corners and
  /// junctions, the parabolic sheets of concave edges, pairs that are not thin
  int PrunedSamples = 0;
  /// Connected regions of pruned samples on a face's mesh: the pruned branches of the medial axis
  int PrunedBranches = 0;
  int BoundaryEdges = 0;
  int NonManifoldEdges = 0; ///< edges of three or more triangles: the junction lines
  /// Non-manifold edges whose triangles all belong to one sheet: folds, not junctions (a defect
  /// of the sheet's construction, counted so it is seen; 0 on the closed-form parts)
  int FoldEdges = 0;
  int Junctions = 0;        ///< connected chains of non-manifold edges
  /// Free boundary edges of sheet samples that found no other sheet to join: open junctions
  int OpenJunctionEdges = 0;
  /// Face triangles left out because their image collapsed or turned over (MinimumAreaRatio)
  int CollapsedTriangles = 0;
  /// Junction strip triangles removed because they folded a sheet onto itself (an edge of one
  /// sheet with more than two triangles, where strips of a boundary's corner overlap)
  int FoldedStripTriangles = 0;
};

Midsurface BuildMidsurface(const MidsurfaceInput& input, const MidsurfaceOptions& options = {});

/// Throws std::invalid_argument, naming `who`, when the per-vertex arrays of `input` differ in
/// length or a triangle refers to a missing vertex.
void CheckMidsurfaceInput(const MidsurfaceInput& input, const char* who);

/// Edges of a triangle mesh by the number of triangles sharing them, and the connected chains of
/// edges shared by three or more.
struct EdgeCounts
{
  int Boundary = 0;
  int Manifold = 0;
  int NonManifold = 0;
  int NonManifoldChains = 0;
};
EdgeCounts CountEdges(const std::vector<int>& triangles);

struct ShellDeckOptions
{
  bool Quadratic = true;           ///< S6 (midside nodes on the chords) instead of S3
  double YoungsModulus = 210000.0; ///< MPa (N/mm^2: the model is in mm)
  double PoissonRatio = 0.3;
  double Density = 7.85e-9;        ///< t/mm^3
  std::string Material = "STEEL";
};

/// Writes `m` as a CalculiX/Abaqus input deck: *NODE, *ELEMENT (S6 or S3) in one element set
/// per sheet and EALL, *NODAL THICKNESS from the Thickness array, the material, *SHELL SECTION
/// with NODAL THICKNESS, and the node set NBOUNDARY (nodes on free edges). No step: the analyst
/// (or the test) adds boundary conditions and loads, e.g. with *INCLUDE. Returns "" or an error.
std::string WriteShellDeck(const Midsurface& m, const std::string& path,
  const ShellDeckOptions& options = {});
} // namespace brt
