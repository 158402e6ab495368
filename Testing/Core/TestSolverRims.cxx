// Samples near rims and holes against an independent exact computation: the largest t for which
// the ball of radius t centred at M = O + t d stays inside the solid, found by bisection on t
// with OpenCASCADE's exact distance (BRepExtrema) from M to the solid's boundary.
#include "AnalyticShapes.h"
#include "ExactDistance.h"
#include "NativeSolver.h"
#include "SolverTestHelpers.h"

#include <gtest/gtest.h>

#include <BRepBuilderAPI_MakeVertex.hxx>
#include <Bnd_Box.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRep_Builder.hxx>
#include <gp_Pln.hxx>
#include <gp_Ax3.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Shape.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCone.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <Geom_BezierSurface.hxx>
#include <GeomAPI_PointsToBSplineSurface.hxx>
#include <Geom_BSplineSurface.hxx>
#include <BRepOffsetAPI_MakeThickSolid.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <gp_Pnt.hxx>

#include "TestHelpers.h"

#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <map>
#include <vector>

namespace
{
using namespace brt;

/// Exact distance from p to the solid's boundary: to the compound of its faces (a solid given to
/// BRepExtrema gives 0 for points inside it).
double BoundaryDistance(const TopoDS_Shape& faces, const std::array<double, 3>& p)
{
  BRepExtrema_DistShapeShape dist(
    BRepBuilderAPI_MakeVertex(gp_Pnt(p[0], p[1], p[2])).Vertex(), faces, Extrema_ExtFlag_MIN);
  return dist.IsDone() ? dist.Value() : -1.0;
}

TopoDS_Shape Faces(const TopoDS_Shape& solid)
{
  BRep_Builder b;
  TopoDS_Compound c;
  b.MakeCompound(c);
  for (TopExp_Explorer ex(solid, TopAbs_FACE); ex.More(); ex.Next())
    b.Add(c, ex.Current());
  return c;
}

/// Largest t with dist(O + t d, boundary) >= t (the ball touches O and stays inside). Samples on
/// a face boundary lie on the Bezier patches, within the conversion tolerance of the exact
/// surface, so the test allows that much: dist >= t - 2 * tolerance.
double ExactRadius(const TopoDS_Shape& faces, const Sample& s, double hi, double tolerance)
{
  double lo = 0.0;
  const double eps = 1e-10 * hi;
  for (int it = 0; it < 60 && hi - lo > eps; ++it)
  {
    const double t = 0.5 * (lo + hi);
    const std::array<double, 3> M{ s.Point[0] + t * s.Direction[0], s.Point[1] + t * s.Direction[1],
      s.Point[2] + t * s.Direction[2] };
    if (BoundaryDistance(faces, M) >= t - 2.0 * tolerance)
      lo = t;
    else
      hi = t;
  }
  return 0.5 * (lo + hi);
}

/// The solver's definition of the radius at sample o, as brt_exact_check computes it: the
/// clearance's sphere by bisection (ExactRadius, searched up to twice the solver's `radius`), then
/// eq. 1's radius through the exact point nearest to its centre. -1 where OpenCASCADE finds no
/// such point, or it lies behind O's tangent plane.
double ExactSphereRadius(const TopoDS_Shape& faces, const Sample& o, double radius, double tolerance)
{
  const double lo = ExactRadius(faces, o, 2.0 * radius + 10.0 * tolerance, tolerance);
  BRepExtrema_DistShapeShape nearest(BRepBuilderAPI_MakeVertex(gp_Pnt(o.Point[0] +
                                       lo * o.Direction[0], o.Point[1] + lo * o.Direction[1],
                                       o.Point[2] + lo * o.Direction[2])).Vertex(),
    faces, Extrema_ExtFlag_MIN);
  if (!nearest.IsDone() || nearest.NbSolution() == 0)
    return -1.0;
  const gp_Pnt P = nearest.PointOnShape2(1);
  const double w[3] = { P.X() - o.Point[0], P.Y() - o.Point[1], P.Z() - o.Point[2] };
  const double h = w[0] * o.Direction[0] + w[1] * o.Direction[1] + w[2] * o.Direction[2];
  return h > 0.0 ? 0.5 * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]) / h : -1.0;
}

void CheckRims(const char* name, const TopoDS_Shape& shape, double h)
{
  // Tight conversion so that the patches do not limit the comparison.
  const test::Solved s = test::SolveShape(shape, 1e-7);
  const TopoDS_Shape faces = Faces(shape);
  const std::vector<double> rim = test::RimDistances(s.Model, s.Samples);
  std::map<std::string, int> types;
  double worst = 0.0, worstEdge = 0.0, worstCorner = 0.0;
  int checked = 0, corners = 0, failed = 0, nearRim = 0;
  for (size_t i = 0; i < s.Samples.size(); ++i)
  {
    if (rim[i] >= h)
      continue;
    ++nearRim;
    if (i % 23 != 0) // every 23rd near-rim sample: enough to cover the rims, quick enough
      continue;
    const SampleResult& r = s.Results[i];
    if (r.Type == ContactType::Failed)
    {
      ++failed;
      continue;
    }
    const double exact =
      ExactRadius(faces, s.Samples[i], std::max(2.0 * r.Radius, h), s.Model.Tolerance);
    // Samples on a face's boundary (mesh vertices on edges, moved 1e-2 of a triangle into the
    // face) have spheres of about 0 at convex edges and corners; they are reported apart.
    if (rim[i] < 1e-3 * h)
    {
      ++corners;
      worstCorner = std::max(worstCorner, std::fabs(r.Radius - exact));
      continue;
    }
    ++types[ContactTypeName(r.Type)];
    const double err = std::fabs(r.Radius - exact) / exact;
    if (err > 1e-5)
      std::printf("[rim] %s sample %zu: solver t=%.10g (%s), exact t=%.10g, rel %.2e\n", name, i,
        r.Radius, ContactTypeName(r.Type), exact, err);
    (r.Type == ContactType::SurfaceSurface ? worst : worstEdge) =
      std::max(r.Type == ContactType::SurfaceSurface ? worst : worstEdge, err);
    ++checked;
  }
  std::printf("[rims] %s: %d samples within one thickness of a rim; %d checked against the exact "
              "radius: max relative error %.2e (surface/surface), %.2e (surface/edge or vertex);",
    name, nearRim, checked, worst, worstEdge);
  for (const auto& t : types)
    std::printf(" %s %d", t.first.c_str(), t.second);
  std::printf("; %d failed; %d on a face boundary, max absolute error %.2e\n", failed, corners,
    worstCorner);
  EXPECT_GT(checked, 50);
  EXPECT_LE(worst, 1e-5);
  // Target 1e-5. Measured 2.4e-4 on the L-bracket, where the foot point leaves a plane across
  // its tangent (G1) edge with the fillet: eq. 7 on that edge gives a slightly larger sphere
  // than the true one, which touches the fillet. Continuing onto the tangent neighbour face is
  // the open fix (docs/Solver.md); this bound keeps the measured level from regressing.
  EXPECT_LE(worstEdge, 5e-4);
  EXPECT_EQ(failed, 0);
}

TEST(SolverRims, HolePlateAgainstExactDistance)
{
  CheckRims("hole plate", analytic::HolePlate(80, 6, 10), 6.0);
}

TEST(SolverRims, FilletedLBracketAgainstExactDistance)
{
  CheckRims("L-bracket", analytic::LBracket(60, 8, 40, 5), 8.0);
}

/// Solved, failed and overlapping samples of about 400 spread over a Data/ model's mesh (solved
/// together, with `options`), against the solid's exact faces (BoundaryDistance): a sphere
/// overlaps where t - dist(M, faces) exceeds the clearance plus the conversion tolerance (the
/// sphere is tangent to the patches, which lie within the tolerance of the exact faces, and the
/// clearance lets boundary points that deep into it) and 1e-4 t.
struct Overlaps
{
  size_t Samples = 0, Solved = 0, Overlapping = 0;
  double Worst = 0.0, WorstT = 0.0, Allowed = 0.0;
};

Overlaps CountOverlaps(const std::string& name, const SolverOptions& options)
{
  Overlaps out;
  {
    std::vector<TopoDS_Face> faces;
    const BRepModel m = ConvertStepFile(test::DataFile(name), ConversionOptions(), &faces);
    EXPECT_EQ(faces.size(), m.Faces.size()) << name;
    if (faces.size() != m.Faces.size())
      return out;
    // Thickness is a property of one solid: each solid's own faces.
    int solids = 0;
    for (const Face& F : m.Faces)
      solids = std::max(solids, F.Solid + 1);
    std::vector<TopoDS_Compound> bySolid(static_cast<size_t>(solids) + 1);
    BRep_Builder b;
    for (auto& c : bySolid)
      b.MakeCompound(c);
    for (size_t f = 0; f < faces.size(); ++f)
      b.Add(bySolid[static_cast<size_t>(m.Faces[f].Solid + 1)], faces[f]);

    const SolverData data = PrepareSolver(m, options);
    const std::vector<Sample> all = SamplesFromMesh(m, data);
    const size_t stride = std::max<size_t>(1, all.size() / 400);
    std::vector<Sample> samples;
    for (size_t i = 0; i < all.size(); i += stride)
      samples.push_back(all[i]);
    std::vector<SampleResult> res;
    SolveReference(m, data, options, samples, res);

    out.Allowed = 2.0 * m.Tolerance + m.Tolerance; // clearance (2x) + patches (1x)
    out.Samples = samples.size();
    for (size_t k = 0; k < samples.size(); ++k)
    {
      const SampleResult& r = res[k];
      if (r.Type == ContactType::Failed)
        continue;
      ++out.Solved;
      const TopoDS_Shape& own = bySolid[static_cast<size_t>(m.Faces[samples[k].Face].Solid + 1)];
      const double overlap = r.Radius - BoundaryDistance(own, r.Center);
      if (overlap > out.Allowed && overlap > 1e-4 * r.Radius)
      {
        ++out.Overlapping;
        std::printf("[overlap] %s (chains of %d) sample %zu: 2t = %.6g, sphere %.3g into the "
                    "exact faces (%s)\n",
          name.c_str(), options.Chain, k * stride, r.Thickness, overlap, ContactTypeName(r.Type));
      }
      if (overlap > out.Worst)
      {
        out.Worst = overlap;
        out.WorstT = r.Radius;
      }
    }
    std::printf("[exact] %s (chains of %d): %zu of %zu samples solved; %zu (%.2f%%) overlap the "
                "exact faces by more than %.1e and 1e-4 t; largest overlap %.3g (t = %.4g)\n",
      name.c_str(), options.Chain, out.Solved, out.Samples, out.Overlapping,
      100.0 * out.Overlapping / std::max<size_t>(out.Solved, 1), out.Allowed, out.Worst,
      out.WorstT);
  }
  return out;
}

/// Every Data/ model, real parts included, against the exact B-Rep (CountOverlaps, the default
/// options): a sphere overlapping the exact faces is not maximal, a wall the verification and
/// the certification missed. This is the independent check that the agreement of the kernels
/// with the reference cannot give.
TEST(SolverExact, EveryDataModelAgainstBRepExtrema)
{
  for (const auto& name : test::DataModels())
  {
    const Overlaps o = CountOverlaps(name, SolverOptions());
    // Measured (docs/Solver.md): 0 on the analytic models; 0-0.73% on the real parts with s1 at
    // 1/300 of the diagonal and points along the edges (the NIST part's 1.5 mm round, where the
    // sphere touches a whole arc; 1.0-3.4% at 1/100, before the second look more). The bound
    // sits above; the rest is an open item, listed above.
    EXPECT_LE(o.Overlapping * 1000, o.Solved * 15) << name;
  }
}

/// Chains (SolverOptions::Chain, docs/Solver.md "Chains"): a sample starts from its predecessor's
/// contact, which only starts the solve; the certification decides. The ~400 samples spread over
/// each Data/ model solved as chains of 64 take every start from a sample far away, often across
/// another wall or on another face altogether: no sphere may overlap the exact faces, and no
/// sample may fail that the starts from s1 (chains of 1) solve.
TEST(SolverExact, FarChainStartsLeaveNoOverlap)
{
  for (const auto& name : test::DataModels())
  {
    SolverOptions far, s1;
    far.Chain = 64;
    s1.Chain = 1;
    const Overlaps a = CountOverlaps(name, far), b = CountOverlaps(name, s1);
    EXPECT_EQ(a.Overlapping, 0u) << name;
    EXPECT_GE(a.Solved, b.Solved) << name;
  }
}

/// A Data/ part at the default settings: the model, its exact faces in one compound, the
/// solver's data and the mesh samples (every vertex, the numbering the tests below use).
struct Part
{
  BRepModel Model;
  TopoDS_Compound Faces;
  std::vector<TopoDS_Face> FaceList; ///< the same faces, in the model's order
  SolverData Data;
};

Part LoadPart(const char* file)
{
  Part tile;
  std::vector<TopoDS_Face> faces;
  tile.Model = ConvertStepFile(test::DataFile(file), ConversionOptions(), &faces);
  BRep_Builder b;
  b.MakeCompound(tile.Faces);
  for (const TopoDS_Face& f : faces)
    b.Add(tile.Faces, f);
  tile.FaceList = faces;
  tile.Data = PrepareSolver(tile.Model, SolverOptions());
  return tile;
}

/// A sample these tests were written for, by value: its number in the part's display mesh when
/// the test was written (to name it), and the sample as SamplesFromMesh made it then (a vertex
/// on a face's boundary already moved into the face). The mesh may change; the model's patches,
/// and so these solves, do not.
struct Numbered
{
  size_t Id;
  Sample S;
};

/// The samples, solved by the reference at the defaults.
std::vector<SampleResult> SolveAt(const Part& part, const std::vector<Numbered>& numbered,
  std::vector<Sample>& samples, std::vector<size_t>& ids)
{
  samples.clear();
  ids.clear();
  for (const Numbered& n : numbered)
  {
    samples.push_back(n.S);
    ids.push_back(n.Id);
    // Still a point of its face (within the conversion tolerance, as the patches it was made
    // on): a reader that moved the face would leave the sample testing something else.
    const double off = BoundaryDistance(part.FaceList[static_cast<size_t>(n.S.Face)], n.S.Point);
    EXPECT_LE(off, 2.0 * part.Model.Tolerance) << "sample " << n.Id << " lies " << off
                                               << " off its face " << n.S.Face;
  }
  std::vector<SampleResult> res;
  SolveReference(part.Model, part.Data, SolverOptions(), samples, res);
  return res;
}

/// The samples solved, each sphere empty within the allowance (the clearance twice and the
/// patches' accuracy) and its radius within 1e-3 relative of ExactSphereRadius.
void ExpectExactSpheres(const char* tag, const Part& part, const std::vector<Numbered>& numbered)
{
  std::vector<Sample> samples;
  std::vector<size_t> ids;
  const std::vector<SampleResult> res = SolveAt(part, numbered, samples, ids);
  const double tolerance = part.Model.Tolerance;
  for (size_t k = 0; k < samples.size(); ++k)
  {
    ASSERT_NE(res[k].Type, ContactType::Failed) << ids[k] << ": " << FailReasonName(res[k].Reason);
    const double overlap = res[k].Radius - BoundaryDistance(part.Faces, res[k].Center);
    const double exact = ExactSphereRadius(part.Faces, samples[k], res[k].Radius, tolerance);
    ASSERT_GT(exact, 0.0) << ids[k];
    std::printf("[%s] sample %zu: 2t = %.6g, %.3g into the exact faces; exact 2t = %.6g\n", tag,
      ids[k], res[k].Thickness, overlap, 2.0 * exact);
    EXPECT_LE(overlap, 3.0 * tolerance) << ids[k];
    EXPECT_NEAR(res[k].Radius, exact, 1e-3 * exact) << ids[k];
  }
}

/// Two samples of the FRAMEWORK tile whose spheres (2t = 0.726 and 1.221) cut 0.009 and 0.011 mm
/// into a convex corner of the part over less than one s1 spacing, between the patch grid's
/// points, so the verification passed them (the exact spheres are 2t = 0.596 and 1.210, touching
/// that corner's edge). The points along the edges (brt::AddEdgePoints) expose such corners.
TEST(SolverExact, CornerNarrowerThanTheGrid)
{
  const Part tile = LoadPart("FRAMEWORK_DESKTOP_BLANK_TILE.stp");
  const BRepModel& m = tile.Model;
  const TopoDS_Compound& all = tile.Faces;
  // Samples 37264 and 38352 of the tile's display mesh of 54,779 vertices.
  const std::vector<Numbered> numbered{
    { 37264, 17, 23.456058269056847, 0.16927945708196987, { -29.006058269056847, 62.635246323186095, 205.06863529764092 }, { -0, -0.9961946980917451, -0.087155742747663953 } },
    { 38352, 20, 19.117642454463741, -1.5002656220646582, { -5.6261832454001501, 51.766720193363739, 203.39996287565629 }, { -0.99984769515639138, -0, 0.017452406437279848 } }
  };
  std::vector<Sample> samples;
  std::vector<size_t> ids;
  const std::vector<SampleResult> res = SolveAt(tile, numbered, samples, ids);
  const double allowed = 3.0 * m.Tolerance; // clearance (2x) + patches (1x)
  for (size_t k = 0; k < samples.size(); ++k)
  {
    ASSERT_NE(res[k].Type, ContactType::Failed) << k;
    const double overlap = res[k].Radius - BoundaryDistance(all, res[k].Center);
    std::printf("[corner] sample %zu: 2t = %.6g, %.3g into the exact faces\n", ids[k],
      res[k].Thickness, overlap);
    EXPECT_LE(overlap, allowed) << k;
  }
}

/// Five samples of the FRAMEWORK tile at a pin's root, where the drafted top face reaches 1.5 um
/// past the pin's round (an edge of file tolerance 2.2e-3): the surface Newton's contact lies on
/// the round's outer side and every descent fails, so the sample was flagged LeftModel. The
/// shrinking ball from eq. 1's first sphere solves it (docs/Solver.md, items 8 and 14). Against
/// OpenCASCADE: the sphere holds no exact face deeper than the allowance, and one half as wide
/// again (plus five tolerances) does: it is the maximal sphere at the tolerance's scale, not a
/// small empty one.
TEST(SolverExact, ShrinkingBallWhereNothingConverges)
{
  const Part tile = LoadPart("FRAMEWORK_DESKTOP_BLANK_TILE.stp");
  const BRepModel& m = tile.Model;
  const TopoDS_Compound& all = tile.Faces;
  // Samples of the tile's display mesh of 54,779 vertices.
  const std::vector<Numbered> numbered{
    { 47116, 36, 3.4436817317097406, 0.12700427808290088, { -9.5583262214425204, 40.218953802272907, 201.89335310965959 }, { -0.03700710955926903, 0.03700710955926903, -0.99862953475457383 } },
    { 47117, 36, 3.4631548241608647, 0.088500467264348931, { -9.5717456587452112, 40.259912351021313, 201.89536824341778 }, { -0.03700710955926903, 0.03700710955926903, -0.99862953475457383 } },
    { 47118, 36, 3.4767850028626603, 0.046584510192170477, { -9.5917061051438584, 40.299148780997612, 201.89756195511299 }, { -0.03700710955926903, 0.03700710955926903, -0.99862953475457383 } },
    { 47131, 36, 0.51004116744772987, 0.088500467264840621, { -11.659912351021317, 38.171745658744506, 201.89536824341775 }, { -0.03700710955926903, 0.03700710955926903, -0.99862953475457383 } },
    { 47132, 36, 0.52951425989864542, 0.12700427808359899, { -11.618953802272898, 38.158326221441527, 201.89335310965956 }, { -0.03700710955926903, 0.03700710955926903, -0.99862953475457383 } }
  };
  std::vector<Sample> samples;
  std::vector<size_t> ids;
  const std::vector<SampleResult> res = SolveAt(tile, numbered, samples, ids);
  const double allowed = 3.0 * m.Tolerance; // clearance (2x) + patches (1x)
  for (size_t k = 0; k < samples.size(); ++k)
  {
    ASSERT_NE(res[k].Type, ContactType::Failed) << ids[k] << ": " << FailReasonName(res[k].Reason);
    const double overlap = res[k].Radius - BoundaryDistance(all, res[k].Center);
    const double wider = 1.5 * res[k].Radius + 5.0 * m.Tolerance;
    std::array<double, 3> c;
    for (int i = 0; i < 3; ++i)
      c[i] = samples[k].Point[i] + wider * samples[k].Direction[i];
    const double overlapWider = wider - BoundaryDistance(all, c);
    std::printf("[shrink] sample %zu: 2t = %.6g, %.3g into the exact faces; 2t = %.6g: %.3g\n",
      ids[k], res[k].Thickness, overlap, 2.0 * wider, overlapWider);
    EXPECT_LE(overlap, allowed) << ids[k];
    EXPECT_GT(overlapWider, allowed) << ids[k];
  }
}

/// Samples of the ExpansionCard next to edges whose curves the file lets stand up to 1.5e-3 mm
/// off their planar faces (OpenCASCADE's edge tolerance 5.7e-4 to 1.5e-3): an s1 point of such
/// an edge lies inside the sphere near O, where the certification counts nothing, and no restart
/// from a face shrinks the sphere. They were flagged NotMaximal; the shrinking ball through the
/// edge's points settles them on the edge's curve (docs/Solver.md, item 14). Against
/// OpenCASCADE: no exact face deeper than the allowance, and the radius is the exact one by the
/// solver's definition (the largest sphere tangent at O that no exact face enters deeper than
/// the clearance, by bisection, then eq. 1 through the exact point nearest to its centre) within
/// 1e-3 relative: 2t = 0.44-0.59 where the edge bounds a wall of 0.6 mm, about 5e-4 at the step
/// its curve makes next to O.
TEST(SolverExact, EdgeCurveOffItsFace)
{
  const Part card = LoadPart("ExpansionCard_SelfTapping.stp");
  // Samples of the ExpansionCard's display mesh of 92,898 vertices.
  const std::vector<Numbered> numbered{
    { 53951, 87, 0.31892324133254041, 0.00082550641506325194, { -13.17895080172933, 3.99787925313673, -31.124407705050608 }, { 0.90755255711053162, 0.043238217083936117, 0.41770661075153881 } },
    { 53967, 87, 0.70106254906091614, 0.9998321483171283, { -13.43979319800747, 4.2149126109373922, -30.999265507025015 }, { 0.20044984137671487, 0.97970322650785935, 0.0012037699696095154 } },
    { 53968, 87, 0.1765361520253636, 0.99960159867845844, { -13.392738575919964, 4.2594402527795685, -31.165420118583977 }, { 0.044128725121717643, 0.83104957994200868, 0.55444499393298041 } },
    { 53969, 87, 0.31892616622724718, 0.9991858112508295, { -13.406402914858315, 4.2375608594837333, -31.124406704747233 }, { 0.090677184435447283, 0.90404817439479979, 0.41770150418245983 } },
    { 55376, 107, 0.19927294869500045, 0.99909280757794139, { -13.4039290982449, 2.4578769026210194, -31.164696018549837 }, { 0.0088671320133935413, -0.83229589540449245, 0.55426069359344898 } },
    { 55379, 107, 0.66359983588135318, 0.99889360575941111, { -13.441034997482745, 2.5028114999556426, -31.038484631270954 }, { 0.13243960156589388, -0.98213364810255543, 0.13369087179696668 } },
    { 55380, 107, 0.80080947301541305, 0.99888993298483264, { -13.450613319343324, 2.5041043841794779, -30.998552526110824 }, { 0.16441253961392618, -0.98639156011273432, 0.00045492424096966268 } },
    { 56949, 134, 0.82497406270077001, 0.99970587427773305, { 13.450456504597184, 2.5041306013812545, -30.99847727725799 }, { -0.16495351007742062, -0.98630123605231912, 0.00045964639223280626 } },
    { 56952, 134, 0.58563532938042928, 0.99913542656660825, { 13.430195019803412, 2.495949386658086, -31.078050851560342 }, { -0.099344306415049766, -0.95912107700233062, 0.26498578911481668 } },
    { 56953, 134, 0.70439274998716728, 0.99913478042719495, { 13.440605554350649, 2.5028355116130583, -31.038577725280071 }, { -0.13315826014794491, -0.98183580430392714, 0.13515669107089323 } },
    { 56968, 134, 0.58566459357820244, 0.00067256698771115872, { 13.195208991024861, 2.7334741084981613, -31.078063745891772 }, { -0.96014365108553279, -0.089028978142177834, 0.26494907120256533 } },
    { 56969, 134, 0.70442633952582057, 0.00067305359363705993, { 13.202204985141007, 2.7438121292959345, -31.03858944595277 }, { -0.98321514114197595, -0.12260331644819787, 0.13511629444692141 } },
    { 57675, 150, 0.31867948638946303, 0.00081883881357209685, { 13.406401863579829, 4.2375635604678354, -31.124412858672809 }, { -0.090739112492453075, 0.90402539669239168, 0.41773735241087334 } },
    { 57676, 150, 0.45986002576181395, 0.00081826846958995604, { 13.419637003090205, 4.2226123340192876, -31.079756950124125 }, { -0.13475643468667542, 0.95334758304407974, 0.27012791269053821 } },
    { 57677, 150, 0.57937970161415364, 0.00081778563159986986, { 13.430049826734857, 4.2159167901233978, -31.040047474152065 }, { -0.16957898854661471, 0.97614029827871074, 0.13562110720627837 } }
  };
  ExpectExactSpheres("edge curve", card, numbered);
}

/// The moulded cover (Data/unseen/; traced in the seventh session, so no longer unseen): its long
/// extrusions (faces 24, 27 and 484) cross the faces next to them by about the edge's tolerance
/// in the file (2.3e-3 mm), up to 2.6e-3 mm above O. The deepest point of the extrusion in these
/// 39 spheres is the nearest point of its patch clamped to the face's trim, 6.8e-11 outside it by
/// the trim test: the certification must count such a point (on the trim within 1e-9 of the
/// domain: on the face). Without that rule these spheres held the extrusion 4.9e-4 to 2.61e-3 mm
/// deep (brt_exact_check's second distance; BRepExtrema_DistShapeShape misses the point).
TEST(SolverExact, PointOnTheTrimCounts)
{
  const Part cover = LoadPart("unseen/FRAMEWORK_DESKTOP_TOP_COVER_V0.stp");
  const BRepModel& m = cover.Model;
  // Samples of the cover's display mesh of 67,208 vertices.
  const std::vector<Numbered> numbered{
    { 19599, 27, 0.29606586871663076, 71.571875000035931, { -0.8963651246986577, 0.010626098883233759, 128.72812499996408 }, { -0.060575462387975329, 0.99816362053346896, -0 } },
    { 19792, 27, 0.27697798671985391, 65.365625000032821, { -0.8873939830498192, 0.011128076189161935, 134.93437499996719 }, { -0.050899156202893189, 0.99870379787894747, -0 } },
    { 19808, 27, 0.29606589016094531, 164.66562500007939, { -0.89636513475694324, 0.010626098272827469, 35.634374999920624 }, { -0.060575472354312189, 0.99816361992864278, -0 } },
    { 47993, 481, 0.91935975891850419, 74.495524410381037, { -0.79994820280237589, 96.780313655680146, 75.995524410381023 }, { -0.13492674302716975, -0.99085557676993474, 4.9577716002143844e-16 } },
    { 48160, 481, 0.90087946631387616, 86.887358902632343, { -0.76809790611423079, 96.775721501028727, 88.387358902632343 }, { -0.15062446320646156, -0.98859105351189847, 0 } },
    { 48689, 481, 0.87227138174354724, 192.39374279561116, { -0.7198079030911364, 96.767730132752135, 193.89374279561116 }, { -0.17626873941830642, -0.98434208053089001, 0 } },
    { 48695, 481, 0.87139099724544422, 155.15619956927827, { -0.71834168364719653, 96.767466946079708, 156.65619956927827 }, { -0.17708455325442851, -0.98419564162755746, 0 } },
    { 48847, 481, 0.89163675292053146, 130.33116884866152, { -0.75236029632079116, 96.773257915036325, 131.83116884866152 }, { -0.15872810392963588, -0.98732233288977245, 0 } },
    { 49054, 481, 0.91628399010002382, 179.98122648377205, { -0.79461197211332968, 96.779579980098376, 181.48122648377205 }, { -0.13749340159367279, -0.99050268274154663, 0 } },
    { 49182, 481, 0.89779856232518629, 155.15619956927827, { -0.76283771965466296, 96.774912751697201, 156.65619956927827 }, { -0.15330671245476843, -0.98817865384570569, 0 } },
    { 50577, 481, 0.90550082344971861, 114.81551917697426, { -0.77601491796672573, 96.776911389124692, 116.31551917697426 }, { -0.14663634659312455, -0.98919046793720233, 0 } },
    { 51044, 481, 0.90858172842653262, 158.25932531688045, { -0.78131068684211802, 96.777689208859968, 159.75932531688045 }, { -0.14400095139800284, -0.9895775492585055, 0 } },
    { 51048, 481, 0.90858172820694993, 133.4342926932022, { -0.78131068646417201, 96.777689208804972, 134.9342926932022 }, { -0.14400095158517065, -0.98957754923126939, 0 } },
    { 51077, 481, 0.89933901459401311, 152.05307001555315, { -0.76546602793875096, 96.775318678472019, 153.55307001555315 }, { -0.15196322815193339, -0.98838614786410439, 0 } },
    { 51078, 481, 0.89933901371566116, 52.75293952084013, { -0.76546602643909478, 96.775318678241447, 54.25293952084013 }, { -0.15196322891662942, -0.98838614774653344, 0 } },
    { 51846, 481, 0.91782444203947922, 139.6405479945295, { -0.7972827929832752, 96.7799489506708, 141.1405479945295 }, { -0.13620565873173443, -0.99068058350280308, 0 } },
    { 51860, 481, 0.91474353717243972, 108.60925816646247, { -0.79194466422812315, 96.779207954008953, 110.10925816646247 }, { -0.13878571612461352, -0.9903224348664319, 0 } },
    { 51874, 481, 0.9085817276579744, 71.371711134006574, { -0.78131068551927496, 96.777689208667468, 72.871711134006574 }, { -0.14400095205310612, -0.98957754916317664, 0 } },
    { 51883, 481, 0.90241991814350198, 34.134164101550695, { -0.77073335020194211, 96.776121223976929, 35.634164101550695 }, { -0.14929040372512564, -0.98879339366502095, 0 } },
    { 52204, 481, 0.91782444099639593, 21.721643032057841, { -0.79728279117359868, 96.779948950421996, 23.221643032057841 }, { -0.1362056596021568, -0.99068058338313125, 0 } },
    { 52738, 481, 0.91935975927525782, 114.825858660265, { -0.79994820342212769, 96.780313655764516, 116.32585866026497 }, { -0.13492674273053168, -0.99085557681032854, 1.6508539712977772e-15 } },
    { 55299, 483, 0.39483582555409963, 0.19521605381522611, { -0.80472941997665259, 96.735588154308473, 200.20929672110762 }, { -0.10530791833607679, -0.75938504549551855, -0.64206276563393028 } },
    { 55673, 484, 0.2578900841467972, 189.29061872621583, { -0.87837084087115502, 96.788461786179425, 190.79061872621583 }, { -0.039678432236416115, -0.99921250093023761, 0 } },
    { 55864, 484, 0.23880220395951335, 145.84683547515959, { -0.86927376941609924, 96.788151893222008, 147.34683547515959 }, { -0.030015211130320608, -0.99954944204916762, 0 } },
    { 56799, 488, 0.91935728713206488, 0.020436070406532544, { -0.79994390882146726, 1.9204360704065329, 0.019686929046287573 }, { -0.13492879839171726, -7.2042064734951411e-19, 0.9908552968847506 } },
    { 57048, 488, 0.89794540706394499, 11.625913152752004, { -0.76308811095178086, 13.525913152752004, 0.025048419071214759 }, { -0.15317843999456973, -0, 0.98819854559740672 } },
    { 57649, 488, 0.90572110408253081, 17.438362299291089, { -0.77639308752361669, 19.338362299291088, 0.023032588433183315 }, { -0.14644730115457405, -0, 0.98921847333364199 } },
    { 59090, 488, 0.90330027204670527, 8.7197001874412532, { -0.77224108121430968, 10.619700187441254, 0.023651728248282572 }, { -0.14853010900905894, -0, 0.98890788586084044 } },
    { 59329, 488, 0.9170909065095767, 2.9072781261393481, { -0.79601055806606968, 4.807278126139348, 0.020226365725058967 }, { -0.13681828954551378, -0, 0.99059616173587095 } },
    { 60345, 491, 0.91936110959185191, 87.066812500043739, { -0.79995054919237962, 0.019686024810791791, 113.23318749995626 }, { -0.13492561991084023, 0.99085572970623492, -8.250228852159482e-20 } },
    { 61113, 491, 0.90344716811593484, 142.94375000007, { -0.77249277472589384, 0.02361394135424183, 57.356249999930014 }, { -0.14840339505874942, 0.98892690950091799, -0 } },
    { 61116, 491, 0.89889923932423244, 56.056250000025713, { -0.76471532220389249, 0.024796890555540047, 144.24374999997428 }, { -0.15234629025244126, 0.98832717651915192, -0 } },
    { 62136, 491, 0.88639245417047541, 170.87187500008201, { -0.74348830515234354, 0.028189903136196806, 29.428124999917998 }, { -0.16340250963849029, 0.98655948621653977, -0 } },
    { 62151, 491, 0.88514512634216902, 9.5093750000042938, { -0.7413843083659446, 0.028539611747148405, 190.79062499999571 }, { -0.16452251171247623, 0.98637332848157355, -0 } },
    { 62478, 491, 0.90473080624415503, 28.128125000012865, { -0.77469355175914167, 0.023284939979687849, 172.17187499998715 }, { -0.14729792732373684, 0.98909216992458859, -0 } },
    { 63189, 491, 0.90913207276442431, 133.63437500006597, { -0.78225816584571717, 0.022173145504408631, 66.665624999934039 }, { -0.14353214509373138, 0.98964565543672856, -0 } },
    { 63206, 491, 0.90231018825421805, 164.66562500008081, { -0.77054550367983699, 0.023907146761524584, 35.634374999919203 }, { -0.14938527644815824, 0.98877906489797163, -0 } },
    { 64797, 491, 0.9159539589433523, 133.6343750000668, { -0.7940402242318747, 0.020499466546508277, 66.665624999933215 }, { -0.13776988565711151, 0.99046426417414291, -0 } },
    { 64918, 491, 0.88184452638000677, 102.60312500004713, { -0.73582829514596249, 0.029474941809942423, 97.696874999952882 }, { -0.16750151608431249, 0.98587181829559212, -0 } }
  };
  std::vector<Sample> samples;
  std::vector<size_t> ids;
  const std::vector<SampleResult> res = SolveAt(cover, numbered, samples, ids);
  const double allowed = 3.0 * m.Tolerance; // clearance (2x) + patches (1x)
  const std::vector<Bnd_Box> boxes = exact::FaceBoxes(cover.FaceList);
  double worst = 0.0;
  for (size_t k = 0; k < samples.size(); ++k)
  {
    ASSERT_NE(res[k].Type, ContactType::Failed) << ids[k] << ": " << FailReasonName(res[k].Reason);
    const gp_Pnt M(res[k].Center[0], res[k].Center[1], res[k].Center[2]);
    const double dist = std::min(BoundaryDistance(cover.Faces, res[k].Center),
      exact::ExtremaDistance(cover.FaceList, boxes, M, res[k].Radius));
    const double overlap = res[k].Radius - dist;
    worst = std::max(worst, overlap);
    EXPECT_LE(overlap, allowed) << ids[k] << ": 2t = " << res[k].Thickness;
  }
  std::printf("[trim point] %zu cover samples: largest overlap of the exact faces %.3g (allowed "
              "%.3g)\n", samples.size(), worst, allowed);
}
/// The moulded cover's extrusions 24 and 488 meet at an edge, and the spheres tangent on either
/// next to it are bounded by the other one's points along that edge: the face's nearest point to
/// the centre lies on its parameter border, which is the edge. The certification's Newton on the
/// patch clamps to that border, where the trim test passes the point over or the edge, being O's
/// own face's, counts only a slack deeper; the face's points just inside the border were never
/// asked, and these spheres read 2t up to 15% too large (57651: 0.6090, 19033: 1.5842, 19080:
/// 0.7986) holding the other face up to 4e-4 mm deep. Expected, independent of the solver:
/// brt_exact_check --grid 200 --thickness (OpenCASCADE's distance from the centre to the faces,
/// a 200 x 200 grid over each and its local minima refined; the clearance's sphere), within 1e-3
/// relative (the contacts are grazing, where a sphere larger by e relative holds the face only
/// about e^2 t deep); and each foot a point of its face (BRepExtrema, 1e-9).
TEST(SolverExact, FaceBorderAlongOwnEdgeCounts)
{
  const Part cover = LoadPart("unseen/FRAMEWORK_DESKTOP_TOP_COVER_V0.stp");
  // Samples of the cover's display mesh of 67,208 vertices.
  const std::vector<Numbered> numbered{
    { 19080, 24, 0.25682962449867325, 55.219181149488833, { -0.87786754644662579, 57.119181149488831, 0.011558031569065957 }, { -0.039011995905371688, -0, 0.99923874233112042 } },
    { 19033, 24, 0.29394491146971913, 31.969357606266023, { -0.89537012598416132, 33.869357606266021, 0.01068598579806374 }, { -0.059579638575769873, -0, 0.99822355545598129 } },
    { 18675, 24, 0.28228015531164807, 63.937831653380378, { -0.88989016300718771, 65.837831653380377, 0.010997265659710096 }, { -0.053746336519172343, -0, 0.99855462109529491 } },
    { 57651, 488, 0.89662526214089411, 29.063229637812483, { -0.76083824233994413, 30.963229637812482, 0.025398511550375549 }, { -0.15433316417622336, -0, 0.98801886340057044 } },
    { 57086, 488, 0.87388565728680201, 58.125397984115963, { -0.72249947259383618, 60.025397984115962, 0.031789986826252892 }, { -0.17477705586912867, -0, 0.98460803406315922 } }
  };
  const double exact[] = { 0.796188, 1.55202, 1.26304, 0.528004, 1.45995 };
  std::vector<Sample> samples;
  std::vector<size_t> ids;
  const std::vector<SampleResult> res = SolveAt(cover, numbered, samples, ids);
  double worst = 0.0;
  for (size_t k = 0; k < samples.size(); ++k)
  {
    ASSERT_NE(res[k].Type, ContactType::Failed) << ids[k] << ": " << FailReasonName(res[k].Reason);
    const double rel = std::fabs(res[k].Thickness - exact[k]) / exact[k];
    worst = std::max(worst, rel);
    EXPECT_LE(rel, 1e-3) << ids[k] << ": 2t = " << res[k].Thickness << ", exact " << exact[k];
    ASSERT_GE(res[k].OppositeFace, 0) << ids[k];
    EXPECT_LE(BoundaryDistance(cover.FaceList[static_cast<size_t>(res[k].OppositeFace)], res[k].Foot),
      1e-9) << ids[k] << ": the foot off its face";
  }
  std::printf("[face border] %zu cover samples: 2t within %.2e relative of the exact thickness\n",
    samples.size(), worst);
}

/// The sphere of `radius` tangent at o along its direction, as a surface/surface result (the
/// certification's question: is it empty?).
SampleResult SphereAlong(const Sample& o, double radius)
{
  SampleResult sphere;
  sphere.Type = ContactType::SurfaceSurface;
  sphere.Radius = radius;
  sphere.Thickness = 2.0 * radius;
  for (int k = 0; k < 3; ++k)
    sphere.Center[k] = o.Point[k] + radius * o.Direction[k];
  return sphere;
}
} // namespace

/// A half ball (a sphere of radius 20 cut through its axis: the spherical face's poles lie on the
/// flat face's rim). On the flat face the maximal sphere at O, a distance rho from the centre, is
/// the one touching the spherical face: t = (R^2 - rho^2) / (2 R), down to nothing at the rim.
/// Every flat-face sample against the closed form, every sphere against OpenCASCADE's distance,
/// and spheres made too large near the poles against the certification. The configuration of a
/// file of OpenCASCADE's test data (trj3_s1-md-214.stp, not kept), where the certification's
/// Newton stopped at a pole of a sphere's patches (u's derivative vanishes there) and a sphere
/// 0.5 mm wide with the spherical face 0.43 mm deep inside it passed; this shape did not make the
/// certification miss before the fix either (R 20 and 59, 1,080 and 250 spheres tried): it guards
/// the poles, the fix itself was measured on that file (docs/Solver.md, twenty-fifth session).
TEST(SolverExact, PlaneThroughASpheresPoles)
{
  const double R = 20.0;
  const TopoDS_Shape half = BRepPrimAPI_MakeSphere(gp_Pnt(0, 0, 0), R, M_PI).Shape();
  const test::Solved s = test::SolveShape(half, ConversionOptions().Tolerance);
  const TopoDS_Shape all = Faces(half);
  const double allowed = 3.0 * s.Model.Tolerance; // clearance (2x) + patches (1x)
  size_t flat = 0, nearPole = 0;
  double worst = 0.0;
  for (size_t i = 0; i < s.Samples.size(); ++i)
  {
    const Sample& o = s.Samples[i];
    const SampleResult& r = s.Results[i];
    ASSERT_NE(r.Type, ContactType::Failed) << i;
    const double overlap = r.Radius - BoundaryDistance(all, r.Center);
    worst = std::max(worst, overlap);
    EXPECT_LE(overlap, allowed) << "sample " << i << " 2t = " << r.Thickness;
    if (s.Model.Faces[static_cast<size_t>(o.Face)].Kind != SurfaceKind::Plane)
      continue;
    ++flat;
    const double rho2 = o.Point[0] * o.Point[0] + o.Point[1] * o.Point[1] + o.Point[2] * o.Point[2];
    const double t = (R * R - rho2) / (2.0 * R);
    EXPECT_LE(r.Radius, t + allowed) << "sample " << i << " at rho^2 " << rho2;
    nearPole += std::abs(o.Point[2]) > R - 1.0 ? 1 : 0;
  }
  std::printf("[half ball] %zu flat-face samples (%zu within 1 of a pole), deepest overlap %.3g\n",
    flat, nearPole, worst);
  EXPECT_GT(flat, 100u);
  EXPECT_GT(nearPole, 0u);
  // The certification itself, given spheres too large: at each flat-face sample near a pole, the
  // sphere tangent at O whose centre lies 6e-4 inside the spherical surface (the spherical face
  // then lies about t deep inside it): each must be found to hold the boundary.
  const NativeSolver native(s.Model, s.Data);
  size_t tried = 0, missed = 0;
  for (const Sample& o : s.Samples)
  {
    if (s.Model.Faces[static_cast<size_t>(o.Face)].Kind != SurfaceKind::Plane ||
      std::abs(o.Point[2]) < R - 2.0)
      continue;
    const double rho2 = o.Point[0] * o.Point[0] + o.Point[1] * o.Point[1] + o.Point[2] * o.Point[2];
    const double od = o.Point[0] * o.Direction[0] + o.Point[1] * o.Direction[1] +
      o.Point[2] * o.Direction[2];
    const double reach = R - 6e-4; // |O + t d| = reach
    const double disc = od * od - (rho2 - reach * reach);
    if (disc <= 0.0)
      continue;
    const double t = -od + std::sqrt(disc);
    if (t < 10.0 * allowed)
      continue;
    const SampleResult big = SphereAlong(o, t);
    ++tried;
    missed += native.HoldsBoundary(SolverOptions(), o, big) ? 0 : 1;
  }
  // And spheres 0.5 mm wide on the flat face within a hair of the rim, 0.05-1 mm from a pole, as
  // trj3_s1-md-214.stp's: no grid point of the pole's patches lies in them.
  for (const Sample& o : s.Samples)
  {
    if (s.Model.Faces[static_cast<size_t>(o.Face)].Kind != SurfaceKind::Plane ||
      std::abs(o.Point[2]) < R - 2.0 || std::abs(o.Point[0]) < 1e-3)
      continue;
    for (const double x : { 0.05, 0.1, 0.2, 0.5, 1.0 })
    {
      const double t = 0.5, reach = R - 6e-4;
      // O = (x, 0, z) on the flat face, |O + t d| = reach, d = (0, +-1, 0).
      const double z2 = reach * reach - t * t - x * x;
      Sample near = o;
      near.Point = { std::copysign(x, o.Point[0]), 0.0, std::copysign(std::sqrt(z2), o.Point[2]) };
      const SampleResult big = SphereAlong(near, t);
      ++tried;
      missed += native.HoldsBoundary(SolverOptions(), near, big) ? 0 : 1;
    }
  }
  std::printf("[half ball] spheres too large near the poles: %zu tried, %zu passed the "
              "certification\n", tried, missed);
  EXPECT_GT(tried, 10u);
  EXPECT_EQ(missed, 0u);
}

/// A face that grazes the sphere tangent at O: z = c x^2 - e x^3 - k y^2 over x in [0, 1] and
/// y in [-1/2, 1/2], one bicubic patch with O = (0, 0, 0) the middle of its side u = 0 (a point of
/// the certification's 5 x 5 grid), the sphere of radius 1 above it (centre (0, 0, 1)). Along x
/// the face bends up into the sphere for 0 < x < (c - 1/2) / e (0.125) and out of it beyond, so
/// every grid point but O lies outside the sphere and O, at exactly the radius, is the nearest.
/// O is a stationary point of the distance from the centre: the certification's Newton, started
/// there, stayed, and the face 4.6e-4 deep inside the sphere 0.08 from O went unseen (OpenCASCADE's
/// bug33398.step, sample 31641: O's own B-spline face 7.3e-4 mm deep, 0.21 from O, 2t = 2.874
/// against an exact 2.707). Newton now starts from the nearest grid point but O's own. With
/// c = 0.45 the face stays outside the sphere (the same grid, nothing inside): not flagged.
TEST(SolverExact, GrazingOwnFaceNextToO)
{
  for (const double c : { 0.7, 0.45 })
  {
    const double e = (c - 0.5) > 0.0 ? (c - 0.5) / 0.125 : 1.6, k = 0.5;
    // Bernstein coefficients of z = g(u) + h(v): g = c u^2 - e u^3, h = -k (v - 1/2)^2.
    const double g[4] = { 0.0, 0.0, c / 3.0, c - e };
    const double h[4] = { -k / 4.0, k / 12.0, k / 12.0, -k / 4.0 };
    TColgp_Array2OfPnt poles(1, 4, 1, 4);
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
        poles.SetValue(i + 1, j + 1, gp_Pnt(i / 3.0, j / 3.0 - 0.5, g[i] + h[j]));
    Handle(Geom_BezierSurface) surface = new Geom_BezierSurface(poles);
    const TopoDS_Face face = BRepBuilderAPI_MakeFace(surface, 1e-7).Face();
    // One patch, as a face of this size gets in a part eight times its size or more (patches
    // are split to 1/8 of the model's diagonal).
    ConversionOptions conversion;
    conversion.MaxPatchSize = 2.0;
    const BRepModel model = ConvertShape(face, conversion);
    const SolverData data = PrepareSolver(model, SolverOptions());
    ASSERT_EQ(model.Faces.size(), 1u);
    if (c > 0.5)
    {
      ASSERT_EQ(model.Patches.size(), 1u);
    }
    Sample o;
    o.Face = 0;
    o.U = 0.0;
    o.V = 0.5;
    o.Point = { 0.0, 0.0, 0.0 };
    o.Direction = { 0.0, 0.0, 1.0 };
    const SampleResult sphere = SphereAlong(o, 1.0);
    // The premise, by OpenCASCADE: how deep the face reaches into the sphere.
    const double depth = 1.0 - BoundaryDistance(face, sphere.Center);
    const bool holds = NativeSolver(model, data).HoldsBoundary(SolverOptions(), o, sphere);
    std::printf("[grazing] c %.2f: the face %.3g deep in the sphere (OpenCASCADE), the "
                "certification says %s\n",
      c, depth, holds ? "not empty" : "empty");
    if (c > 0.5)
    {
      EXPECT_GT(depth, 4e-4);
      EXPECT_TRUE(holds);
    }
    else
    {
      EXPECT_LE(depth, 1e-9);
      EXPECT_FALSE(holds);
    }
  }
}

/// The certification, given the sphere of `radius` tangent at o, finds the boundary that
/// OpenCASCADE puts more than minDepth inside it (`face`, whose model is `model`).
void ExpectCertificationFinds(const char* name, const TopoDS_Face& face, const BRepModel& model,
  const Sample& o, double radius, double minDepth)
{
  const SolverData data = PrepareSolver(model, SolverOptions());
  const SampleResult sphere = SphereAlong(o, radius);
  const double depth = radius - BoundaryDistance(face, sphere.Center);
  const bool holds = NativeSolver(model, data).HoldsBoundary(SolverOptions(), o, sphere);
  std::printf("[%s] the face %.3g deep in the sphere (OpenCASCADE), the certification says %s\n",
    name, depth, holds ? "not empty" : "empty");
  EXPECT_GT(depth, minDepth);
  EXPECT_TRUE(holds);
}

/// The certification, given the sphere of `radius` tangent at O along d, on the face of one
/// bicubic Bezier patch (control points c, row by row along u) beside a 1 mm square of the plane
/// through O normal to d (the sample's own face), finds the patch more than minDepth inside it.
void ExpectPatchBesideSquareFound(const char* name, const double (&c)[16][3], const gp_Pnt& O,
  const gp_Dir& d, double radius, double minDepth)
{
  TColgp_Array2OfPnt poles(1, 4, 1, 4);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      poles.SetValue(i + 1, j + 1, gp_Pnt(c[4 * i + j][0], c[4 * i + j][1], c[4 * i + j][2]));
  Handle(Geom_BezierSurface) surface = new Geom_BezierSurface(poles);
  const TopoDS_Face patch = BRepBuilderAPI_MakeFace(surface, 1e-7).Face();
  const TopoDS_Face square =
    BRepBuilderAPI_MakeFace(gp_Pln(gp_Ax3(O, d)), -0.5, 0.5, -0.5, 0.5).Face();
  ConversionOptions conversion;
  conversion.MaxPatchSize = 100.0;
  const BRepModel model = ConvertShape(analytic::CompoundOf(square, patch), conversion);
  ASSERT_EQ(model.Faces.size(), 2u);
  ASSERT_EQ(model.Faces[1].PatchCount, 1);
  Sample o;
  o.Face = 0;
  o.Point = { O.X(), O.Y(), O.Z() };
  o.Direction = { d.X(), d.Y(), d.Z() };
  ExpectCertificationFinds(name, patch, model, o, radius, minDepth);
}

/// A wall whose section bends much within one patch: a ruled cubic face, x(u), z(u) with
/// control points (0, 0), (-2.5, 2.55) twice and (-0.25, 10.55), straight along y over 2 (the
/// side wall of Bastardkb's Charybdis Mini case, a single B-spline patch there). A sphere of
/// radius 1 whose centre lies 0.0086 from the wall's bulge holds it 0.99 deep, yet every point of
/// the certification's 5 x 5 grid lies outside it (the nearest 1.3 from the centre), and
/// Newton's first step from there lands farther still (the bulge bends the distance within the
/// step): stopping there, the certification passed the sphere, and the chained solve's start
/// across the 2 mm plate stood, 2t = 2 against the exact 0.0172 (`brt_exact_check`). The step
/// is now halved back until it gets nearer.
TEST(SolverExact, BulgingWallBeyondNewtonsFirstStep)
{
  TColgp_Array2OfPnt poles(1, 4, 1, 2);
  const double x[4] = { 0.0, -2.5058, -2.5058, -0.246082 };
  const double z[4] = { 0.0, 2.54793, 2.54793, 10.5484 };
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 2; ++j)
      poles.SetValue(i + 1, j + 1, gp_Pnt(x[i], -2.0 * j, z[i]));
  Handle(Geom_BezierSurface) surface = new Geom_BezierSurface(poles);
  const TopoDS_Face face = BRepBuilderAPI_MakeFace(surface, 1e-7).Face();
  ConversionOptions conversion;
  conversion.MaxPatchSize = 20.0;
  const BRepModel model = ConvertShape(face, conversion);
  ASSERT_EQ(model.Patches.size(), 1u);
  // The centre where the Charybdis sample's sphere had it: 1.8055 and 4.5248 from the wall's
  // first corner, half way along y; O one radius above it along y. OpenCASCADE puts the wall
  // 0.99 into the sphere.
  Sample o;
  o.Face = 0;
  o.Point = { -1.80552, 0.0, 4.52476 };
  o.Direction = { 0.0, -1.0, 0.0 };
  ExpectCertificationFinds("bulging wall", face, model, o, 1.0, 0.9);
}

/// A patch with two valleys towards the centre: one bicubic B-spline patch of Bastardkb's
/// charybdisnano case (a bend 18 mm wide, its 16 control points as the file's), and the sphere
/// of radius 2 that a chained start gave the sample beside it (its centre 2 along the normal of
/// the plane the sample lies on, a 1 mm square here). Newton from the nearest of the 5 x 5 grid's
/// points ends on the patch's border where the sphere touches it; the patch dips 0.086 mm into
/// the sphere in its other valley, between the grid's points. Only O's own face had the finer
/// grid for such a patch; a face without an exact surface whose Newton ends on the patch's border
/// at the sphere now has it too (`brt_exact_check`: 2t = 4 where the exact thickness is 3.909).
TEST(SolverExact, SecondValleyOfALargePatch)
{
  const double c[16][3] = { { -14.7648872, 0, -66.4798388 }, { -14.7648872, 0.722161458, -66.4798388 },
    { -14.519712, 3.38632298, -64.5645013 }, { -14.0295401, 5.07948446, -60.7422724 },
    { -20.6355724, 0, -67.0432485 }, { -20.6355724, 0.722161458, -67.0432485 },
    { -20.3612879, 4.08293819, -65.0861025 }, { -19.8997125, 6.12440729, -60.7670029 },
    { -26.5062576, 0, -67.6066583 }, { -26.5062576, 0.722161458, -67.6066583 },
    { -26.2617485, 4.77955341, -65.3300205 }, { -25.7698848, 7.16933011, -60.7917334 },
    { -32.3769429, 0, -68.170068 }, { -32.3769429, 0.722161458, -68.170068 },
    { -32.1313143, 5.47616862, -65.7188666 }, { -31.6400572, 8.21425293, -60.816464 } };
  const gp_Pnt O(-30.240738737, -0.00333333333333, -63.9466781852);
  const gp_Dir d(0.0955310864584, 0.0, -0.995426447067);
  ExpectPatchBesideSquareFound("second valley", c, O, d, 2.0, 0.08);
}

/// A second basin of the 5 x 5 grid on a patch smaller than the sphere: one bicubic patch of the
/// SO-ARM101 arm's base (TheRobotStudio/SO-ARM100, Base_SO101.step; a B-spline face curving
/// about as the sphere does, its v = 1 side a pole; its 16 control points as converted), and the
/// sphere of radius 2.4914 at which the shrinking ball settled sample 11374 of that face (the
/// patch here beside a 1 mm square of the plane through O, as the sample's own face it was).
/// The distance from the centre is nearly flat over the patch: the grid's nearest point (its
/// border u = 0) led Newton to the border, 0.0009 outside the sphere, while the patch dips about
/// 1.2e-3 into it between the grid's first two rows near u = 0.6 of the patch, whose nearest
/// grid point was only the second nearest; the patch is narrower than the sphere's radius, so
/// no finer grid ran (`brt_exact_check`: 2t = 4.9672 where the exact thickness is 4.9533, face
/// 69 5.3e-4 mm inside). Newton now also starts from the grid's next local minimum there.
TEST(SolverExact, SecondBasinOfASmallPatch)
{
  const double c[16][3] = { { -40.656265812, 16.370331941, -15.345253016 },
    { -40.562866378, 17.071031147, -14.784856414 }, { -40.414989959, 17.5, -13.897597901 },
    { -40.265390309, 17.5, -13.0 }, { -41.127760422, 16.600557444, -15.157418739 },
    { -40.856697635, 17.245530498, -14.528234716 }, { -40.557465817, 17.5, -13.755122044 },
    { -40.265390309, 17.5, -13.0 }, { -41.599868827, 16.707536721, -14.823820983 },
    { -41.154574643, 17.322230306, -14.247692591 }, { -40.699941674, 17.5, -13.612646186 },
    { -40.265390309, 17.5, -13.0 }, { -41.971124476, 16.673189681, -14.410588709 },
    { -41.43965962, 17.297063085, -13.958570971 }, { -40.842417531, 17.5, -13.470170329 },
    { -40.265390309, 17.5, -13.0 } };
  const gp_Pnt O(-42.113686949003, 16.786521682838, -13.875355041415);
  const gp_Dir d(0.600105984263, -0.771845896553, 0.210063608523);
  ExpectPatchBesideSquareFound("second basin", c, O, d, 2.4914, 1e-3);
}

/// A valley that Newton creeps along: one bicubic patch of a B-spline fillet of Bastardkb's
/// Charybdis3 case (its 16 control points as the file's), narrow across and flat along towards
/// the centre of a sphere of radius 2.00436 that a chained start gave a sample 1.8 mm away (O and
/// d as the file's sample). The patch's nearest point to the centre lies at u = 0.47 of the patch,
/// 0.0011 inside the sphere (OpenCASCADE). Newton's first step from the 5 x 5 grid's nearest
/// point (u = 0.25) jumped past it to the patch's border, which was nearer; from there each step
/// crept back along the valley by about 0.002 of the patch, nearer each time, until the cap of 8
/// steps, 0.001 outside the sphere. Where Newton stops at its cap still getting nearer, a face
/// without an exact surface now gets the finer grid (`brt_exact_check`: 2t = 4.00872 where the
/// exact thickness is 4.00309).
TEST(SolverExact, ValleyNewtonCreepsAlong)
{
  const double c[16][3] = { { -63.0149116, 29.0152535, 15.3295939 },
    { -62.5760659, 29.765267, 13.5836995 }, { -62.3679132, 30.4540758, 11.7566525 },
    { -62.4186904, 31.0568019, 9.91190235 }, { -63.0598864, 29.5023608, 15.5085208 },
    { -62.6011513, 30.2448507, 13.7531606 }, { -62.3762375, 30.9275512, 11.9122413 },
    { -62.4147304, 31.5252852, 10.0512416 }, { -62.8967162, 29.9863828, 15.7385619 },
    { -62.4240742, 30.7219042, 13.9520896 }, { -62.1894998, 31.3987385, 12.0784895 },
    { -62.2235179, 31.9916232, 10.1844328 }, { -62.5741404, 30.3321945, 15.9546953 },
    { -62.0947069, 31.0686284, 14.1278651 }, { -61.8579063, 31.7462239, 12.21339 },
    { -61.8947014, 32.3397574, 10.2788829 } };
  const gp_Pnt O(-60.9615591135, 32.7412999523, 10.9329380446);
  const gp_Dir d(0.276654717136, -0.918957999238, -0.281030893538);
  ExpectPatchBesideSquareFound("creeping valley", c, O, d, 2.00436, 9e-4);
}

/// A ring that the sphere grazes: one bicubic patch of a bent tube (the cubic arcs of a torus's
/// piece, core radius 2.3, tube radius 0.5 varied along the ring by up to 1e-3), and a sphere
/// centred on the core between the 5 x 5 grid's lines across, so that the grid's nearest point
/// lies on the patch's border, where the tube's radius is largest and falls away concavely
/// along the ring, while the ring dips 4.7e-4 into the sphere (OpenCASCADE) about 0.7 along the
/// patch. Along the ring the distance from the centre is nearly flat (the sphere osculates the
/// tube there) and Gauss-Newton's steps, sized by the metric alone, creep. So it was in a
/// printable part (the Enraged Rabbit Carrot Feeder's smart-watch sensor, a 1 mm filament bore,
/// GPL, not kept): steps of 0.002 of the patch, Newton stopping at its cap 5.3e-4 outside the
/// sphere, short of the finer grid's window, where the bore dipped 6.0e-4 into it; 4 of 300
/// random spheres held its exact faces 3.1e-4 to 5.9e-4 mm deep. Where Newton stops at its cap
/// still getting nearer after a step that found the distance concave, it now goes on from
/// there along the valley's soft direction, each step doubled while the distance falls
/// (`patch_nearest_newton`); without that the certification finds nothing here (checked).
TEST(SolverExact, RingGrazedAlongATube)
{
  const double Rc = 2.3, r0 = 0.5, delta = 1e-3, thetaA = 2.4, thetaB = 1.5, phiA = -0.3,
               phiB = 0.3, phiM = 0.075;
  const double a[4] = { 1.0, 0.8, -1.5, 0.5 }; // the tube's radius along the ring, r0 + delta a
  // The cubic arcs' control points at unit radius: across (theta, in the plane of the core's
  // radius and z) and along the core (phi, in the xy plane).
  const double k = 4.0 / 3.0 * std::tan(std::abs(thetaB - thetaA) / 4.0),
               kp = 4.0 / 3.0 * std::tan((phiB - phiA) / 4.0);
  const double across[4][2] = { { std::cos(thetaA), std::sin(thetaA) },
    { std::cos(thetaA) + k * std::sin(thetaA), std::sin(thetaA) - k * std::cos(thetaA) },
    { std::cos(thetaB) - k * std::sin(thetaB), std::sin(thetaB) + k * std::cos(thetaB) },
    { std::cos(thetaB), std::sin(thetaB) } };
  const double along[4][2] = { { std::cos(phiA), std::sin(phiA) },
    { std::cos(phiA) - kp * std::sin(phiA), std::sin(phiA) + kp * std::cos(phiA) },
    { std::cos(phiB) + kp * std::sin(phiB), std::sin(phiB) - kp * std::cos(phiB) },
    { std::cos(phiB), std::sin(phiB) } };
  double c[16][3];
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
    {
      const double rho = r0 + delta * a[i], radial = Rc + rho * across[i][0];
      c[4 * i + j][0] = radial * along[j][0];
      c[4 * i + j][1] = radial * along[j][1];
      c[4 * i + j][2] = rho * across[i][1];
    }
  // The sphere on the core at phiM, 4e-4 deeper than the ring's least radius (about r0 - 0.28
  // delta), tangent at O on the tube's inner side, where the square stands for O's own face.
  const double t = r0 - 0.28 * delta + 4e-4;
  const gp_Dir d(std::cos(phiM), std::sin(phiM), 0.0);
  const gp_Pnt O((Rc - t) * std::cos(phiM), (Rc - t) * std::sin(phiM), 0.0);
  ExpectPatchBesideSquareFound("ring along a tube", c, O, d, t, 3e-4);
}

/// O's own free-form face curving into the sphere a little away from O: a face z = h(x), straight
/// along y, of degree 6 (so its patches only approximate it), tangent at O = 0 to a sphere of
/// radius 1.3 along d = z; h follows the sphere's lower cap to a tenth of a micrometre and adds a
/// bump that stays below it within 0.03 of O and rises above it to about 3.8e-4 at x = +-0.16
/// (OpenCASCADE's trj4_pm2-ec-214, sample 112490: its B-spline face 730 held 3.68e-4 deep 0.159
/// from O, 2t = 2.618 against the exact 2.488). Within half the radius of O the certification
/// counted a point of O's own face only below twice the tolerance more than another face's
/// (4.5e-4 in all at the default tolerance), which hid it; a face without an exact surface now
/// allows there only its patches' measured deviation and half as much again.
TEST(SolverExact, OwnFreeFormFaceNearO)
{
  const double T = 1.3, s0 = 0.16 * 0.16, D = 4.2e-4, E = 0.1 * D, X = 0.2, W = 0.2;
  // h(x) in powers of x, then in the Bernstein basis of u in [0, 1], x = -X + 2 X u.
  double power[7] = { 0, 0, 1.0 / (2 * T) - E / s0, 0, 1.0 / (8 * T * T * T) + 3 * D / (s0 * s0), 0,
    -2 * D / (s0 * s0 * s0) };
  double inU[7] = { 0, 0, 0, 0, 0, 0, 0 }; // h(x(u)) in powers of u
  for (int i = 0; i <= 6; ++i)
    for (int j = 0; j <= i; ++j) // (-X + 2 X u)^i, the u^j term
    {
      double binom = 1;
      for (int k = 0; k < j; ++k)
        binom = binom * (i - k) / (k + 1);
      inU[j] += power[i] * binom * std::pow(-X, i - j) * std::pow(2 * X, j);
    }
  TColgp_Array2OfPnt poles(1, 7, 1, 2);
  for (int k = 0; k <= 6; ++k)
  {
    double b = 0, ck = 1; // sum over j <= k of C(k, j) / C(6, j) a_j
    for (int j = 0; j <= k; ++j)
    {
      double c6 = 1;
      for (int q = 0; q < j; ++q)
        c6 = c6 * (6 - q) / (q + 1);
      b += ck / c6 * inU[j];
      ck = ck * (k - j) / (j + 1);
    }
    for (int j = 0; j < 2; ++j)
      poles.SetValue(k + 1, j + 1, gp_Pnt(-X + 2 * X * k / 6.0, j ? W : -W, b));
  }
  Handle(Geom_BezierSurface) surface = new Geom_BezierSurface(poles);
  const TopoDS_Face face = BRepBuilderAPI_MakeFace(surface, 1e-7).Face();
  const BRepModel model = ConvertShape(face, ConversionOptions());
  ASSERT_EQ(model.Faces.size(), 1u);
  std::printf("[own free-form face] %d patches, measured %.3g off the face\n",
    model.Faces[0].PatchCount, model.Faces[0].MaxDeviation);
  // The point counts where it lies deeper than the depth and a quarter slack (2.5e-4) and the
  // margin (1.5 times the measured deviation): the bump's 3.8e-4 stands out of that with the
  // patches within half the tolerance, which the conversion's fit aims at.
  ASSERT_GE(model.Faces[0].MaxDeviation, 0.0);
  ASSERT_LT(model.Faces[0].MaxDeviation, 5e-5);
  Sample o;
  o.Face = 0;
  o.Point = { 0.0, 0.0, 0.0 };
  o.Direction = { 0.0, 0.0, 1.0 };
  const SampleResult sphere = SphereAlong(o, T);
  const double depth = T - BoundaryDistance(face, sphere.Center);
  EXPECT_LT(depth, 4.5e-4); // within the margin that hid it
  ExpectCertificationFinds("own free-form face", face, model, o, T, 3.5e-4);
}

/// A blind drilled hole whose 118 degree point ends h above the floor of a block: at a sample O
/// of the floor a distance rho from the hole's axis, the maximal sphere touches the point, the
/// cone face's apex, a degenerated edge (a pole of its trim): t = (rho^2 + h^2) / (2 h). It
/// guards contacts at a pole, where eq. 7 now starts on the edge next to the degenerated segment
/// (the Phillips recesses of Creality's Ender-3 pan-head screws, whose walls close in poles,
/// failed 3 samples each). It does not reproduce that failure: the solver before the change
/// reached this apex by other paths and passes it too; the change was measured on the screws.
TEST(SolverExact, DrillPointAboveTheFloor)
{
  const double r = 3.0, apex = 2.0, tip = r / std::tan(59.0 * M_PI / 180.0);
  const gp_Dir z(0, 0, 1);
  const TopoDS_Shape drill = BRepAlgoAPI_Fuse(
    BRepPrimAPI_MakeCone(gp_Ax2(gp_Pnt(10, 10, apex), z), 0.0, r, tip).Shape(),
    BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(10, 10, apex + tip), z), r, 20.0).Shape())
                               .Shape();
  const TopoDS_Shape part =
    BRepAlgoAPI_Cut(BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 20, 20, 10).Shape(), drill).Shape();
  ConversionOptions conversion;
  conversion.MaxEdgeLength = 0.1; // floor samples near the axis
  const BRepModel model = ConvertShape(part, conversion);
  const SolverData data = PrepareSolver(model, SolverOptions());
  const std::vector<Sample> samples = SamplesFromMesh(model, data);
  std::vector<SampleResult> results;
  SolveReference(model, data, SolverOptions(), samples, results);
  size_t near = 0, failed = 0;
  double worst = 0.0;
  for (size_t i = 0; i < samples.size(); ++i)
  {
    const Sample& o = samples[i];
    const double rho = std::hypot(o.Point[0] - 10.0, o.Point[1] - 10.0);
    if (std::abs(o.Point[2]) > 1e-9 || rho > 0.5)
      continue;
    ++near;
    const SampleResult& res = results[i];
    if (res.Type == ContactType::Failed)
    {
      ++failed;
      continue;
    }
    const double t = (rho * rho + apex * apex) / (2.0 * apex);
    worst = std::max(worst, std::abs(res.Radius - t) / t);
    EXPECT_NEAR(res.Radius, t, 1e-6 * t) << "sample " << i << " at rho " << rho;
  }
  std::printf("[drill point] %zu floor samples within 0.5 of the axis, %zu failed, worst %.3g "
              "relative\n", near, failed, worst);
  EXPECT_GT(near, 20u);
  EXPECT_EQ(failed, 0u);
}

/// Spheres whose exact foot lies on a tangent edge: a wall's face where a round begins (the
/// hinge's 0.4 mm walls, NIST_MBE_PMI_11's 3 mm one). The exact finish moves such a contact onto
/// the face's exact surface: the foot is within the trim's tolerance band of the edge, and the
/// face across it is tangent to the sphere there (docs/Solver.md, item 18, "Tangent edges").
/// Against OpenCASCADE: the centre lies as far from the exact faces other than O's own (which the
/// sphere touches at O) as the radius, to well below the conversion tolerance, and a sphere 1e-4 t
/// larger reaches into them. Before the rule the patches' contact stayed: NIST's spheres 4.4e-6 and
/// 1.9e-6 mm short of its wall, the hinge's 1.5e-4 relative small (tangent to the round beside
/// the wall, not maximal).
TEST(SolverExact, TangentEdgeFootOnTheExactSurface)
{
  struct Case
  {
    const char* File;
    std::vector<Numbered> Samples;
  };
  const std::vector<Case> cases{
    { "NIST_MBE_PMI_11.stp",
      { // Samples of its display mesh of 10,644 vertices.
        { 7171, { 4, 18.902494303016326, 3.1932733351127331, { 23.748683698067154, 17.024012250651374, 1.2813386590842197 }, { 0.42255070690401741, 0.30290135244172922, -0.85422577272281286 } } },
        { 7206, { 4, 25.116522485213622, 3.5480814834585921, { 19.308180242822225, 21.542685209383539, 1.0503255138146115 }, { 0.47649902942161271, 0.53164350365035606, -0.70021700920974139 } } } } },
    { "fw13_hinge_l_assy.stp",
      { // Samples of its display mesh of 36,423 vertices.
        { 14028, { 121, 4.757242079359373, 4.7129707568019992, { -126.3975426640869, 3.5999999703151713, 10.154511217940755 }, { -9.5234545918075275e-05, -0.99999985157585658, 0.0005364500406561726 } } },
        { 13538, { 116, 4.4081762289605191, 4.7129707568020391, { -116.75176953940374, 3.5999999703421994, 5.1043899909992501 }, { 9.3943092443886467e-05, -0.99999985171099859, 0.00053642583501322717 } } } } }
  };
  for (const Case& c : cases)
  {
    const Part part = LoadPart(c.File);
    std::vector<Sample> samples;
    std::vector<size_t> ids;
    const std::vector<SampleResult> res = SolveAt(part, c.Samples, samples, ids);
    for (size_t k = 0; k < samples.size(); ++k)
    {
      ASSERT_EQ(res[k].Type, ContactType::SurfaceSurface) << c.File << " " << ids[k];
      BRep_Builder b;
      TopoDS_Compound others;
      b.MakeCompound(others);
      for (size_t f = 0; f < part.FaceList.size(); ++f)
        if (static_cast<int>(f) != samples[k].Face)
          b.Add(others, part.FaceList[f]);
      const double off = BoundaryDistance(others, res[k].Center) - res[k].Radius;
      std::printf("[tangent edge] %s sample %zu: 2t = %.9g, centre %.3g from the faces across "
                  "beyond the radius\n", c.File, ids[k], res[k].Thickness, off);
      // OpenCASCADE's distance is good to about Precision::Confusion (1e-7).
      EXPECT_LE(std::fabs(off), 1e-6) << c.File << " " << ids[k];
      // And maximal: 1e-4 t larger, the sphere tangent at O reaches into the wall across.
      const double grown = 1.0001 * res[k].Radius;
      const Sample& o = samples[k];
      const std::array<double, 3> M{ o.Point[0] + grown * o.Direction[0],
        o.Point[1] + grown * o.Direction[1], o.Point[2] + grown * o.Direction[2] };
      EXPECT_LT(BoundaryDistance(others, M) - grown, -1e-6) << c.File << " " << ids[k];
    }
  }
}

/// Three samples of the unseen cover whose spheres only the shrinking ball settles (no Newton
/// or descent shrinks them), each where the surface meets the sphere at a grazing angle near O.
/// The ball stops where nothing lies deeper than the certification's depth, which left those
/// spheres 18-55% larger than the tangent one (2t = 0.02597, 0.00308 and 0.00295 against
/// OpenCASCADE's 0.01674, 0.00260 and 0.00247); the settled sphere is now polished by its
/// contact's own Newton (docs/Solver.md, item 14, "The settled sphere made tangent"). Against
/// OpenCASCADE as brt_exact_check measures it: within 1e-3 relative, and empty within the
/// allowance.
TEST(SolverExact, SettledSphereMadeTangent)
{
  const Part cover = LoadPart("unseen/FRAMEWORK_DESKTOP_TOP_COVER_V0.stp");
  // Samples of the cover's display mesh of 67,208 vertices.
  const std::vector<Numbered> numbered{
    { 11048, { 8, 1.029462478462787, 0.99999657490955374, { -2.8003418964792042, 96.800000962171183, 200.09999031420244 }, { 0.0029205360283572498, -0.98817531898457911, -0.15330038949406594 } } },
    { 56775, { 487, 0.82825168685747219, 0.0056755526939071075, { -0.56516927496116598, 94.901113131671892, 0.069265517093226897 }, { -0.28117641197343657, 0.00090536266631182217, 0.9596556703673389 } } },
    { 59415, { 490, 0.82791068990983629, 0.00017082216476714491, { -0.56473647452575537, 0.069394922499504408, 1.4989206886684336 }, { -0.28150416407102691, 0.95955929902742876, 0.0011650153055306712 } } }
  };
  ExpectExactSpheres("settled", cover, numbered);
}

/// A wall between a free-form face and its offset, 14 mm apart: a cubic B-spline fitted to
/// z = sin(x / 5) cos(y / 7) + 0.002 x y over 40 x 40 mm, made a solid by OpenCASCADE's thick
/// solid (its far face an offset surface). Both faces are interpolated by the reader, their
/// patches joined with C0 continuity, so t has a kink along every join; the descents whose
/// minimum lay on one crept there up to their cap of 4 x MaxIterations steps (docs/Solver.md,
/// item 9, "At a patch join"; AnalysisSitus's storage part ran 25% slower so). Away from the
/// side faces every sphere spans the wall: 2t = 14 exactly (the offset's distance), within twice
/// the faces' deviation. With 6a61fdb's descent a sample took 463 steps, with the first kink test
/// (a full step shorter than the slack) 229; since, 89 at most.
TEST(SolverReference, DescentEndsAtAPatchJoin)
{
  const int n = 25;
  const double H = 14.0;
  TColgp_Array2OfPnt points(1, n, 1, n);
  for (int i = 1; i <= n; ++i)
    for (int j = 1; j <= n; ++j)
    {
      const double x = 40.0 * (i - 1) / (n - 1), y = 40.0 * (j - 1) / (n - 1);
      points.SetValue(i, j, gp_Pnt(x, y, std::sin(x / 5.0) * std::cos(y / 7.0) + 0.002 * x * y));
    }
  const GeomAPI_PointsToBSplineSurface fit(points, 3, 3, GeomAbs_C2, 1e-6);
  const TopoDS_Face face = BRepBuilderAPI_MakeFace(fit.Surface(), 1e-7).Face();
  BRepOffsetAPI_MakeThickSolid thick;
  thick.MakeThickSolidBySimple(face, H);
  ASSERT_TRUE(thick.IsDone());
  const SolverOptions options;
  const test::Solved s = test::SolveShape(thick.Shape(), ConversionOptions().Tolerance, options);
  const std::vector<double> rim = test::RimDistances(s.Model, s.Samples);
  int most = 0, failed = 0, inner = 0;
  double worst = 0.0;
  for (size_t i = 0; i < s.Results.size(); ++i)
  {
    const SampleResult& r = s.Results[i];
    most = std::max(most, r.Iterations);
    failed += r.Type == ContactType::Failed;
    if (rim[i] > 0.6 * H)
    {
      ++inner;
      worst = std::max(worst, std::fabs(r.Thickness - H) / H);
    }
  }
  // Neither face has an exact surface to finish on: 2t is as good as the two faces' patches.
  double deviation = 0.0;
  for (const Face& F : s.Model.Faces)
    deviation = std::max(deviation, F.MaxDeviation);
  std::printf("[patch joins] %zu samples, %zu patches (deviation %.3g), most steps %d, %d failed; "
              "%d samples 0.6 H or more from the sides, worst 2t %.3g off H\n",
    s.Samples.size(), s.Model.Patches.size(), deviation, most, failed, inner, worst * H);
  EXPECT_EQ(failed, 0);
  EXPECT_LT(most, 4 * options.MaxIterations);
  EXPECT_GT(inner, 300);
  EXPECT_LE(worst * H, 2.0 * deviation);
}
