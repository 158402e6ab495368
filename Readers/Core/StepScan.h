// BRepThickness: a check of a STEP file's text before OpenCASCADE parses it.
//
// OpenCASCADE's STEP import trusts its input: a reference to a missing entity or to one of the
// wrong type, an entity referring to itself or parentheses nested thousands deep crash it, and
// non-finite or absurd numbers make its healing loop. This scanner reads the exchange structure
// (ISO 10303-21) once, in linear time and without recursion, and rejects such files with the
// entity number and the line. It also counts what the file declares (faces, solids, surface
// models), so that the reader can tell what the transfer lost. Free of OpenCASCADE and VTK.
#pragma once

#include <string>
#include <unordered_map>
#include <vector>

namespace brt
{
struct StepScanResult
{
  long Entities = 0;
  long DeclaredFaces = 0;   ///< ADVANCED_FACE and FACE_SURFACE instances
  long DeclaredSolids = 0;  ///< MANIFOLD_SOLID_BREP (BREP_WITH_VOIDS included) and FACETED_BREP
  long SurfaceModels = 0;   ///< SHELL_BASED_SURFACE_MODEL instances
  std::vector<long> SolidIds; ///< entity numbers of the solids above, in file order
  double UnitInMillimetres = 1.0; ///< largest length unit the file declares (mm if none)
  /// Largest |coordinate| or radius of a geometric entity, in the file's unit, and where.
  double LargestCoordinate = 0.0;
  long LargestCoordinateEntity = 0;
  /// Problems that do not stop the read (a dangling reference in a colour or a note, a B-spline
  /// OpenCASCADE reads otherwise than written or not at all).
  std::vector<std::string> Warnings;
  /// Of those, the B-splines OpenCASCADE reads no curve or surface from (data that contradict
  /// each other: knots, multiplicities, degree, control points, weights), each naming its
  /// entity: a refusal of the file for an open solid repeats them.
  std::vector<std::string> UnreadGeometry;
  /// Entities that a geometric or topological entity refers to, with the first such referrer:
  /// after OpenCASCADE has parsed the file, one of them that it could not read (unknown type,
  /// damaged parameters) is an error, since its transfer dereferences it.
  std::unordered_map<long, long> GeometryTargets;
  /// Type name of each entity (a complex one's as "(A B C)").
  std::unordered_map<long, std::string> TypeNames;
  /// The STEP files an assembly names as the sources of its parts (an EXTERNAL_SOURCE's or a
  /// DOCUMENT_FILE's strings ending in .stp or .step), each once, in the file's order.
  std::vector<std::string> ExternalFiles;
  /// Each REPRESENTATION_MAP's mapped representation (its second reference).
  std::unordered_map<long, long> MappedRepresentations;
};

/// Largest coordinate or radius accepted, in millimetres (1,000 km).
constexpr double MaxCoordinateMillimetres = 1e9;
/// The largest B-spline knot the text check accepts, in the knots' own units (a parameter by arc
/// length in mm reaches the curve's length: 1,000 km at most, as a coordinate).
constexpr double MaxKnotValue = 1e9;
/// Deepest nesting of parentheses accepted (real files nest fewer than 10).
constexpr int MaxNesting = 64;

/// Checks the text of a STEP file; `path` only names it in messages. Throws InputError naming
/// the file, the line and the entity for the first problem found.
StepScanResult ScanStepText(const std::string& path, const std::string& text);

/// Reads the file and checks it (ScanStepText).
StepScanResult ScanStepFile(const std::string& path);
/// For an error after OpenCASCADE's transfer: the B-splines it read nothing from (scan's
/// UnreadGeometry, the first named and the others counted), as a sentence to append; empty if
/// none.
std::string DescribeUnreadGeometry(const StepScanResult& scan);

} // namespace brt
