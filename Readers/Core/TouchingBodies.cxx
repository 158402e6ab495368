#include "TouchingBodies.h"

#include <Bnd_Box.hxx>
#include <BOPAlgo_MakerVolume.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepBndLib.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepClass3d.hxx>
#include <BRepClass3d_SolidClassifier.hxx>
#include <BRepClass3d_SolidExplorer.hxx>
#include <BRepGProp.hxx>
#include <BRepTools_ReShape.hxx>
#include <BRepTopAdaptor_FClass2d.hxx>
#include <BRepTools.hxx>
#include <ElSLib.hxx>
#include <Geom2d_Curve.hxx>
#include <GProp_GProps.hxx>
#include <ShapeUpgrade_UnifySameDomain.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Iterator.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Solid.hxx>
#include <TopoDS_Wire.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_IndexedMapOfShape.hxx>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <sstream>

namespace brt
{
namespace
{
/// Above this many faces a solid is not remade by the volume maker (it intersects every pair of
/// faces: 1.4 s for a resistor model's 97 faces, 16 of them B-splines).
constexpr int MaxFacesToRemake = 400;

/// A plane, cylinder or sphere face of a solid, described so that faces on one surface meet in
/// a sorted list: the key is a plane's offset along its canonical normal, or the radius.
struct SurfaceFace
{
  int Index = 0;     ///< in the solid's face map (1-based)
  GeomAbs_SurfaceType Type = GeomAbs_Plane;
  double Key = 0.0;  ///< plane: Canonical . (a point of it); cylinder, sphere: the radius
  gp_Dir Canonical;  ///< plane: +-its normal, the first clearly non-zero component positive;
                     ///< cylinder: +-its axis, likewise
  gp_Pnt Point;      ///< cylinder: a point of its axis; sphere: the centre
  int Outward = 1;   ///< plane: +1 where the outward normal is Canonical, else -1; cylinder,
                     ///< sphere: +1 where it points away from the axis or centre, else -1
  mutable Bnd_Box Box; ///< made when first needed (BoxOf)
  mutable bool HasBox = false;
};

const Bnd_Box& BoxOf(const SurfaceFace& p, const TopoDS_Face& f, double tol)
{
  if (!p.HasBox)
  {
    BRepBndLib::Add(f, p.Box);
    p.Box.Enlarge(tol);
    p.HasBox = true;
  }
  return p.Box;
}

double Volume(const TopoDS_Shape& s)
{
  GProp_GProps g;
  BRepGProp::VolumeProperties(s, g);
  return g.Mass();
}

double Area(const TopoDS_Face& f)
{
  GProp_GProps g;
  BRepGProp::SurfaceProperties(f, g);
  return g.Mass();
}

gp_Pnt CentreOfArea(const TopoDS_Face& f)
{
  GProp_GProps g;
  BRepGProp::SurfaceProperties(f, g);
  return g.CentreOfMass();
}

/// The face's wires as it holds them, its orientation composed (TopoDS_Iterator's default).
std::vector<TopoDS_Wire> Wires(const TopoDS_Face& f)
{
  std::vector<TopoDS_Wire> wires;
  for (TopoDS_Iterator it(f); it.More(); it.Next())
    if (it.Value().ShapeType() == TopAbs_WIRE)
      wires.push_back(TopoDS::Wire(it.Value()));
  return wires;
}

/// Points along a wire: each edge's ends and seven points between.
std::vector<gp_Pnt> WirePoints(const TopoDS_Wire& w)
{
  std::vector<gp_Pnt> points;
  for (TopExp_Explorer ex(w, TopAbs_EDGE); ex.More(); ex.Next())
  {
    const TopoDS_Edge& e = TopoDS::Edge(ex.Current());
    if (BRep_Tool::Degenerated(e))
      continue;
    BRepAdaptor_Curve c(e);
    const double f = c.FirstParameter(), l = c.LastParameter();
    if (!std::isfinite(f) || !std::isfinite(l))
      continue;
    for (int k = 0; k <= 8; ++k)
      points.push_back(c.Value(f + (l - f) * k / 8.0));
  }
  return points;
}

/// A face's point classification: a 3D point on (or near) its plane, cylinder or sphere, by the
/// surface's parameters (the periodic one moved into the face's range) in the face's trim
/// (BRepTopAdaptor_FClass2d, made once per face).
class SurfaceClassifier
{
public:
  SurfaceClassifier(const TopoDS_Face& f, double tol)
    : Surface(f, false)
    , Trim(f, tol)
  {
    double v0 = 0.0, v1 = 0.0;
    BRepTools::UVBounds(f, U0, U1, v0, v1);
  }
  TopAbs_State State(const gp_Pnt& p) const
  {
    double u = 0.0, v = 0.0;
    switch (Surface.GetType())
    {
      case GeomAbs_Plane: ElSLib::Parameters(Surface.Plane(), p, u, v); break;
      case GeomAbs_Cylinder: ElSLib::Parameters(Surface.Cylinder(), p, u, v); break;
      case GeomAbs_Sphere: ElSLib::Parameters(Surface.Sphere(), p, u, v); break;
      default: return TopAbs_UNKNOWN;
    }
    if (Surface.GetType() != GeomAbs_Plane)
    {
      // ElSLib's u lies in [0, 2 pi): moved by whole turns to the face's range.
      const double turn = 2.0 * M_PI;
      while (u < U0 - 1e-9)
        u += turn;
      while (u > U0 + turn + 1e-9)
        u -= turn;
    }
    return Trim.Perform(gp_Pnt2d(u, v));
  }

private:
  BRepAdaptor_Surface Surface;
  BRepTopAdaptor_FClass2d Trim;
  double U0 = 0.0, U1 = 0.0;
};

/// How many of the points lie strictly inside the face, and how many outside.
void Count(const SurfaceClassifier& f, const std::vector<gp_Pnt>& points, int& in, int& out)
{
  in = out = 0;
  for (const gp_Pnt& p : points)
  {
    const TopAbs_State s = f.State(p);
    in += s == TopAbs_IN ? 1 : 0;
    out += s == TopAbs_OUT ? 1 : 0;
  }
}

/// Edges of the shape bounding one face only (a seam, which bounds its face twice, is not free),
/// and edges bounding more than two faces (bodies touching along a line).
void CountEdges(const TopoDS_Shape& s, int& free, int& nonManifold)
{
  TopTools_IndexedDataMapOfShapeListOfShape edgeFaces;
  TopExp::MapShapesAndUniqueAncestors(s, TopAbs_EDGE, TopAbs_FACE, edgeFaces);
  free = nonManifold = 0;
  for (int i = 1; i <= edgeFaces.Extent(); ++i)
  {
    const TopoDS_Edge& e = TopoDS::Edge(edgeFaces.FindKey(i));
    if (BRep_Tool::Degenerated(e))
      continue;
    const TopTools_ListOfShape& faces = edgeFaces(i);
    if (faces.Extent() == 1 && !BRep_Tool::IsClosed(e, TopoDS::Face(faces.First())))
      ++free;
    if (faces.Extent() > 2)
      ++nonManifold;
  }
}

std::string Where(const gp_Pnt& p)
{
  std::ostringstream w;
  w << "(" << p.X() << ", " << p.Y() << ", " << p.Z() << ")";
  return w.str();
}

gp_Dir CanonicalOf(const gp_Dir& n)
{
  const double c[3] = { n.X(), n.Y(), n.Z() };
  int k = 0;
  while (k < 2 && std::fabs(c[k]) < 1e-9)
    ++k;
  return c[k] < 0.0 ? n.Reversed() : n;
}

/// The plane, cylinder and sphere faces of a solid, sorted by type and key.
std::vector<SurfaceFace> SurfaceFaces(const TopTools_IndexedMapOfShape& faces)
{
  std::vector<SurfaceFace> out;
  for (int i = 1; i <= faces.Extent(); ++i)
  {
    const TopoDS_Face& f = TopoDS::Face(faces(i));
    BRepAdaptor_Surface s(f, false);
    const int reversed = f.Orientation() == TopAbs_REVERSED ? -1 : 1;
    SurfaceFace p;
    p.Index = i;
    p.Type = s.GetType();
    if (p.Type == GeomAbs_Plane)
    {
      const gp_Pln pl = s.Plane();
      // The surface's normal is XDir ^ YDir (the axis's direction for a right-handed frame).
      gp_Dir n = pl.Position().XDirection().Crossed(pl.Position().YDirection());
      if (reversed < 0)
        n.Reverse();
      p.Canonical = CanonicalOf(n);
      p.Outward = p.Canonical.Dot(n) > 0.0 ? 1 : -1;
      p.Key = gp_Vec(p.Canonical).Dot(gp_Vec(pl.Location().XYZ()));
    }
    else if (p.Type == GeomAbs_Cylinder || p.Type == GeomAbs_Sphere)
    {
      // The surface's normal points away from the axis (centre) for a right-handed frame.
      const gp_Ax3 frame =
        p.Type == GeomAbs_Cylinder ? s.Cylinder().Position() : s.Sphere().Position();
      p.Outward = (frame.Direct() ? 1 : -1) * reversed;
      p.Canonical = CanonicalOf(frame.Direction());
      p.Point = frame.Location();
      p.Key = p.Type == GeomAbs_Cylinder ? s.Cylinder().Radius() : s.Sphere().Radius();
    }
    else
      continue;
    out.push_back(p);
  }
  std::sort(out.begin(), out.end(), [](const SurfaceFace& a, const SurfaceFace& b) {
    return a.Type != b.Type ? a.Type < b.Type : a.Key < b.Key;
  });
  return out;
}

/// The two faces lie on one surface (their keys already within tol) and face opposite ways.
bool SameSurfaceOpposite(const SurfaceFace& a, const SurfaceFace& b, double tol)
{
  if (a.Type != b.Type || a.Outward == b.Outward)
    return false;
  if (a.Type == GeomAbs_Plane)
    return a.Canonical.Angle(b.Canonical) <= 1e-7;
  if (a.Type == GeomAbs_Sphere)
    return a.Point.Distance(b.Point) <= tol;
  // Cylinders: parallel axes, b's axis point on a's axis.
  const gp_Vec ab(a.Point, b.Point);
  return a.Canonical.Angle(b.Canonical) <= 1e-7 &&
    ab.Crossed(gp_Vec(a.Canonical)).Magnitude() <= tol;
}

/// What the pairs of one solid are: inside (the first face lies inside the second) or a partial
/// overlap.
struct SolidPairs
{
  std::vector<std::pair<int, int>> Inside; ///< (inner, outer) face indices
  int Partial = 0;
  gp_Pnt PartialAt;
};

SolidPairs FindPairs(const TopTools_IndexedMapOfShape& faces, double tol)
{
  SolidPairs found;
  const std::vector<SurfaceFace> surfaces = SurfaceFaces(faces);
  std::map<int, std::unique_ptr<SurfaceClassifier>> classifiers;
  auto classifier = [&](int index) -> const SurfaceClassifier& {
    std::unique_ptr<SurfaceClassifier>& c = classifiers[index];
    if (!c)
      c.reset(new SurfaceClassifier(TopoDS::Face(faces(index)), tol));
    return *c;
  };
  std::vector<bool> inner(static_cast<size_t>(faces.Extent()) + 1, false);
  for (size_t a = 0; a < surfaces.size(); ++a)
    for (size_t b = a + 1; b < surfaces.size() && surfaces[b].Type == surfaces[a].Type &&
         surfaces[b].Key - surfaces[a].Key <= tol;
         ++b)
    {
      const SurfaceFace& pa = surfaces[a];
      const SurfaceFace& pb = surfaces[b];
      if (!SameSurfaceOpposite(pa, pb, tol))
        continue;
      const TopoDS_Face& fa = TopoDS::Face(faces(pa.Index));
      const TopoDS_Face& fb = TopoDS::Face(faces(pb.Index));
      if (BoxOf(pa, fa, tol).IsOut(BoxOf(pb, fb, tol)))
        continue;
      try
      {
        const SurfaceClassifier& ca = classifier(pa.Index);
        const SurfaceClassifier& cb = classifier(pb.Index);
        // Each face's wires' points against the other face: strictly inside, outside, or on its
        // boundary.
        int in[2] = { 0, 0 }, out[2] = { 0, 0 };
        for (int k = 0; k < 2; ++k)
          for (const TopoDS_Wire& w : Wires(k == 0 ? fa : fb))
          {
            int i = 0, o = 0;
            Count(k == 0 ? cb : ca, WirePoints(w), i, o);
            in[k] += i;
            out[k] += o;
          }
        // The same outline (every point on the other's boundary): a cut of no width through
        // the part, a sheet-metal relief: two walls, left as they are.
        if (in[0] == 0 && in[1] == 0 && out[0] == 0 && out[1] == 0)
          continue;
        // One inside the other, with one wire (its rim inside or on the other's boundary,
        // somewhere strictly inside): a boss on a plate.
        int k = -1;
        if (out[0] == 0 && in[0] > 0 && Wires(fa).size() == 1 && !inner[static_cast<size_t>(pa.Index)])
          k = 0;
        else if (out[1] == 0 && in[1] > 0 && Wires(fb).size() == 1 &&
          !inner[static_cast<size_t>(pb.Index)])
          k = 1;
        if (k >= 0)
        {
          const int i = k == 0 ? pa.Index : pb.Index, o = k == 0 ? pb.Index : pa.Index;
          inner[static_cast<size_t>(i)] = true;
          found.Inside.emplace_back(i, o);
          continue;
        }
        bool overlap = in[0] > 0 || in[1] > 0;
        for (int j = 0; j < 2 && !overlap; ++j)
        {
          const gp_Pnt c = CentreOfArea(j == 0 ? fa : fb);
          overlap = ca.State(c) == TopAbs_IN && cb.State(c) == TopAbs_IN;
        }
        if (overlap && found.Partial++ == 0)
          found.PartialAt = CentreOfArea(fa);
      }
      catch (const Standard_Failure&)
      {
        // Classification failed: this pair is not counted.
      }
    }
  return found;
}

/// Cuts each inner plane face's wire out of its outer face and removes the inner face, hole by
/// hole, each kept only where the cut face stays valid and loses the inner face's area. Returns
/// the pairs it did not join (and those on cylinders and spheres).
std::vector<std::pair<int, int>> CutOut(const TopTools_IndexedMapOfShape& faces,
  const std::vector<std::pair<int, int>>& inside, double tol, BRepTools_ReShape& reshape)
{
  std::vector<std::pair<int, int>> left;
  std::map<int, std::vector<int>> holesOf;
  for (const auto& p : inside)
    holesOf[p.second].push_back(p.first);
  BRep_Builder builder;
  for (const auto& entry : holesOf)
  {
    const TopoDS_Face& outerFace = TopoDS::Face(faces(entry.first));
    if (BRepAdaptor_Surface(outerFace, false).GetType() != GeomAbs_Plane)
    {
      // A hole's curves on a cylinder or sphere are not projected here: the volume maker's.
      for (const int inner : entry.second)
        left.emplace_back(inner, entry.first);
      continue;
    }
    std::vector<TopoDS_Wire> kept;
    TopoDS_Face cut;
    double removed = 0.0;
    const double before = Area(outerFace);
    for (const int inner : entry.second)
    {
      const TopoDS_Face& innerFace = TopoDS::Face(faces(inner));
      const double area = Area(innerFace);
      bool ok = false;
      try
      {
        // The inner face's wire, as the inner face holds it, runs round the outward normal
        // opposite to the outer face's: it is a hole of the outer face as it stands.
        const TopoDS_Wire hole = Wires(innerFace)[0];
        TopoDS_Face trial = TopoDS::Face(outerFace.EmptyCopied());
        for (const TopoDS_Wire& w : Wires(outerFace))
          builder.Add(trial, w);
        for (const TopoDS_Wire& w : kept)
          builder.Add(trial, w);
        builder.Add(trial, hole);
        for (TopExp_Explorer ex(hole, TopAbs_EDGE); ex.More(); ex.Next())
        {
          const TopoDS_Edge& e = TopoDS::Edge(ex.Current());
          double f = 0.0, l = 0.0;
          // A plane's curve of the edge, projected (BRep_Tool makes it for a plane).
          const Handle(Geom2d_Curve) pc = BRep_Tool::CurveOnSurface(e, trial, f, l);
          if (pc.IsNull())
            throw Standard_Failure("no curve on the plane");
          builder.UpdateEdge(e, pc, trial, BRep_Tool::Tolerance(e));
          builder.Range(e, trial, f, l);
        }
        ok = std::fabs(Area(trial) - (before - removed - area)) <= 1e-6 * before + tol * tol &&
          BRepCheck_Analyzer(trial).IsValid();
        if (ok)
        {
          kept.push_back(hole);
          cut = trial;
          removed += area;
        }
      }
      catch (const Standard_Failure&)
      {
        ok = false;
      }
      if (ok)
        reshape.Remove(innerFace);
      else
        left.emplace_back(inner, entry.first);
    }
    if (!cut.IsNull())
      reshape.Replace(outerFace, cut);
  }
  return left;
}

/// The solid again from its faces: OpenCASCADE's volume maker splits the faces where they meet
/// and builds the volumes they enclose; where the bodies meet only where they touch, each is a
/// volume of its own, fused. Null with `failure` set where that gives no single solid.
TopoDS_Shape RemakeSolid(const TopoDS_Shape& solid, std::string& failure)
{
  TopTools_ListOfShape arguments;
  for (TopExp_Explorer fx(solid, TopAbs_FACE); fx.More(); fx.Next())
    arguments.Append(fx.Current());
  BOPAlgo_MakerVolume maker;
  maker.SetArguments(arguments);
  maker.SetRunParallel(false);
  maker.SetIntersect(true);
  maker.Perform();
  if (maker.HasErrors())
  {
    failure = "OpenCASCADE's volume maker failed";
    return TopoDS_Shape();
  }
  TopTools_ListOfShape volumes;
  TopoDS_Shape joined;
  for (TopExp_Explorer x(maker.Shape(), TopAbs_SOLID); x.More(); x.Next())
  {
    volumes.Append(x.Current());
    joined = x.Current();
  }
  if (volumes.Extent() > 1)
  {
    TopTools_ListOfShape first;
    first.Append(volumes.First());
    volumes.RemoveFirst();
    BRepAlgoAPI_Fuse fuse;
    fuse.SetArguments(first);
    fuse.SetTools(volumes);
    fuse.SetRunParallel(false);
    fuse.Build();
    joined.Nullify();
    int made = 0;
    if (fuse.IsDone() && !fuse.HasErrors())
    {
      // The fuse leaves the faces split along the shared area's rim: merged again.
      ShapeUpgrade_UnifySameDomain unify(fuse.Shape(), true, true, false);
      unify.Build();
      for (TopExp_Explorer x(unify.Shape(), TopAbs_SOLID); x.More(); x.Next(), ++made)
        joined = x.Current();
    }
    if (made != 1)
    {
      failure = "its bodies would not fuse into one";
      return TopoDS_Shape();
    }
  }
  if (joined.IsNull())
    failure = "its faces enclose no volume";
  return joined;
}

/// `solid` with each of its shells but the outer one whose inside lies outside the outer shell's
/// material turned the other way, or a null shape where it has none. OpenCASCADE's STEP
/// transfer makes a body that lies within another's envelope (a rod in a sleeve's bore, shorter
/// than the sleeve, the two in one shell) the other's cavity, its faces turned inwards: the rod
/// then counts as air and the air around it as material. A true cavity's inside lies within the
/// outer shell's material; points just inside the shell (a point of a face moved along the
/// solid's outward normal there, a thousandth of the shell's size, on up to five faces) are
/// classified against the outer shell alone, and a shell most of whose points lie outside it is
/// a body, turned. `where` receives a point of the first one turned.
TopoDS_Shape WithFalseCavitiesTurned(
  const TopoDS_Shape& shape, double tol, int& turned, gp_Pnt& where)
{
  turned = 0;
  if (shape.ShapeType() != TopAbs_SOLID)
    return TopoDS_Shape();
  const TopoDS_Solid& solid = TopoDS::Solid(shape);
  std::vector<TopoDS_Shell> shells;
  for (TopoDS_Iterator it(solid); it.More(); it.Next())
    if (it.Value().ShapeType() == TopAbs_SHELL)
      shells.push_back(TopoDS::Shell(it.Value()));
  if (shells.size() < 2)
    return TopoDS_Shape();
  const TopoDS_Shell outer = BRepClass3d::OuterShell(solid);
  if (outer.IsNull())
    return TopoDS_Shape();
  BRep_Builder b;
  TopoDS_Solid envelope;
  b.MakeSolid(envelope);
  b.Add(envelope, outer);
  BRepClass3d_SolidClassifier classifier(envelope);
  TopoDS_Solid out;
  b.MakeSolid(out);
  for (const TopoDS_Shell& shell : shells)
  {
    if (shell.IsSame(outer))
    {
      b.Add(out, shell);
      continue;
    }
    Bnd_Box box;
    BRepBndLib::Add(shell, box);
    const double step = std::max(10.0 * tol, 1e-3 * std::sqrt(box.SquareExtent()));
    int inside = 0, outside = 0, tried = 0;
    gp_Pnt first;
    for (TopExp_Explorer fx(shell, TopAbs_FACE); fx.More() && tried < 5; fx.Next())
    {
      const TopoDS_Face& f = TopoDS::Face(fx.Current());
      gp_Pnt p;
      double u = 0.0, v = 0.0, param = 0.0;
      if (!BRepClass3d_SolidExplorer::FindAPointInTheFace(f, p, u, v, param))
        continue;
      BRepAdaptor_Surface surface(f);
      gp_Vec du, dv;
      surface.D1(u, v, p, du, dv);
      gp_Vec n = du.Crossed(dv);
      if (n.Magnitude() < 1e-12)
        continue;
      n.Normalize();
      if (f.Orientation() == TopAbs_REVERSED)
        n.Reverse(); // the solid's outward normal: into a cavity, away from its material
      classifier.Perform(p.Translated(n * step), tol);
      ++tried;
      inside += classifier.State() == TopAbs_IN ? 1 : 0;
      outside += classifier.State() == TopAbs_OUT ? 1 : 0;
      if (tried == 1)
        first = p;
    }
    if (outside > inside)
    {
      b.Add(out, shell.Reversed());
      if (turned++ == 0)
        where = first;
    }
    else
      b.Add(out, shell);
  }
  return turned > 0 ? TopoDS_Shape(out) : TopoDS_Shape();
}
} // namespace

TouchingFacesResult JoinBodiesTouchingFaceToFace(
  const TopoDS_Shape& shape, double tolerance, std::vector<std::string>& warnings)
{
  TouchingFacesResult result;
  result.Shape = shape;
  const double tol = std::max(tolerance, 1e-7);
  // Replacements recorded in a solid's own frame (location stripped from the key), so that each
  // placement of a solid placed several times takes its joined solid in its place.
  BRepTools_ReShape solids;
  solids.ModeConsiderLocation() = true;
  bool anyReplaced = false;
  int solidIndex = -1;
  std::set<const TopoDS_TShape*> seen; // a solid placed several times is looked at once
  for (TopExp_Explorer sx(shape, TopAbs_SOLID); sx.More(); sx.Next())
  {
    ++solidIndex;
    // In the solid's own frame: the replacement then holds for every placement of it.
    const TopoDS_Shape original = sx.Current().Located(TopLoc_Location());
    if (!seen.insert(original.TShape().get()).second)
      continue;
    const std::string name = "solid " + std::to_string(solidIndex);
    // A body the transfer made another's cavity is turned back into a body first.
    int turned = 0;
    gp_Pnt turnedAt;
    TopoDS_Shape turnedSolid;
    try
    {
      turnedSolid = WithFalseCavitiesTurned(original, tol, turned, turnedAt);
    }
    catch (const Standard_Failure&)
    {
      turned = 0;
    }
    if (turned > 0)
    {
      // Recorded below, once: the turned solid, or the join made from it.
      anyReplaced = true;
      result.Turned += turned;
      warnings.push_back(name + ": " + std::to_string(turned) +
        " shell(s) that OpenCASCADE's transfer made cavities lie outside the solid's material, " +
        (turned == 1 ? "" : "the first ") + "near " + Where(turnedAt) +
        " (a body within another's bore or pocket, written in one shell): read as bodies");
    }
    const TopoDS_Shape solid = turned > 0 ? turnedSolid : original;
    TopTools_IndexedMapOfShape faces;
    TopExp::MapShapes(solid, TopAbs_FACE, faces);
    const SolidPairs pairs = FindPairs(faces, tol);
    if (pairs.Partial > 0)
    {
      result.LeftAlone += pairs.Partial;
      warnings.push_back(name + ": " + std::to_string(pairs.Partial) +
        " pair(s) of faces on one surface overlap with opposite normals over part of their area, " +
        (pairs.Partial == 1 ? "" : "the first ") + "near " + Where(pairs.PartialAt) +
        " (a cut of no width, or two bodies touching face to face in one shell): left as two "
        "walls, each sphere ending at them");
    }
    if (pairs.Inside.empty())
    {
      if (turned > 0)
        solids.Replace(original, turnedSolid);
      continue;
    }
    double shared = 0.0;
    for (const auto& p : pairs.Inside)
      shared += Area(TopoDS::Face(faces(p.first)));
    std::ostringstream w;
    w << name << ": " << pairs.Inside.size() << " face(s) lie inside another face of the "
      << "solid on the same surface with the opposite normal, " << (pairs.Inside.size() == 1 ? "" : "the first ")
      << "near " << Where(CentreOfArea(TopoDS::Face(faces(pairs.Inside[0].first))))
      << " (two bodies touching face to face in one shell, " << shared << " mm^2 in all)";
    // The inner faces cut out of the outer ones; where one will not cut, the solid made again
    // from its faces. Kept where it gives one valid, closed solid of the same volume (the bodies
    // touch, they do not overlap).
    std::string failure;
    TopoDS_Shape joined;
    try
    {
      BRepTools_ReShape reshape;
      const std::vector<std::pair<int, int>> left = CutOut(faces, pairs.Inside, tol, reshape);
      joined = left.size() < pairs.Inside.size() ? reshape.Apply(solid) : solid;
      if (!left.empty())
      {
        int count = 0;
        for (TopExp_Explorer fx(joined, TopAbs_FACE); fx.More(); fx.Next())
          ++count;
        if (count > MaxFacesToRemake)
        {
          failure = "a face's rim touches the other's edge, and remaking a solid of " +
            std::to_string(count) + " faces is left undone";
          joined.Nullify();
        }
        else
          joined = RemakeSolid(joined, failure);
      }
      if (!joined.IsNull())
      {
        const double before = Volume(solid), after = Volume(joined);
        int free = 0, nonManifold = 0, free0 = 0, nonManifold0 = 0;
        CountEdges(joined, free, nonManifold);
        CountEdges(solid, free0, nonManifold0);
        if (!(std::fabs(after - before) <= 1e-6 * std::fabs(before)))
          failure = "the joined solid's volume differs from the solid's: the bodies overlap";
        else if (nonManifold > nonManifold0)
          failure = "the bodies touch along a line too, where the joined solid would be "
                    "non-manifold";
        else if (free > 0 || !BRepCheck_Analyzer(joined).IsValid())
          failure = "the joined solid is not valid";
      }
    }
    catch (const Standard_Failure& e)
    {
      failure = std::string("OpenCASCADE failed: ") + e.GetMessageString();
    }
    if (failure.empty() && !joined.IsNull())
    {
      solids.Replace(original, joined);
      anyReplaced = true;
      result.Joined += static_cast<int>(pairs.Inside.size());
      warnings.push_back(w.str() + ": joined into one body, the shared area now inside the solid");
    }
    else
    {
      if (turned > 0)
        solids.Replace(original, turnedSolid);
      result.LeftAlone += static_cast<int>(pairs.Inside.size());
      warnings.push_back(w.str() + ": not joined (" + failure +
        "), so the samples on the shared area measure one body, and the spheres of both end "
        "at it");
    }
  }
  if (anyReplaced)
    result.Shape = solids.Apply(shape);
  return result;
}
} // namespace brt
