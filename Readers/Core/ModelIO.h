// BRepThickness: the converted model in a file, and the checks that make a model safe to solve.
//
// The STEP worker (Utilities/StepWorker.cxx) hands its converted model back to the process that
// started it through such a file (StepIsolation.h). Same-architecture files only; not a storage
// format. Free of VTK and OpenCASCADE.
#pragma once

#include "BRepModel.h"

#include <array>
#include <istream>
#include <ostream>
#include <string>
#include <vector>

namespace brt
{
/// The B-Rep's six arrays (faces, patches, loops, trimming segments, edges, edge segments) in
/// this order: the part of a model file that a solve file (Filters/Core/SolverIO.h) shares.
void PutGeometry(std::ostream& out, const BRepModel& model);
/// Reads them back; throws std::runtime_error on a corrupt count or a truncated file.
void GetGeometry(std::istream& in, BRepModel& model);

/// Writes every part of the model (geometry, display mesh, statistics, warnings).
/// Throws std::runtime_error naming the file if it cannot be written.
void WriteModel(const std::string& path, const BRepModel& model);

/// Reads a file of WriteModel and checks it with ValidateModel.
/// Throws std::runtime_error naming the file if it is not such a file or is inconsistent.
BRepModel ReadModel(const std::string& path);

/// Structural checks the solver relies on: every index in range, every count consistent, every
/// coordinate and parameter finite. Throws std::runtime_error with the first problem found.
void ValidateModel(const BRepModel& model);

/// Closure of one solid (or loose shell: Face::Solid) of a model.
struct SolidCheck
{
  int Faces = 0;
  /// Edges bounding only one face of the solid (a seam is not free): the shell is open.
  int FreeEdges = 0;
  /// Edges shared by more than two faces: the solid is non-manifold (a fin, two bodies touching
  /// along an edge), and a sphere cannot tell its inside.
  int NonManifoldEdges = 0;
  std::array<double, 3> FreeEdgeAt{}; ///< a point of the first free or non-manifold edge
  /// Volume enclosed by the display mesh (divergence theorem), negative for a solid whose
  /// normals point inwards; only meaningful when the mesh covers every face and FreeEdges == 0.
  double Volume = 0.0;
  /// The outermost points' vote (+1: the faces there face outwards, -1: inwards, 0: no vote or
  /// a tie): at the display mesh's farthest vertices along +-x, +-y and +-z, a closed solid's
  /// outward normals point away from it whatever its other faces hold; the majority of the six
  /// directions decides. Where a face's loops are damaged
  /// (FreeCAD wrote a plane's outer loop as a hole: Thor's Art4BodyBot.step), its mesh covers
  /// another area and the volume's sign lies, while these points still tell.
  int Outward = 0;
  bool Closed() const { return FreeEdges == 0 && NonManifoldEdges == 0; }
  /// Whether the solid's normals point inwards: by the outermost points where they vote, by the
  /// volume's sign where they do not.
  bool InsideOut() const { return Outward != 0 ? Outward < 0 : Volume < 0.0; }
};

/// One entry per solid index 0 .. max(Face::Solid).
/// (volumes false: Volume left 0, the display mesh not read; Closed() needs only the edges.)
std::vector<SolidCheck> CheckSolids(const BRepModel& model, bool volumes = true);

/// Splits each edge that bounds four or more faces of one solid where two bodies of it touch
/// along the edge (a casting blank's ribs meeting along a line, two blocks touching at an edge):
/// around the edge the faces, in order of angle, bound wedges of material in pairs, each pair
/// the faces of one wedge. The first pair keeps the edge; each other pair gets a copy of it (its
/// 3D segments copied, its faces' trimming segments moved to the copy), so that every edge bounds
/// two faces and the solid is closed. The wedges come from the faces' patches and trims at the
/// edge's middle: a face's direction into itself (the left of its trimming loop) and its
/// material side (against its outward normal, or along it in a solid whose display mesh encloses
/// a negative volume, checks[s].Volume). An edge whose faces do not pair so is left as it is (the
/// solid stays non-manifold). Returns the edges split.
std::vector<int> SplitNonManifoldEdges(BRepModel& model, const std::vector<SolidCheck>& checks);

/// Appends a copy of edge e (its segments copied too, numbered for the copy) and returns the
/// copy's index; the trimming segments still name e (the caller moves those that go to the copy).
int CopyEdge(BRepModel& model, int e);

/// Reverses every closed solid whose display mesh encloses a negative volume (its faces'
/// normals pointed inwards): Face::Reversed, the mesh normals and the triangles' winding.
/// Returns the indices of the solids reversed.
std::vector<int> OrientSolids(BRepModel& model, const std::vector<SolidCheck>& checks);
} // namespace brt
