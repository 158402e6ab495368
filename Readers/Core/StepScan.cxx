#include "StepScan.h"

#include "InputError.h"

#include <algorithm>
#include <map>
#include <set>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <unordered_map>

namespace brt
{
namespace
{
/// A parameter at the top level of a simple entity.
struct Param
{
  char Kind = 'o'; ///< 'r' reference, 'n' number, 's' string, 'e' enumeration, 'o' anything else
  long Ref = 0;
  double Value = 0.0;
};

struct Entity
{
  int Type = -1;      ///< interned name of a simple entity; -1 for a complex one
  std::string Parts;  ///< complex entity: ",A,B,C," (the partial entity names)
  long Line = 0;
  int Dim = 0;        ///< a CARTESIAN_POINT's or DIRECTION's number of coordinates
};

/// A reference whose target's type is checked once the whole file is read.
struct TypedRef
{
  long From = 0, To = 0, Line = 0;
  int Param = 0;
  const char* Expected = nullptr;
  int Pcurve = 0; ///< a Rule's PcurveRep or PcurveItem (0: neither)
  const char* Said = nullptr;
  int Dim = 0; ///< a Rule's Dim
};

/// The rules about a pcurve's definitional representation: the reference to it, and its items
/// (checked only where a pcurve refers to it; elsewhere a definitional representation may hold
/// other items).
constexpr int PcurveRep = 1, PcurveItem = 2;

/// The curves of STEP (simple entities, and the partial entities of complex ones).
#define BRT_STEP_CURVES                                                                            \
  "LINE|CIRCLE|ELLIPSE|HYPERBOLA|PARABOLA|CONIC|B_SPLINE_CURVE_WITH_KNOTS|B_SPLINE_CURVE|"          \
  "BEZIER_CURVE|UNIFORM_CURVE|QUASI_UNIFORM_CURVE|RATIONAL_B_SPLINE_CURVE|TRIMMED_CURVE|"          \
  "COMPOSITE_CURVE|POLYLINE|OFFSET_CURVE_2D|OFFSET_CURVE_3D|CURVE_REPLICA|SURFACE_CURVE|"          \
  "SEAM_CURVE|INTERSECTION_CURVE|PCURVE|BOUNDED_CURVE|CURVE"

/// Parameters whose references must point at given types (alternatives separated by '|').
/// List = true: the parameter is a list whose elements are checked. Pcurve: PcurveRep or
/// PcurveItem (above), 0 for the others. Said: how the error names what is required (nullptr:
/// the types).
struct Rule
{
  const char* Type;
  int Param;
  const char* Expected;
  bool List;
  int Pcurve = 0;
  const char* Said = nullptr;
  /// The target's number of coordinates, where a point or direction must have it (0: any). A
  /// vertex on a point of 2 coordinates crashed OpenCASCADE 7.6 (a mutation of NIST_MBE_PMI_11
  /// that dropped a coordinate: 41 of 900 variants, fifty-ninth session).
  int Dim = 0;
};
const Rule Rules[] = {
  // A pcurve's curve in the face's parameters: OpenCASCADE 7.6 dereferences the first item of
  // its definitional representation as a curve (a point, a direction or a placement there, or
  // no item at all, crashed it: a mutation of an OpenCASCADE export of a screw, twenty-fifth
  // session). Elsewhere a definitional representation may hold other items.
  { "PCURVE", 2, "DEFINITIONAL_REPRESENTATION", false, PcurveRep, nullptr },
  { "DEFINITIONAL_REPRESENTATION", 1, BRT_STEP_CURVES, true, PcurveItem, "a curve" },
  // The same written as a complex entity, (DEFINITIONAL_REPRESENTATION() REPRESENTATION('',
  // (items), context) SHAPE_REPRESENTATION()): the items are the REPRESENTATION part's (files
  // of OpenCASCADE's test data, trj4_k1_geo-ac-214.stp among them).
  { "REPRESENTATION", 1, BRT_STEP_CURVES, true, PcurveItem, "a curve" },
  { "VERTEX_POINT", 1, "CARTESIAN_POINT", false, 0, nullptr, 3 },
  { "AXIS2_PLACEMENT_3D", 1, "CARTESIAN_POINT", false, 0, nullptr, 3 },
  { "AXIS2_PLACEMENT_3D", 2, "DIRECTION", false, 0, nullptr, 3 },
  { "AXIS2_PLACEMENT_3D", 3, "DIRECTION", false, 0, nullptr, 3 },
  { "AXIS2_PLACEMENT_2D", 1, "CARTESIAN_POINT", false, 0, nullptr, 2 },
  { "AXIS2_PLACEMENT_2D", 2, "DIRECTION", false, 0, nullptr, 2 },
  { "AXIS1_PLACEMENT", 1, "CARTESIAN_POINT", false, 0, nullptr, 3 },
  { "AXIS1_PLACEMENT", 2, "DIRECTION", false, 0, nullptr, 3 },
  { "VECTOR", 1, "DIRECTION", false },
  { "LINE", 1, "CARTESIAN_POINT", false },
  { "LINE", 2, "VECTOR", false },
  { "CIRCLE", 1, "AXIS2_PLACEMENT_3D|AXIS2_PLACEMENT_2D", false },
  { "ELLIPSE", 1, "AXIS2_PLACEMENT_3D|AXIS2_PLACEMENT_2D", false },
  { "PLANE", 1, "AXIS2_PLACEMENT_3D", false },
  { "CYLINDRICAL_SURFACE", 1, "AXIS2_PLACEMENT_3D", false },
  { "CONICAL_SURFACE", 1, "AXIS2_PLACEMENT_3D", false },
  { "SPHERICAL_SURFACE", 1, "AXIS2_PLACEMENT_3D", false },
  { "TOROIDAL_SURFACE", 1, "AXIS2_PLACEMENT_3D", false },
  { "EDGE_CURVE", 1, "VERTEX_POINT", false },
  { "EDGE_CURVE", 2, "VERTEX_POINT", false },
  { "ORIENTED_EDGE", 3, "EDGE_CURVE|ORIENTED_EDGE", false },
  { "EDGE_LOOP", 1, "ORIENTED_EDGE", true },
  { "FACE_BOUND", 1, "EDGE_LOOP|VERTEX_LOOP|POLY_LOOP", false },
  { "FACE_OUTER_BOUND", 1, "EDGE_LOOP|VERTEX_LOOP|POLY_LOOP", false },
  { "ADVANCED_FACE", 1, "FACE_BOUND|FACE_OUTER_BOUND", true },
  { "MANIFOLD_SOLID_BREP", 1, "CLOSED_SHELL|ORIENTED_CLOSED_SHELL", false },
  { "BREP_WITH_VOIDS", 1, "CLOSED_SHELL|ORIENTED_CLOSED_SHELL", false },
  { "BREP_WITH_VOIDS", 2, "ORIENTED_CLOSED_SHELL", true },
  { "ORIENTED_CLOSED_SHELL", 2, "CLOSED_SHELL", false },
  { "CLOSED_SHELL", 1, "ADVANCED_FACE|FACE_SURFACE|ORIENTED_FACE|FACE", true },
  { "OPEN_SHELL", 1, "ADVANCED_FACE|FACE_SURFACE|ORIENTED_FACE|FACE", true },
  { "SHELL_BASED_SURFACE_MODEL", 1, "OPEN_SHELL|CLOSED_SHELL|ORIENTED_OPEN_SHELL|ORIENTED_CLOSED_SHELL", true },
  // Control points: simple entities carry a name first, the partial entities of a complex
  // (rational) B-spline do not.
  { "B_SPLINE_CURVE_WITH_KNOTS", 2, "CARTESIAN_POINT", true },
  { "BEZIER_CURVE", 2, "CARTESIAN_POINT", true },
  { "UNIFORM_CURVE", 2, "CARTESIAN_POINT", true },
  { "QUASI_UNIFORM_CURVE", 2, "CARTESIAN_POINT", true },
  { "B_SPLINE_CURVE", 1, "CARTESIAN_POINT", true },
  { "B_SPLINE_SURFACE_WITH_KNOTS", 3, "CARTESIAN_POINT", true },
  { "BEZIER_SURFACE", 3, "CARTESIAN_POINT", true },
  { "UNIFORM_SURFACE", 3, "CARTESIAN_POINT", true },
  { "QUASI_UNIFORM_SURFACE", 3, "CARTESIAN_POINT", true },
  { "B_SPLINE_SURFACE", 2, "CARTESIAN_POINT", true },
  { "POLYLINE", 1, "CARTESIAN_POINT", true },
};

/// Radii and lengths that must be positive: (type, parameter).
struct Positive
{
  const char* Type;
  int Param;
  const char* What;
};
const Positive Positives[] = {
  { "CIRCLE", 2, "radius" },
  { "ELLIPSE", 2, "first semi-axis" },
  { "ELLIPSE", 3, "second semi-axis" },
  { "CYLINDRICAL_SURFACE", 2, "radius" },
  { "SPHERICAL_SURFACE", 2, "radius" },
  { "TOROIDAL_SURFACE", 2, "major radius" },
  { "TOROIDAL_SURFACE", 3, "minor radius" },
  { "VECTOR", 2, "magnitude" },
};

/// Geometric and topological entities, by the words in their (partial) type names. Presentation
/// entities are not, whatever words their names hold (SURFACE_SIDE_STYLE, CURVE_STYLE,
/// ANNOTATION_PLANE, DRAUGHTING_PRE_DEFINED_CURVE_FONT): the shape's transfer
/// (STEPControl_Reader) never reads them, so a style OpenCASCADE cannot read loses a colour,
/// not geometry. Inventor's exports through ST-Developer write each colour's
/// SURFACE_STYLE_RENDERING_WITH_PROPERTIES with its rendering method unset ($), which
/// OpenCASCADE flags as damaged: 16 of the 22 STEP files of Prusa's Original Prusa i3 parts
/// were refused for it (docs/Robustness.md).
bool IsGeometric(const std::string& type)
{
  // Nor are constructive solids and their features (BOOLEAN_RESULT, CSG_SOLID,
  // EDGE_BLEND_FILLET_FIXED_RADIUS: CAx-IF's ch1 files write a blend of a Boolean beside the
  // B-Rep): the B-Rep's transfer never reads them either.
  static const char* const presentation[] = { "STYLE", "COLOUR", "PRESENTATION", "DRAUGHTING",
    "ANNOTATION", "BLEND", "BOOLEAN", "CSG" };
  for (const char* w : presentation)
    if (type.find(w) != std::string::npos)
      return false;
  static const char* const words[] = { "POINT", "DIRECTION", "VECTOR", "PLACEMENT", "LINE",
    "CIRCLE", "ELLIPSE", "HYPERBOLA", "PARABOLA", "CURVE", "SURFACE", "PLANE", "EDGE", "VERTEX",
    "LOOP", "FACE", "SHELL", "BREP", "SOLID", "BOUND", "SHAPE_REPRESENTATION", "MAPPED_ITEM",
    "TRANSFORMATION", "ITEM_DEFINED" };
  for (const char* w : words)
    if (type.find(w) != std::string::npos)
      return true;
  return false;
}

bool IsIdStart(unsigned char c)
{
  return std::isalpha(c) || c == '_' || c == '!';
}
bool IsIdChar(unsigned char c)
{
  return std::isalnum(c) || c == '_' || c == '-';
}
bool IsNumberChar(unsigned char c)
{
  return std::isdigit(c) || c == '.' || c == '+' || c == '-' || c == 'E' || c == 'e';
}

class Scanner
{
public:
  Scanner(const std::string& path, const std::string& text)
    : Path(path)
    , Text(text)
  {
  }

  StepScanResult Run();

private:
  [[noreturn]] void Fail(const std::string& what) const
  {
    std::string where = "line " + std::to_string(this->Line);
    if (this->Current > 0)
      where += ", entity #" + std::to_string(this->Current);
    throw InputError("STEP file '" + this->Path + "': " + where + ": " + what);
  }

  /// Skips white space and comments from `i`; returns the next significant position.
  size_t SkipBlank(size_t i)
  {
    const size_t n = this->Text.size();
    while (i < n)
    {
      const char c = this->Text[i];
      if (c == '\n')
      {
        ++this->Line;
        ++i;
      }
      else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v')
        ++i;
      else if (c == '/' && i + 1 < n && this->Text[i + 1] == '*')
      {
        const size_t end = this->Text.find("*/", i + 2);
        if (end == std::string::npos)
          this->Fail("a comment (/*) is never closed");
        this->Line += std::count(this->Text.begin() + static_cast<long>(i),
          this->Text.begin() + static_cast<long>(end), '\n');
        i = end + 2;
      }
      else
        break;
    }
    return i;
  }

  int Intern(const std::string& name)
  {
    auto it = this->TypeIds.find(name);
    if (it != this->TypeIds.end())
      return it->second;
    const int id = static_cast<int>(this->TypeNames.size());
    this->TypeNames.push_back(name);
    this->TypeIds.emplace(name, id);
    return id;
  }

  bool HasType(const Entity& e, const std::string& name) const
  {
    if (e.Type >= 0)
      return this->TypeNames[static_cast<size_t>(e.Type)] == name;
    return e.Parts.find("," + name + ",") != std::string::npos;
  }

  std::string TypeText(const Entity& e) const
  {
    if (e.Type >= 0)
      return this->TypeNames[static_cast<size_t>(e.Type)];
    std::string p = e.Parts.substr(1, e.Parts.size() > 1 ? e.Parts.size() - 2 : 0);
    std::replace(p.begin(), p.end(), ',', ' ');
    return "(" + p + ")";
  }

  void EndEntity(size_t begin, size_t end);
  void Geometry(double v, const char* what);

  const std::string& Path;
  const std::string& Text;
  long Line = 1;
  long Current = 0;      ///< entity being read (0: none)
  std::string CurrentType; ///< its simple type name, or "" for a complex one
  std::string Parts;     ///< its partial names when complex
  std::vector<Param> Params;
  std::vector<double> Coordinates; ///< numbers in the list that is parameter 1
  /// The entity or partial entity whose parameters are being read (a complex entity's parts
  /// open at depth 2), and the index of its current parameter.
  std::string PartName;
  int PartBase = 0;
  int PartParam = 0;
  /// A B-spline as the text check reads it, written as a simple entity or as the partial
  /// entities of a complex one (SplineSlotOf): its degrees, the control net's and the weights'
  /// rows (a curve has one row), the knots and their multiplicities in each direction (0: u, or
  /// the curve's; 1: v) and the smallest weight. CheckSpline checks them where the entity ends.
  struct SplineData
  {
    bool Surface = false;
    double Degree[2] = { -1.0, -1.0 };
    bool Net = false, Weights = false;
    std::vector<int> NetRows, WeightRows;
    bool HasMults[2] = { false, false }, HasKnots[2] = { false, false };
    std::vector<double> Mults[2], Knots[2];
    std::vector<double> WeightValues; ///< row by row
  } Spline;
  void CheckSpline();
  /// The list being read that must not be empty (NonEmptyListName: a B-spline's knots or
  /// multiplicities, an edge loop's edges, ...): what it holds, how many items so far, and
  /// whether its numbers are knots (bounded by MaxKnotValue).
  struct CheckedList
  {
    const char* Of = nullptr; ///< nullptr: none open
    int Items = 0;
    bool Knots = false;
  } Listed;
  /// Where a list opens (level 0: the parameter's own list, 1: a row in it) or a reference or
  /// number stands in one, counts it into Spline and Listed.
  void CountSplineList(int level);
  void CountSplineItem(int level, bool reference, double value = 0.0);
  std::unordered_map<long, Entity> Entities;
  std::unordered_map<std::string, int> TypeIds;
  std::vector<std::string> TypeNames;
  std::vector<std::pair<long, long>> Refs; ///< (from, to), checked at the end
  std::vector<long> RefLines;
  std::vector<TypedRef> Typed;
  StepScanResult Result;
};

namespace
{
/// Lists of simple entities that OpenCASCADE 7.6 crashed on when empty (the mutation corpus's
/// emptied lists, fifty-ninth session): the type, the parameter (counted from 0, the name
/// included) and what the list holds.
struct NonEmptyList
{
  const char* Type;
  int Param;
  const char* What;
};
const NonEmptyList NonEmptyLists[] = {
  { "EDGE_LOOP", 1, "edge" },
  { "SURFACE_CURVE", 2, "curve-on-surface (associated geometry)" },
  { "SEAM_CURVE", 2, "curve-on-surface (associated geometry)" },
  { "APPLIED_DATE_AND_TIME_ASSIGNMENT", 2, "item" },
  { "APPLIED_DATE_ASSIGNMENT", 2, "item" },
  { "APPLIED_PERSON_AND_ORGANIZATION_ASSIGNMENT", 2, "item" },
  { "APPLIED_ORGANIZATION_ASSIGNMENT", 2, "item" },
  { "APPLIED_APPROVAL_ASSIGNMENT", 1, "item" },
  { "APPLIED_SECURITY_CLASSIFICATION_ASSIGNMENT", 1, "item" },
  { "CC_DESIGN_DATE_AND_TIME_ASSIGNMENT", 2, "item" },
  { "CC_DESIGN_PERSON_AND_ORGANIZATION_ASSIGNMENT", 2, "item" },
  { "CC_DESIGN_SECURITY_CLASSIFICATION", 1, "item" },
  { "CC_DESIGN_APPROVAL", 1, "item" },
  { "CC_DESIGN_CERTIFICATION", 1, "item" },
  { "CC_DESIGN_CONTRACT", 1, "item" },
};

/// Whether parameter `param` of `part` (a simple entity's, counted from its name, or a complex
/// one's partial entity's, `inComplex`) is a list that must not be empty: a B-spline's knot or
/// multiplicity list, or one of NonEmptyLists; what its items are.
const char* NonEmptyListName(const std::string& part, int param, bool inComplex)
{
  if (!inComplex)
    for (const NonEmptyList& l : NonEmptyLists)
      if (param == l.Param && part == l.Type)
        return l.What;
  static const char* const curveLists[] = { "knot multiplicities", "knots" };
  static const char* const surfaceLists[] = { "u knot multiplicities", "v knot multiplicities",
    "u knots", "v knots" };
  if (part == "B_SPLINE_CURVE_WITH_KNOTS")
  {
    const int k = param - (inComplex ? 0 : 6);
    return k >= 0 && k < 2 ? curveLists[k] : nullptr;
  }
  if (part == "B_SPLINE_SURFACE_WITH_KNOTS")
  {
    const int k = param - (inComplex ? 0 : 8);
    return k >= 0 && k < 4 ? surfaceLists[k] : nullptr;
  }
  return nullptr;
}

/// What parameter `param` of `part` holds of a B-spline (ISO 10303-42's
/// B_SPLINE_CURVE_WITH_KNOTS and B_SPLINE_SURFACE_WITH_KNOTS as simple entities, their Bezier,
/// uniform and quasi-uniform forms, or the partial entities B_SPLINE_CURVE, B_SPLINE_SURFACE,
/// their _WITH_KNOTS and RATIONAL_ forms in a complex one).
enum SplineSlot
{
  NotSpline,
  DegreeU,
  DegreeV,
  ControlNet,
  MultsU,
  MultsV,
  KnotsU,
  KnotsV,
  WeightList
};
SplineSlot SplineSlotOf(const std::string& part, int param, bool inComplex)
{
  const char c = part.empty() ? '\0' : part[0];
  if (c != 'B' && c != 'R' && c != 'U' && c != 'Q')
    return NotSpline;
  if (!inComplex)
  {
    // The knotless forms (their knots implied): their control nets alone.
    if (part == "BEZIER_CURVE" || part == "UNIFORM_CURVE" || part == "QUASI_UNIFORM_CURVE")
      return param == 1 ? DegreeU : param == 2 ? ControlNet : NotSpline;
    if (part == "BEZIER_SURFACE" || part == "UNIFORM_SURFACE" || part == "QUASI_UNIFORM_SURFACE")
      return param == 1 ? DegreeU : param == 2 ? DegreeV : param == 3 ? ControlNet : NotSpline;
    if (part == "B_SPLINE_CURVE_WITH_KNOTS")
    {
      const SplineSlot slots[] = { NotSpline, DegreeU, ControlNet, NotSpline, NotSpline,
        NotSpline, MultsU, KnotsU };
      return param >= 0 && param < 8 ? slots[param] : NotSpline;
    }
    if (part == "B_SPLINE_SURFACE_WITH_KNOTS")
    {
      const SplineSlot slots[] = { NotSpline, DegreeU, DegreeV, ControlNet, NotSpline,
        NotSpline, NotSpline, NotSpline, MultsU, MultsV, KnotsU, KnotsV };
      return param >= 0 && param < 12 ? slots[param] : NotSpline;
    }
    return NotSpline;
  }
  if (part == "B_SPLINE_CURVE")
    return param == 0 ? DegreeU : param == 1 ? ControlNet : NotSpline;
  if (part == "B_SPLINE_SURFACE")
    return param == 0 ? DegreeU : param == 1 ? DegreeV : param == 2 ? ControlNet : NotSpline;
  if (part == "B_SPLINE_CURVE_WITH_KNOTS")
    return param == 0 ? MultsU : param == 1 ? KnotsU : NotSpline;
  if (part == "B_SPLINE_SURFACE_WITH_KNOTS")
  {
    const SplineSlot slots[] = { MultsU, MultsV, KnotsU, KnotsV };
    return param >= 0 && param < 4 ? slots[param] : NotSpline;
  }
  if (part == "RATIONAL_B_SPLINE_CURVE" || part == "RATIONAL_B_SPLINE_SURFACE")
    return param == 0 ? WeightList : NotSpline;
  return NotSpline;
}
} // namespace

void Scanner::CountSplineList(int level)
{
  if (level == 0)
    if (const char* name = NonEmptyListName(this->PartName, this->PartParam, this->PartBase == 2))
    {
      const size_t len = std::strlen(name);
      this->Listed = { name, 0, len >= 5 && std::strcmp(name + len - 5, "knots") == 0 };
    }
  const SplineSlot slot = SplineSlotOf(this->PartName, this->PartParam, this->PartBase == 2);
  if (slot == NotSpline)
    return;
  SplineData& s = this->Spline;
  const bool surface = this->PartName.find("SURFACE") != std::string::npos;
  s.Surface = s.Surface || surface;
  if (slot == ControlNet || slot == WeightList)
  {
    const bool net = slot == ControlNet;
    std::vector<int>& rows = net ? s.NetRows : s.WeightRows;
    if (level == 0)
    {
      (net ? s.Net : s.Weights) = true;
      rows.clear();
      if (!surface)
        rows.push_back(0);
    }
    else if (level == 1 && surface)
      rows.push_back(0);
    return;
  }
  if (level != 0 || slot == DegreeU || slot == DegreeV)
    return;
  const int k = slot == MultsV || slot == KnotsV ? 1 : 0;
  const bool mults = slot == MultsU || slot == MultsV;
  (mults ? s.HasMults : s.HasKnots)[k] = true;
  (mults ? s.Mults : s.Knots)[k].clear();
}

void Scanner::CountSplineItem(int level, bool reference, double value)
{
  // A knot far beyond any parametrisation a CAD system writes (by arc length in mm a knot
  // reaches the curve's length): one of 1e300 in the ExpansionCard's curve made OpenCASCADE
  // 7.6 run past 120 s (the mutation corpus, fifty-ninth session).
  if (this->Listed.Knots && level == 1 && !reference && !(std::fabs(value) <= MaxKnotValue))
  {
    std::ostringstream w;
    w << "its " << this->PartName << "'s " << this->Listed.Of << " list holds " << value
      << ", beyond " << MaxKnotValue << ": not a parametrisation any CAD system writes";
    this->Fail(w.str());
  }
  const SplineSlot slot = SplineSlotOf(this->PartName, this->PartParam, this->PartBase == 2);
  if (slot == NotSpline)
    return;
  SplineData& s = this->Spline;
  const int rowLevel = this->PartName.find("SURFACE") != std::string::npos ? 2 : 1;
  if (slot == ControlNet || slot == WeightList)
  {
    std::vector<int>& rows = slot == ControlNet ? s.NetRows : s.WeightRows;
    if (level == rowLevel && reference == (slot == ControlNet) && !rows.empty())
      ++rows.back();
    if (slot == WeightList && level == rowLevel && !reference)
      s.WeightValues.push_back(value);
    return;
  }
  if (reference)
    return;
  if (level == 0 && (slot == DegreeU || slot == DegreeV))
    s.Degree[slot == DegreeV ? 1 : 0] = value;
  else if (level == 1 && slot != DegreeU && slot != DegreeV)
  {
    const int k = slot == MultsV || slot == KnotsV ? 1 : 0;
    (slot == MultsU || slot == MultsV ? s.Mults : s.Knots)[k].push_back(value);
  }
}

namespace
{
/// Whether OpenCASCADE 7.6 builds one direction of a B-spline from the file's degree, number of
/// control points, multiplicities and knots, as StepToGeom and Geom_BSplineCurve (or _Surface)
/// do: knots within a rounding of the last one kept (or below it) are joined to it, their
/// multiplicities added; a curve's multiplicities above its degree plus 1 are lowered to that,
/// an end's excess taking as many control points off that end; the
/// B-spline is periodic where the sum is not the control points and degree plus 1 but the sum
/// less the first multiplicity is the control points; Geom then refuses it unless its control
/// points are exactly as many as its multiplicities and degree give (BSplCLib::NbPoles).
bool OpenCascadeBuilds(bool curve, int degree, long poles, const std::vector<double>& mults,
  const std::vector<double>& knots, size_t* joinedIncreasing)
{
  long trimmed = 0;
  *joinedIncreasing = 0;
  if (knots.size() != mults.size() || mults.empty())
    return false; // (refused before)
  for (const double m : mults)
    if (!(m >= -1e6 && m <= 1e6 && m == std::floor(m)))
      return false;
  std::vector<long> joined;
  double last = knots[0];
  joined.push_back(static_cast<long>(mults[0]));
  for (size_t i = 1; i < mults.size(); ++i)
  {
    if (knots[i] - last > std::nextafter(std::fabs(last), HUGE_VAL) - std::fabs(last))
    {
      joined.push_back(static_cast<long>(mults[i]));
      last = knots[i];
    }
    else
    {
      joined.back() += static_cast<long>(mults[i]);
      if (knots[i] > knots[i - 1] && *joinedIncreasing == 0)
        *joinedIncreasing = i;
    }
  }
  if (joined.size() < 2 || degree < 1 || degree > 25)
    return false;
  if (curve)
    for (size_t i = 0; i < joined.size(); ++i)
      if (joined[i] > degree + 1)
      {
        if (i == 0 || i + 1 == joined.size())
          trimmed += joined[i] - degree - 1;
        joined[i] = degree + 1;
      }
  long sum = 0;
  for (const long j : joined)
    sum += j;
  const long mf = joined.front(), ml = joined.back();
  const bool periodic = sum != poles + degree + 1 && mf == ml && sum - mf == poles;
  if (mf <= 0 || ml <= 0)
    return false;
  long sigma = periodic ? mf : mf + ml - degree - 1;
  if (periodic ? (mf > degree || ml > degree || mf != ml) : (mf > degree + 1 || ml > degree + 1))
    return false;
  for (size_t i = 1; i + 1 < joined.size(); ++i)
  {
    if (joined[i] <= 0 || joined[i] > degree)
      return false;
    sigma += joined[i];
  }
  return sigma == poles - trimmed;
}
} // namespace

void Scanner::CheckSpline()
{
  const SplineData& s = this->Spline;
  if (!s.Net)
    return;
  const char* what = s.Surface ? "surface" : "curve";
  // ISO 10303-42's rules for a B-spline (constraints_param_b_spline, a rational one's
  // weights_data), in order: the first one broken is the problem named.
  std::string problem;
  auto broken = [&](const std::ostringstream& w) {
    if (problem.empty())
      problem = w.str();
  };
  // Whether OpenCASCADE 7.6 builds it (OpenCascadeBuilds; a rational one's weights are read for
  // as many control points as the file has, and must be positive).
  bool builds = true;
  const int dirs = s.Surface ? 2 : 1;
  // The control net: a list of points, or for a surface a list of rows of one length (ISO
  // 10303-42's LIST [2:?] OF LIST [2:?]). OpenCASCADE 7.6 sizes the net by its first row: a
  // later row with fewer points, or none, it reads past its end (an emptied row of the cubic
  // ridge's surface crashed it, a shorter one made it call the surface damaged), a longer one
  // it reads in part, and a shorter first row makes it read another net. Refused.
  if (s.NetRows.empty() || s.NetRows.front() == 0)
    this->Fail(std::string("its B-spline ") + what + " has no control points");
  if (std::any_of(s.NetRows.begin(), s.NetRows.end(),
        [&](int r) { return r != s.NetRows.front(); }))
  {
    const auto [shortest, longest] = std::minmax_element(s.NetRows.begin(), s.NetRows.end());
    this->Fail("its B-spline surface's control net has rows of " + std::to_string(*shortest) +
      " to " + std::to_string(*longest) + " points: a control net's rows are all of one length");
  }
  for (int k = 0; k < dirs; ++k)
  {
    if (!s.HasMults[k] || !s.HasKnots[k])
      continue; // no knots written (a Bezier or uniform form), or an empty list (refused)
    // Lists that hold no number (a libFuzzer input wrote strings there, sixtieth session):
    // OpenCASCADE's parser calls such an entity damaged, which the check after it reports.
    if (s.Mults[k].empty() || s.Knots[k].empty())
      continue;
    const std::string dir = s.Surface ? (k ? "v " : "u ") : "";
    // (A degree outside 1-25 is refused below: as an int it is only compared.)
    const int degree = s.Degree[k] >= 1.0 && s.Degree[k] <= 25.0 ? static_cast<int>(s.Degree[k]) : -1;
    const long poles = k == 0 ? (s.Surface ? static_cast<long>(s.NetRows.size()) : s.NetRows[0])
                              : s.NetRows.front();
    const std::vector<double>& m = s.Mults[k];
    const std::vector<double>& u = s.Knots[k];
    // Lists of unequal length: OpenCASCADE 7.6 reads one by the other's count, past its end
    // (its release build does not check the index): read memory it does not own, or a B-spline
    // built from it (a mutation of Data/cubic_ridge.step with 1 multiplicity for 2 knots read as
    // a surface). Refused.
    if (u.size() != m.size())
    {
      std::ostringstream w;
      w << "its " << (s.Surface ? "B-spline surface" : "B-spline curve") << " has " << u.size()
        << " " << dir << "knots for " << m.size() << " " << dir
        << "knot multiplicities: a B-spline has one multiplicity for each knot";
      this->Fail(w.str());
    }
    size_t joinedAt = 0;
    builds = OpenCascadeBuilds(!s.Surface, degree, poles, m, u, &joinedAt) && builds;
    if (degree < 1 || s.Degree[k] != std::floor(s.Degree[k]))
    {
      std::ostringstream w;
      w << "its " << dir << "degree is " << s.Degree[k] << ": a B-spline's degree is 1 to 25";
      broken(w);
    }
    bool whole = true;
    for (size_t i = 0; i < m.size() && whole; ++i)
      if (!(m[i] >= 1.0 && m[i] <= 1e6 && m[i] == std::floor(m[i])))
      {
        std::ostringstream x;
        x << "it has a " << dir << "knot multiplicity of " << m[i]
          << (m[i] > 1e6 ? ": more than any control net's points"
                         : ": a multiplicity is a whole number, 1 or more");
        broken(x);
        whole = false;
      }
    for (size_t i = 1; i < u.size(); ++i)
      if (!(u[i] > u[i - 1]))
      {
        std::ostringstream x;
        x << "its " << dir << "knots do not increase (" << u[i - 1] << " then " << u[i]
          << "): a B-spline's knots increase";
        broken(x);
        break;
      }
    if (!whole)
      continue;
    long sum = 0;
    for (size_t i = 0; i < m.size(); ++i)
      sum += static_cast<long>(m[i]);
    if (sum != poles + degree + 1)
    {
      std::ostringstream x;
      x << "its " << dir << "knot multiplicities add up to " << sum << " where its " << poles
        << " " << dir << "control points and degree " << degree << " need " << poles + degree + 1;
      broken(x);
    }
    for (size_t i = 0; i < m.size(); ++i)
    {
      const bool end = i == 0 || i + 1 == m.size();
      if (m[i] > degree + (end ? 1 : 0))
      {
        std::ostringstream x;
        x << "it has a" << (end ? "n end " : "n inner ") << dir << "knot of multiplicity " << m[i]
          << ", above its degree" << (end ? " plus 1" : "");
        broken(x);
        break;
      }
    }
    if (joinedAt > 0)
    {
      std::ostringstream x;
      x.precision(17);
      x << "its " << dir << "knots " << u[joinedAt - 1] << " and " << u[joinedAt]
        << " differ by a rounding only, and OpenCASCADE joins them into one";
      broken(x);
    }
    // Knots that span a rounding of their size (a mutation of the cubic ridge with knots 0 and
    // 1e-300): OpenCASCADE builds the surface, and its face then spans no area in its
    // parameters, kept without patches while it bounds the solid in space, so that spheres
    // leave the solid through it. The 136 real STEP files on disk span 2.5e-6 of their size
    // at least. Refused.
    const double span = u.back() - u.front(), size = std::max({ 1.0, std::fabs(u.front()),
                                                       std::fabs(u.back()) });
    if (span > 0.0 && span < 1e-12 * size)
    {
      std::ostringstream x;
      x << "its " << (s.Surface ? "B-spline surface's " : "B-spline curve's ") << dir
        << "knots span only " << span << " (from " << u.front() << " to " << u.back()
        << "): not a parametrisation any CAD system writes";
      this->Fail(x.str());
    }
  }
  if (s.Weights)
  {
    // One weight for each control point, positive. OpenCASCADE 7.6 reads as many weights as
    // there are control points: from a list (or a row) with fewer, past its end (an empty one
    // crashed it: a mutation of Data/l_bracket.step): refused. More (zellyn/dodgy-step-files's
    // Gn002) it reads, leaving the last out: a warning.
    std::ostringstream w;
    if (s.NetRows != s.WeightRows)
    {
      if (!s.Surface)
        w << "it has " << (s.WeightRows.empty() ? 0 : s.WeightRows[0]) << " weights for its "
          << s.NetRows[0] << " control points";
      else
      {
        auto shape = [](const std::vector<int>& rows) {
          std::ostringstream o;
          o << rows.size() << " rows of ";
          const bool even =
            std::all_of(rows.begin(), rows.end(), [&](int r) { return r == rows.front(); });
          if (rows.empty())
            o << "none";
          else if (even)
            o << rows.front();
          else
            o << "unequal lengths";
          return o.str();
        };
        w << "its weights (" << shape(s.WeightRows) << ") do not match its control points ("
          << shape(s.NetRows) << ")";
      }
      w << ": a rational B-spline has one weight for each control point";
      bool fewer = s.WeightRows.size() < s.NetRows.size();
      for (size_t r = 0; r < s.NetRows.size() && !fewer; ++r)
        fewer = s.WeightRows[r] < s.NetRows[r];
      if (fewer)
        this->Fail(w.str());
      broken(w);
    }
    // The weights OpenCASCADE reads: the first row's first ones for a curve; for a surface as
    // many rows, and in each as many, as the control net has.
    double least = HUGE_VAL;
    size_t at = 0;
    for (size_t r = 0; r < s.WeightRows.size(); ++r)
    {
      const bool read = r < s.NetRows.size();
      for (int j = 0; j < s.WeightRows[r] && at < s.WeightValues.size(); ++j, ++at)
      {
        const double v = s.WeightValues[at];
        if (!(v > 0.0))
        {
          std::ostringstream x;
          x << "it has a weight of " << v << ": a rational B-spline's weights are positive";
          broken(x);
        }
        if (read && j < s.NetRows[r])
          least = std::min(least, v);
      }
    }
    builds = builds && least > DBL_MIN;
  }
  if (problem.empty() && !builds)
    problem = "OpenCASCADE cannot build it from its degree, knots and control points";
  if (problem.empty())
    return;
  // OpenCASCADE 7.6 reads no curve or surface from a B-spline it cannot build, with no message
  // a user sees: a pcurve is rebuilt from its edge, and a face on such a surface is lost (its
  // solid then open: flagged, or the file refused for it). Each such B-spline gets a warning
  // that names it, and a refusal repeats it (StepScanResult::UnreadGeometry); one it builds
  // from data that break the rules gets a warning too.
  std::ostringstream w;
  w << "#" << this->Current << " (line " << this->Line << "), a B-spline " << what << ": "
    << problem << "; OpenCASCADE ";
  if (builds)
    w << "reads a " << what << " from it that may not be the one meant";
  else if (s.Surface)
    w << "reads no surface from it (a face on it is lost)";
  else
    w << "reads no curve from it (a pcurve is rebuilt from its edge; an edge on such a curve "
         "loses its faces)";
  this->Result.Warnings.push_back(w.str());
  if (!builds)
    this->Result.UnreadGeometry.push_back(w.str());
}

void Scanner::Geometry(double v, const char* what)
{
  if (std::fabs(v) > this->Result.LargestCoordinate)
  {
    this->Result.LargestCoordinate = std::fabs(v);
    this->Result.LargestCoordinateEntity = this->Current;
  }
  (void)what;
}

void Scanner::EndEntity(size_t begin, size_t end)
{
  Entity e;
  e.Line = this->Line;
  const std::string& type = this->CurrentType;
  if (type.empty())
    e.Parts = this->Parts;
  else
    e.Type = this->Intern(type);
  auto put = this->Entities.emplace(this->Current, e);
  if (!put.second)
    this->Fail("#" + std::to_string(this->Current) + " is defined twice (also at line " +
      std::to_string(put.first->second.Line) + ")");
  ++this->Result.Entities;
  auto is = [&](const char* name) { return this->HasType(e, name); };
  if (is("ADVANCED_FACE") || is("FACE_SURFACE"))
    ++this->Result.DeclaredFaces;
  if (is("MANIFOLD_SOLID_BREP") || is("BREP_WITH_VOIDS") || is("FACETED_BREP"))
  {
    ++this->Result.DeclaredSolids;
    this->Result.SolidIds.push_back(this->Current);
  }
  if (is("SHELL_BASED_SURFACE_MODEL"))
    ++this->Result.SurfaceModels;
  if (is("LENGTH_UNIT"))
  {
    // The unit's size: SI prefixes of the metre, or the common conversion-based units.
    const std::string body = this->Text.substr(begin, end - begin);
    std::string upper(body);
    std::transform(upper.begin(), upper.end(), upper.begin(),
      [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
    double mm = 1.0;
    if (upper.find(".METRE.") != std::string::npos)
    {
      mm = 1000.0;
      const std::pair<const char*, double> prefixes[] = { { ".MILLI.", 1.0 },
        { ".CENTI.", 10.0 }, { ".DECI.", 100.0 }, { ".KILO.", 1e6 }, { ".MICRO.", 1e-3 },
        { ".NANO.", 1e-6 } };
      for (const auto& p : prefixes)
        if (upper.find(p.first) != std::string::npos)
          mm = p.second;
    }
    if (upper.find("'INCH'") != std::string::npos)
      mm = 25.4;
    if (upper.find("'FOOT'") != std::string::npos)
      mm = 304.8;
    this->Result.UnitInMillimetres = std::max(this->Result.UnitInMillimetres, mm);
  }
  this->CheckSpline();
  if (type.empty())
    return;

  // Simple entities: reference types, positive radii, coordinates.
  const std::vector<Param>& p = this->Params;
  // A number, string or enumeration where a reference is required: OpenCASCADE reads no entity
  // there, and dereferenced the null (an AXIS2_PLACEMENT_3D whose location read "012", a
  // libFuzzer input, sixtieth session).
  for (const Rule& r : Rules)
    if (!r.List && type == r.Type && static_cast<size_t>(r.Param) < p.size() &&
      std::strchr("nse", p[static_cast<size_t>(r.Param)].Kind) != nullptr &&
      p[static_cast<size_t>(r.Param)].Kind != '\0')
    {
      std::string want = r.Said ? r.Said : r.Expected;
      std::replace(want.begin(), want.end(), '|', '/');
      this->Fail(type + " parameter " + std::to_string(r.Param + 1) + " is a " +
        (p[static_cast<size_t>(r.Param)].Kind == 'n' ? "number"
            : p[static_cast<size_t>(r.Param)].Kind == 's' ? "string" : "enumeration") +
        " where a reference to " + want + " is required");
    }
  for (const Positive& q : Positives)
  {
    if (type != q.Type || static_cast<size_t>(q.Param) >= p.size() || p[q.Param].Kind != 'n')
      continue;
    const double v = p[q.Param].Value;
    // A spindle torus's lemon (major radius below the minor) as Parasolid-based systems write
    // it: with a negative major radius (SolidWorks 2020, Ploopy's headbands; ISO 10303-42 asks
    // for a DEGENERATE_TOROIDAL_SURFACE). OpenCASCADE reads the torus of radius |R|, the same
    // points; its faces' sides come from their loops and the healing, and the checks after
    // the transfer (closed, oriented, valid) hold as for any face (docs/Robustness.md, item 3).
    const bool lemon = type == "TOROIDAL_SURFACE" && q.Param == 2 && v < 0.0 &&
      p.size() > 3 && p[3].Kind == 'n' && -v < p[3].Value;
    if (!(v > 0.0) && !lemon)
    {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%g", v);
      this->Fail(type + " has " + (v < 0.0 ? "a negative " : "a zero ") + q.What + " (" + buf +
        "): no solid has such a face or curve");
    }
    this->Geometry(std::fabs(v), q.What);
  }
  if (type == "CONICAL_SURFACE" && p.size() > 2 && p[2].Kind == 'n')
  {
    if (!(p[2].Value >= 0.0))
      this->Fail("CONICAL_SURFACE has a negative radius");
    this->Geometry(p[2].Value, "radius");
  }
  // The semi-angle lies strictly between 0 and 90 degrees (ISO 10303-42). OpenCASCADE reads one
  // of 0 or below as a cone of 1e-12 rad, nearly a cylinder, whose face then lies up to the
  // cone's spread off its own edges, with no warning (a mutated Voron part: its vertices 0.3 mm
  // off the surface, the file read and measured); 90 or more is no cone in radians or degrees.
  // Between pi/2 and 90 the file's angle unit decides, which this check does not read:
  // OpenCASCADE then fails on the face, and the solid left open is refused after the transfer.
  if (type == "CONICAL_SURFACE" && p.size() > 3 && p[3].Kind == 'n' &&
    !(p[3].Value > 0.0 && p[3].Value < 90.0))
  {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g", p[3].Value);
    this->Fail(std::string("CONICAL_SURFACE has a semi-angle of ") + buf +
      ", not between 0 and 90 degrees: no cone has such a face");
  }
  if (type == "CARTESIAN_POINT" || type == "DIRECTION")
  {
    const size_t n = this->Coordinates.size();
    if (n < 1 || n > 3)
      this->Fail(type + " has " + std::to_string(n) + " coordinates (1 to 3 expected)");
    put.first->second.Dim = static_cast<int>(n);
    for (double v : this->Coordinates)
      this->Geometry(v, "coordinate");
    if (type == "DIRECTION" && std::all_of(this->Coordinates.begin(), this->Coordinates.end(),
                                 [](double v) { return v == 0.0; }))
      this->Fail("DIRECTION has length zero: it points nowhere");
  }
}

StepScanResult Scanner::Run()
{
  const std::string& t = this->Text;
  const size_t n = t.size();
  bool inData = false;
  int depth = 0;
  // State at depth 0 in the data section: 0 expect '#N' or a keyword, 1 expect '=', 2 expect a
  // name or '(', 3 expect '(' after a simple entity's name, 4 expect ';'.
  int state = 0;
  int param = 0; // parameter index at depth 1 of a simple entity
  size_t entityBegin = 0;
  // Parameter separators: after a value only ',' or ')' may follow; ',' needs a value before
  // it; a name's '(' continues the name's value (typed parameter or partial entity).
  bool needSep = false, afterName = false, afterComma = false;
  auto value = [&]() {
    if (depth >= 1 && needSep)
      this->Fail("two parameters without a ',' between them");
    // A complex entity holds partial entities only, each a name with its parameters
    // (ISO 10303-21's subsuper record). A value or a nameless list beside them crashed
    // OpenCASCADE 7.6's parser (a libFuzzer input: "#5=((),'');", sixtieth session).
    if (inData && depth == 1 && this->CurrentType.empty() && this->Current > 0)
      this->Fail("a complex entity holds a parameter outside its partial entities (each part is "
                 "a name followed by its parameters)");
    needSep = true;
    afterComma = false;
    if (this->Listed.Of && depth - this->PartBase == 1)
      ++this->Listed.Items;
  };
  for (size_t i = this->SkipBlank(0); i < n; i = this->SkipBlank(i))
  {
    const unsigned char c = static_cast<unsigned char>(t[i]);
    const bool simple = !this->CurrentType.empty();
    if (c == '\'')
    {
      // A string: '' is a quote inside it (ISO 10303-21). OpenCASCADE 7.6's lexer ends a string
      // at the first quote followed by blanks (space, line break) and a ',' or ')', whether
      // doubled or not, and nowhere else. Where the two disagree (a string holding "'', " or
      // "'')", or closed by a quote followed by anything else), OpenCASCADE reads the rest of
      // the string as entities and parameters that this check never saw: a libFuzzer input so
      // crashed its parser past the check (sixtieth session). Refused; no real file on disk
      // holds such a string (a throwaway scan of 225 of them).
      size_t j = i + 1;
      auto endsForOpenCascade = [&](size_t q) {
        size_t k = q + 1;
        while (k < n && (t[k] == ' ' || t[k] == '\n' || t[k] == '\r'))
          ++k;
        return k < n && (t[k] == ',' || t[k] == ')');
      };
      for (;; ++j)
      {
        if (j >= n)
          this->Fail("a string (') is never closed");
        if (t[j] == '\n')
          ++this->Line;
        if (t[j] == '\'')
        {
          if (j + 1 < n && t[j + 1] == '\'')
          {
            if (endsForOpenCascade(j + 1))
              this->Fail("a string holds a quote followed by ',' or ')' (\"'',\" or \"'')\"): "
                         "OpenCASCADE's parser ends the string there and reads the rest as "
                         "parameters");
            ++j;
            continue;
          }
          if (!endsForOpenCascade(j))
            this->Fail("a string's closing quote is followed by something other than ',' or ')' "
                       "(blanks aside): OpenCASCADE's parser reads on as if the string went on");
          break;
        }
      }
      if (inData && depth == 0)
        this->Fail("a string outside an entity's parameters");
      // A file an assembly names as a part's source (StepScanResult::ExternalFiles).
      if (inData && (this->CurrentType == "EXTERNAL_SOURCE" || this->CurrentType == "DOCUMENT_FILE") &&
        j - i - 1 <= 256 && this->Result.ExternalFiles.size() < 1000)
      {
        std::string name = t.substr(i + 1, j - i - 1), upper = name;
        std::transform(upper.begin(), upper.end(), upper.begin(),
          [](unsigned char ch) { return static_cast<char>(std::toupper(ch)); });
        auto ends = [&](const char* x) {
          const size_t k = std::strlen(x);
          return upper.size() > k && upper.compare(upper.size() - k, k, x) == 0;
        };
        auto& files = this->Result.ExternalFiles;
        if ((ends(".STP") || ends(".STEP")) &&
          std::find(files.begin(), files.end(), name) == files.end())
          files.push_back(name);
      }
      value();
      if (simple && depth == 1)
      {
        if (static_cast<size_t>(param) >= this->Params.size())
          this->Params.resize(static_cast<size_t>(param) + 1);
        this->Params[static_cast<size_t>(param)].Kind = 's';
      }
      i = j + 1;
      continue;
    }
    if (c == '"')
    {
      const size_t end = t.find('"', i + 1);
      if (end == std::string::npos)
        this->Fail("a binary literal (\") is never closed");
      if (inData && depth == 0)
        this->Fail("a binary literal outside an entity's parameters");
      value();
      i = end + 1;
      continue;
    }
    if (c == '(')
    {
      if (depth >= 1 && !afterName)
        value();
      afterName = false;
      needSep = false;
      afterComma = false;
      if (inData && depth == 0)
      {
        if (state == 2)
        {
          this->CurrentType.clear(); // complex entity
          this->Parts = ",";
        }
        else if (state != 3)
          this->Fail("unexpected '('");
        state = 4;
        param = 0;
        this->PartName = this->CurrentType;
        this->PartBase = 1;
        this->PartParam = 0;
      }
      else if (inData && depth == 1 && this->CurrentType.empty() && this->Current > 0)
      {
        this->PartBase = 2; // a partial entity of a complex one; PartName set by its name
        this->PartParam = 0;
      }
      else if (inData && this->PartBase > 0 && depth >= this->PartBase)
        this->CountSplineList(depth - this->PartBase);
      if (++depth > MaxNesting)
        this->Fail("parentheses nested deeper than " + std::to_string(MaxNesting) +
          " levels: not an exchange structure any CAD system writes");
      ++i;
      continue;
    }
    if (c == ')')
    {
      if (afterComma)
        this->Fail("a parameter is missing after ','");
      if (--depth < 0)
        this->Fail("a ')' closes nothing");
      if (this->Listed.Of && depth == this->PartBase)
      {
        const std::string of = this->Listed.Of;
        if (this->Listed.Items == 0)
          this->Fail(this->PartName.find("B_SPLINE") != std::string::npos
              ? "its " + this->PartName + "'s " + of +
                " list is empty: a B-spline's knots and their multiplicities are never empty"
              : "its " + of + " list is empty: " +
                (std::strchr("AEIOU", this->PartName[0]) ? "an " : "a ") + this->PartName +
                " holds at least one");
        this->Listed = CheckedList();
      }
      needSep = depth >= 1;
      ++i;
      continue;
    }
    if (c == ',')
    {
      if (depth >= 1 && !needSep)
        this->Fail("a parameter is missing before ','");
      needSep = false;
      afterComma = true;
      if (depth == 1)
        ++param;
      if (depth == this->PartBase)
        ++this->PartParam;
      ++i;
      continue;
    }
    if (c == ';')
    {
      if (depth != 0)
        this->Fail("';' inside an entity's parameters: the entity is not closed");
      if (inData && this->Current > 0)
      {
        if (state != 4)
          this->Fail("an entity ends before its parameters");
        if (this->CurrentType.empty() && this->Parts == ",")
          this->Fail("a complex entity holds no partial entity");
        this->EndEntity(entityBegin, i);
      }
      else if (inData && state != 0)
        this->Fail("unexpected ';'");
      this->Current = 0;
      this->CurrentType.clear();
      this->Params.clear();
      this->Coordinates.clear();
      this->PartName.clear();
      this->PartBase = 0;
      this->Spline = SplineData();
      this->Listed = CheckedList();
      state = 0;
      needSep = afterName = afterComma = false;
      ++i;
      continue;
    }
    if (c == '#')
    {
      size_t j = i + 1;
      long id = 0;
      while (j < n && std::isdigit(static_cast<unsigned char>(t[j])))
      {
        if (id > 100000000000000L)
          this->Fail("an entity number has too many digits");
        id = id * 10 + (t[j] - '0');
        ++j;
      }
      if (j == i + 1)
        this->Fail("'#' without an entity number");
      // Outside DATA only the header's entities stand, which refer to nothing: an instance or a
      // reference there is data whose section was never opened ('ENDSEC;' and 'DATA;' left out
      // after the header, a generator's fixture of dodgy STEP files; OpenCASCADE's parser
      // refuses it, and the check had called its first reference a missing parameter).
      if (!inData)
        this->Fail(depth == 0
            ? "entity #" + std::to_string(id) +
              " stands outside the DATA section (no 'DATA;' opens a section before it)"
            : "a reference (#" + std::to_string(id) + ") outside the DATA section");
      if (inData && depth == 0)
      {
        if (state != 0)
          this->Fail("unexpected '#" + std::to_string(id) + "'");
        this->Current = id;
        entityBegin = i;
        state = 1;
        // OpenCASCADE's lexer reads "#N =" as one token: only blanks may separate them.
        size_t k = j;
        while (k < n && (t[k] == ' ' || t[k] == '\t'))
          ++k;
        if (k >= n || t[k] != '=')
          this->Fail("'#" + std::to_string(id) + "' must be followed by '=' on the same line");
      }
      else if (inData)
      {
        value();
        if (id == this->Current)
          this->Fail("#" + std::to_string(id) + " refers to itself");
        this->Refs.emplace_back(this->Current, id);
        this->RefLines.push_back(this->Line);
        const int level = depth - this->PartBase;
        this->CountSplineItem(level, true);
        if (level >= 0 && !this->PartName.empty())
          for (const Rule& r : Rules)
            if (r.Param == this->PartParam && (r.List ? level >= 1 : level == 0) &&
              this->PartName == r.Type)
              this->Typed.push_back(
                { this->Current, id, this->Line, r.Param, r.Expected, r.Pcurve, r.Said, r.Dim });
        if (simple && depth == 1)
        {
          if (static_cast<size_t>(param) >= this->Params.size())
            this->Params.resize(static_cast<size_t>(param) + 1);
          this->Params[static_cast<size_t>(param)] = { 'r', id, 0.0 };
        }
      }
      i = j;
      continue;
    }
    if (c == '=')
    {
      if (inData && !(depth == 0 && state == 1))
        this->Fail("unexpected '='");
      state = 2;
      ++i;
      continue;
    }
    if (c == '$' || c == '*')
    {
      // Outside the parameters (a libFuzzer input wrote "#59 =$LINE(...)"): OpenCASCADE's parser
      // drops that entity and binds the references to it to another one, a DIRECTION where a
      // pcurve's line stood, and its transfer crashed (sixtieth session).
      if (inData && depth == 0)
        this->Fail(std::string("'") + static_cast<char>(c) + "' outside an entity's parameters");
      value();
      ++i;
      continue;
    }
    if (c == '.' && i + 1 < n && IsIdStart(static_cast<unsigned char>(t[i + 1])))
    {
      // An enumeration value .NAME.
      size_t j = i + 1;
      while (j < n && IsIdChar(static_cast<unsigned char>(t[j])))
        ++j;
      if (j >= n || t[j] != '.')
        this->Fail("an enumeration value (.NAME.) is not closed");
      if (inData && depth == 0)
        this->Fail("an enumeration value outside an entity's parameters");
      value();
      if (simple && depth == 1)
      {
        if (static_cast<size_t>(param) >= this->Params.size())
          this->Params.resize(static_cast<size_t>(param) + 1);
        this->Params[static_cast<size_t>(param)].Kind = 'e';
      }
      i = j + 1;
      continue;
    }
    if (std::isdigit(c) || c == '+' || c == '-' || c == '.')
    {
      size_t j = i;
      while (j < n && IsNumberChar(static_cast<unsigned char>(t[j])))
        ++j;
      const std::string token = t.substr(i, j - i);
      errno = 0;
      char* end = nullptr;
      const double v = std::strtod(token.c_str(), &end);
      if (end != token.c_str() + token.size() || token.find_first_of("0123456789") ==
          std::string::npos)
        this->Fail("'" + token + "' is not a number");
      // A number below the smallest normal double reads as the subnormal it rounds to (an
      // exporter's 8.54E-316 for a centre's 0, CAx-IF's s1 by one system); one whose exponent
      // takes it below every double (it reads as 0), or above, is refused: OpenCASCADE's parser
      // hung on 1E-99999.
      const bool subnormal = errno == ERANGE && v != 0.0 && std::fabs(v) < DBL_MIN;
      if ((errno == ERANGE && !subnormal) || !std::isfinite(v))
        this->Fail("the number " + token + " is out of the range of a double");
      if (inData && depth == 0)
        this->Fail("a number outside an entity's parameters");
      value();
      if (inData)
        this->CountSplineItem(depth - this->PartBase, false, v);
      if (simple && depth == 1)
      {
        if (static_cast<size_t>(param) >= this->Params.size())
          this->Params.resize(static_cast<size_t>(param) + 1);
        this->Params[static_cast<size_t>(param)] = { 'n', 0, v };
      }
      else if (simple && depth == 2 && param == 1)
        this->Coordinates.push_back(v);
      i = j;
      continue;
    }
    if (IsIdStart(c))
    {
      size_t j = i;
      while (j < n && IsIdChar(static_cast<unsigned char>(t[j])))
        ++j;
      const std::string name = t.substr(i, j - i);
      const size_t next = this->SkipBlank(j);
      const char follow = next < n ? t[next] : '\0';
      if (depth == 0 && follow == ';')
      {
        // An entity left open by a missing ';' (a file cut and closed again): its references
        // would stand with no entity to hold them.
        if (inData && this->Current > 0)
          this->Fail("the entity is not closed by ';' before '" + name.substr(0, 40) + ";'");
        if (name == "DATA")
          inData = true;
        else if (name == "ENDSEC")
          inData = false;
        else if (inData)
          this->Fail("unexpected keyword '" + name + "'");
        i = next; // the ';' ends the statement
        continue;
      }
      // Names are upper case (ISO 10303-21); OpenCASCADE does not know "EDGE_LOOp" and
      // crashes on the references to it.
      if (name[0] != '!' && std::any_of(name.begin(), name.end(),
                              [](unsigned char ch) { return std::islower(ch) != 0; }))
        this->Fail("'" + name.substr(0, 40) + "' is not an entity name (names are upper case)");
      if (follow != '(')
        this->Fail("unexpected word '" + name.substr(0, 40) + "' (a name must be followed by "
          "its parameters in parentheses)");
      // A partial entity of a complex one follows the previous part without a ','.
      if (!(inData && depth == 1 && this->CurrentType.empty() && this->Current > 0))
        value();
      else
        needSep = false;
      afterName = true;
      if (inData && depth == 0)
      {
        if (state != 2)
          this->Fail("unexpected name '" + name.substr(0, 40) + "'");
        this->CurrentType = name;
        state = 3;
      }
      else if (inData && depth == 1 && this->CurrentType.empty() && this->Current > 0)
      {
        this->Parts += name + ",";
        this->PartName = name;
      }
      else if (simple && depth == 1)
      {
        if (static_cast<size_t>(param) >= this->Params.size())
          this->Params.resize(static_cast<size_t>(param) + 1);
      }
      i = j;
      continue;
    }
    char buf[96];
    if (c >= 0x80)
      std::snprintf(buf, sizeof buf, "byte 0x%02X outside a string: STEP files are 7-bit text "
                                     "outside their strings", c);
    else
      std::snprintf(buf, sizeof buf, "unexpected character 0x%02X", c);
    this->Fail(buf);
  }
  if (depth != 0 || (inData && this->Current > 0))
    this->Fail("the file ends inside an entity");
  this->Current = 0;

  // References: every target defined, of the right type where the schema fixes it. A missing
  // target of a geometric or topological entity is an error (OpenCASCADE dereferences it);
  // elsewhere (styles, notes, PMI) OpenCASCADE drops the reference, and it is a warning.
  for (const auto& e : this->Entities)
    this->Result.TypeNames.emplace(e.first, this->TypeText(e.second));
  // The definitional representations that a pcurve refers to, whose items are checked, and how
  // many items each of them has.
  std::set<long> pcurveReps;
  std::map<long, long> pcurveItems;
  for (const TypedRef& r : this->Typed)
    if (r.Pcurve == PcurveRep)
      pcurveReps.insert(r.To);
  std::unordered_map<long, int> mapRefs; // references seen so far of each REPRESENTATION_MAP
  for (const auto& r : this->Refs)
  {
    const auto from = this->Entities.find(r.first);
    if (from == this->Entities.end())
      continue;
    const std::string type = this->TypeText(from->second);
    // (A pcurve's definitional representation too: OpenCASCADE dereferences its items.)
    if (IsGeometric(type) || pcurveReps.count(r.first))
      this->Result.GeometryTargets.emplace(r.second, r.first);
    if (type == "REPRESENTATION_MAP" && ++mapRefs[r.first] == 2)
      this->Result.MappedRepresentations.emplace(r.first, r.second);
  }
  long dangling = 0;
  std::string firstDangling;
  for (size_t k = 0; k < this->Refs.size(); ++k)
    if (this->Entities.find(this->Refs[k].second) == this->Entities.end())
    {
      this->Line = this->RefLines[k];
      this->Current = this->Refs[k].first;
      const std::string what = "refers to #" + std::to_string(this->Refs[k].second) +
        ", which the file does not define";
      const auto from = this->Entities.find(this->Current);
      const std::string type = from == this->Entities.end() ? "" : this->TypeText(from->second);
      // A pcurve's definitional representation is no geometric type by its name, but
      // OpenCASCADE dereferences its items: a missing one crashed its transfer (a libFuzzer
      // input, read through the solids' direct transfer, sixtieth session).
      if (IsGeometric(type) || from == this->Entities.end() || pcurveReps.count(this->Current))
        this->Fail(what);
      if (dangling++ == 0)
        firstDangling = "#" + std::to_string(this->Current) + " " + type + " (line " +
          std::to_string(this->Line) + ") " + what;
    }
  if (dangling > 0)
    this->Result.Warnings.push_back(std::to_string(dangling) + " reference(s) to entities the "
      "file does not define, outside the geometry (ignored), the first: " + firstDangling);
  for (const TypedRef& r : this->Typed)
  {
    if (r.Pcurve == PcurveItem)
    {
      if (!pcurveReps.count(r.From))
        continue;
      ++pcurveItems[r.From];
    }
    const auto found = this->Entities.find(r.To);
    if (found == this->Entities.end())
      continue; // dangling: an error or a warning above
    const Entity& target = found->second;
    const std::string expected = r.Expected;
    bool ok = false;
    for (size_t a = 0, b; a <= expected.size(); a = b + 1)
    {
      b = expected.find('|', a);
      if (b == std::string::npos)
        b = expected.size();
      ok = ok || this->HasType(target, expected.substr(a, b - a));
    }
    // The referring entity's type, for an error (only then: every typed reference passes here).
    auto typeOfFrom = [&]() {
      const auto source = this->Entities.find(r.From);
      return source == this->Entities.end() ? std::string("the entity")
                                            : this->TypeText(source->second);
    };
    if (!ok)
    {
      this->Line = r.Line;
      this->Current = r.From;
      const std::string from = typeOfFrom();
      std::string want = r.Said ? r.Said : expected;
      std::replace(want.begin(), want.end(), '|', '/');
      auto article = [](const std::string& w) {
        return std::string(w.empty() || std::strchr("AEIOU", w[0]) == nullptr ? "a " : "an ") + w;
      };
      this->Fail(from + " parameter " + std::to_string(r.Param + 1) + " refers to #" +
        std::to_string(r.To) + ", " + article(this->TypeText(target)) + ", where " +
        (r.Said ? want : article(want)) + " is required");
    }
    if (r.Dim > 0 && target.Dim > 0 && target.Dim != r.Dim)
    {
      this->Line = r.Line;
      this->Current = r.From;
      this->Fail(typeOfFrom() + " parameter " + std::to_string(r.Param + 1) + " refers to #" +
        std::to_string(r.To) + ", a " + this->TypeText(target) + " of " +
        std::to_string(target.Dim) + " coordinate" + (target.Dim == 1 ? "" : "s") +
        ", where one of " + std::to_string(r.Dim) + " is required");
    }
  }
  // A pcurve's definitional representation with no curve at all (OpenCASCADE 7.6 crashed on it).
  for (const TypedRef& r : this->Typed)
    if (r.Pcurve == PcurveRep && this->Entities.count(r.To) &&
      this->HasType(this->Entities.at(r.To), "DEFINITIONAL_REPRESENTATION") &&
      pcurveItems.count(r.To) == 0)
    {
      this->Line = r.Line;
      this->Current = r.From;
      this->Fail("PCURVE parameter 3 refers to #" + std::to_string(r.To) +
        ", a DEFINITIONAL_REPRESENTATION that holds no curve");
    }
  this->Line = 0;
  const double bound = MaxCoordinateMillimetres / this->Result.UnitInMillimetres;
  if (this->Result.LargestCoordinate > bound)
  {
    char buf[160];
    std::snprintf(buf, sizeof buf, "a coordinate or radius of %g (the file's unit is %g mm) "
      "lies beyond 1,000 km: not a real part", this->Result.LargestCoordinate,
      this->Result.UnitInMillimetres);
    throw InputError("STEP file '" + this->Path + "': entity #" +
      std::to_string(this->Result.LargestCoordinateEntity) + ": " + buf);
  }
  return this->Result;
}
} // namespace

StepScanResult ScanStepText(const std::string& path, const std::string& text)
{
  return Scanner(path, text).Run();
}

StepScanResult ScanStepFile(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError("STEP file '" + path + "': cannot be opened: " + std::strerror(errno));
  std::ostringstream s;
  s << in.rdbuf();
  return ScanStepText(path, s.str());
}
std::string DescribeUnreadGeometry(const StepScanResult& scan)
{
  const std::vector<std::string>& unread = scan.UnreadGeometry;
  if (unread.empty())
    return std::string();
  std::string why = ". The likely cause: " + unread.front();
  if (unread.size() > 1)
    why += " (and " + std::to_string(unread.size() - 1) + " more B-splines so)";
  return why;
}

} // namespace brt
