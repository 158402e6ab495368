// brt_exact_check: how many maximal spheres hold boundary of their own solid, measured against
// OpenCASCADE's exact distance (a program that prints figures, not a test).
//
//   brt_exact_check [--samples N] [--seed S] [--device native|any|cpu|gpu|NAME] [--double]
//                   [--list K] [--thickness M] [--gap [--all-solids]] FILE.step ...
//
// For each file: N samples drawn at random from the display-mesh vertices (default 2,500), solved
// with the native CPU device (the reference) or an OpenCL device (float, with the host's polish, unless --double);
// for each solved sample the distance from its sphere's centre to the exact faces of the
// sample's own solid (BRepExtrema, and where it misses a nearer point, the nearest of every
// extremum on the faces and edges near the centre: GeomAPI_ProjectPointOnSurf and
// GeomAPI_ProjectPointOnCurve, kept where the face's classifier puts the point on the face).
// --indices I,J,... checks those samples (every mesh vertex
// numbered as brt_thickness_bench --counts 0 numbers them) instead. Every sample of the mesh is
// solved, as the filter solves them (a sample's chain, SolverOptions::Chain, is its neighbours
// in SpatialOrder), and the drawn ones are checked; --solve-drawn solves the drawn ones alone
// (chains of samples far apart: each starts from a distant one's contact, a test of the
// certification), --chain N sets the chains' length. A sphere overlaps when its radius exceeds
// that distance by more than the clearance plus the conversion tolerance and by more than 1e-4 t. Prints the
// solved, failed (per reason; the results checked as the filter checks them, brt::CheckResults:
// a sample on an open shell or a non-manifold solid is failed, not measured) and overlapping
// shares, the largest overlap and the K worst samples. With --thickness M, the first M solved samples also get an independent exact
// thickness by the solver's definition: the largest sphere tangent at O that no point of the
// exact faces enters deeper than the clearance, by bisection on t with the same two distances
// from the centre to the solid's faces (Testing/Core/TestSolverRims.cxx uses BRepExtrema), reported as
// eq. 1's radius through the exact foot point; printed: the share of them within 1e-4 relative
// of ours, how many of the others are edge zones (brt::IsEdgeZone: the map's class a user does
// not read as thin), and the largest differences. With --indices, a failed sample gets its exact thickness
// too (what it should have been). With --gap the same for the exterior gap (the sphere from
// the outward normal, in the air; --all-solids: bounded by every solid's faces): the overlap is
// measured against the faces that bound it, --thickness M checks M gaps by the same bisection,
// and every sample the solver finds facing nothing (an infinite gap) is checked: its exact
// sphere must stay empty up to a radius of the model's bounding-box diagonal. With --ray the ray
// thickness instead (NativeSolver::RayThickness, the filter's Method Ray) against OpenCASCADE's
// first intersection of the same ray with the exact faces of the sample's solid
// (IntCurvesFace_ShapeIntersector) beyond twice the patches' accuracy, as ours counts.
#include "BRepConverter.h"
#include "NativeSolver.h"
#include "ExactDistance.h"
#include "ResultCheck.h"
#include "Solver.h"
#include "Statistics.h"
#ifdef BRT_HAVE_OPENCL
#include "OpenCLSolver.h"
#endif

#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepClass3d_SolidClassifier.hxx>
#include <BRepClass_FaceClassifier.hxx>
#include <BRepTopAdaptor_FClass2d.hxx>
#include <gp_Pnt2d.hxx>
#include <IntCurvesFace_ShapeIntersector.hxx>
#include <gp_Lin.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Solid.hxx>
#include <BRepBndLib.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRep_Tool.hxx>
#include <GeomLProp_SLProps.hxx>
#include <Geom_Surface.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <Bnd_Box.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Vertex.hxx>
#include <BRep_Builder.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Face.hxx>
#include <gp_Pnt.hxx>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace
{
const char* const Usage =
  "usage: brt_exact_check [--samples N] [--seed S] [--device native|any|cpu|gpu|NAME] "
  "[--double] [--no-certify] [--list K] [--thickness M] [--gap [--all-solids]] [--ray] [--indices I,J,...]\n"
  "       [--grid N] [--delaunay] [--chain N] [--solve-drawn]\n"
  "       FILE.step ...\n"
  "Solves every sample of each file (native CPU device by default) and measures N random ones\n"
  "(default 2500) against OpenCASCADE's exact distance from its centre to the faces of the\n"
  "sample's own solid (BRepExtrema, and every extremum on the faces and edges near the centre\n"
  "where that is nearer, and with --grid N the nearest point on the face of an N x N grid over\n"
  "each such face's parameters, refined three times around its nearest cell and its other local\n"
  "minima: a third opinion, slow, off by default).\n"
  "Prints solved, failed (per reason, flagged as the filter flags them: samples on open shells\n"
  "and non-manifold solids fail; also over every sample of the part, with the first few that\n"
  "the checks after the solve flag) and overlapping shares (overlap beyond the clearance plus\n"
  "the conversion tolerance and 1e-4 t), the largest overlap and the K worst samples (--list),\n"
  "and the solved samples whose sphere's centre lies outside their solid (OpenCASCADE's\n"
  "classifier, confirmed by most of seven rays from it): a sphere in the air touches the\n"
  "boundary from outside, which no distance sees (and how many of them lie beyond the file's\n"
  "own tolerance at the centre); and the samples whose O lies off its own face\n"
  "by more than the tolerance (OpenCASCADE's face classifier and distance, confirmed by its 2D\n"
  "classifier).\n"
  "--thickness M: the first M solved samples against an exact thickness (bisection on t with\n"
  "OpenCASCADE's distance), the share within 1e-4 relative, how many of the others lie in edge\n"
  "zones (a corner bounds the sphere: the map's class left out of the thin share by default),\n"
  "and the largest differences.\n"
  "--gap: the exterior gap instead (--all-solids: every solid's walls bound it); samples with an\n"
  "infinite gap are checked to face nothing up to a radius of the bounding-box diagonal.\n"
  "--indices I,J,...: those samples (indices into every mesh vertex, as brt_thickness_bench\n"
  "--counts 0 numbers them) instead of a random draw; with --thickness, each failed one also\n"
  "gets its exact thickness.\n"
  "--delaunay: the display mesh (whose vertices are the samples) refined with Delaunay flips\n"
  "(the reader's DelaunayRefinement).\n"
  "--chain N: SolverOptions::Chain (default 0: the device's, 32 on a CPU; 1: every sample started\n"
  "  from s1).\n"
  "--solve-drawn: solve the drawn samples alone, not the whole mesh: each chain's samples lie far\n"
  "apart, and each starts from a distant one's contact (a test of the certification).\n"
  "--ray: the ray thickness (the filter's Method Ray, native device) of the drawn samples against\n"
  "OpenCASCADE's first intersection of the same ray with the exact faces of the sample's solid\n"
  "(IntCurvesFace_ShapeIntersector) beyond twice the patches' accuracy: the share within 1e-4\n"
  "relative, misses on either side, and the K largest differences (--list).\n";
}

int main(int argc, char** argv)
{
  size_t count = 2500;
  unsigned seed = 1;
  bool gap = false, allSolids = false, ray = false;
  int list = 5;
  int grid = 0;
  size_t exactCount = 0;
  std::string device = "native";
  [[maybe_unused]] bool useDouble = false;
  bool certify = true, solveDrawn = false;
  int chain = brt::SolverOptions().Chain;
  brt::ConversionOptions conversion;
  std::vector<size_t> indices;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h")
    {
      std::fputs(Usage, stdout);
      return 0;
    }
    if (a == "--samples" && i + 1 < argc)
      count = std::strtoul(argv[++i], nullptr, 10);
    else if (a == "--indices" && i + 1 < argc)
    {
      for (const char* c = argv[++i]; *c;)
      {
        char* end = nullptr;
        indices.push_back(std::strtoul(c, &end, 10));
        c = *end == ',' ? end + 1 : end;
        if (end == c && *c)
          break;
      }
    }
    else if (a == "--seed" && i + 1 < argc)
      seed = static_cast<unsigned>(std::strtoul(argv[++i], nullptr, 10));
    else if (a == "--device" && i + 1 < argc)
      device = argv[++i];
    else if (a == "--double")
      useDouble = true;
    else if (a == "--no-certify")
      certify = false;
    else if (a == "--solve-drawn")
      solveDrawn = true;
    else if (a == "--chain" && i + 1 < argc)
      chain = std::atoi(argv[++i]);
    else if (a == "--delaunay")
      conversion.DelaunayRefinement = true;
    else if (a == "--list" && i + 1 < argc)
      list = std::atoi(argv[++i]);
    else if (a == "--grid" && i + 1 < argc)
      grid = std::atoi(argv[++i]);
    else if (a == "--thickness" && i + 1 < argc)
      exactCount = std::strtoul(argv[++i], nullptr, 10);
    else if (a == "--gap")
      gap = true;
    else if (a == "--ray")
      ray = true;
    else if (a == "--all-solids")
      allSolids = true;
    else if (a.compare(0, 2, "--") == 0)
    {
      std::fprintf(stderr, "error: unknown option %s\n%s", a.c_str(), Usage);
      return 2;
    }
    else
      files.push_back(a);
  }
  if (files.empty())
  {
    std::fputs(Usage, stderr);
    return 2;
  }
  if (!ray)
    std::printf("%-34s %7s %8s %8s %9s %10s %9s  %s\n", "model", "samples", "solved", "failed",
      "overlap", "overlap_%", "largest", "failed by reason");
  int status = 0;
  for (const std::string& file : files)
  {
    const char* slash = std::strrchr(file.c_str(), '/');
    const std::string name = slash ? slash + 1 : file;
    brt::BRepModel m;
    std::vector<TopoDS_Face> faces;
    try
    {
      m = brt::ConvertStepFile(file, conversion, &faces);
    }
    catch (const std::exception& e)
    {
      std::fprintf(stderr, "error: %s\n", e.what());
      status = 1;
      continue;
    }
    int solids = 0;
    for (const brt::Face& f : m.Faces)
      solids = std::max(solids, f.Solid + 1);
    std::vector<TopoDS_Compound> bySolid(static_cast<size_t>(solids) + 1);
    BRep_Builder b;
    for (auto& c : bySolid)
      b.MakeCompound(c);
    TopoDS_Compound allFaces;
    b.MakeCompound(allFaces);
    for (size_t f = 0; f < faces.size(); ++f)
    {
      b.Add(bySolid[static_cast<size_t>(m.Faces[f].Solid + 1)], faces[f]);
      b.Add(allFaces, faces[f]);
    }
    // A second distance, apart from BRepExtrema_DistShapeShape (which can miss the nearest
    // point of a face: docs/Solver.md, item 14), over the faces that bound the sample's sphere.
    const std::vector<Bnd_Box> faceBox = brt::exact::FaceBoxes(faces);
    auto secondDistance = [&](const brt::Sample& s, const gp_Pnt& X, double reach, gp_Pnt& at,
                            int& atFace) {
      const int solid = m.Faces[static_cast<size_t>(s.Face)].Solid;
      return brt::exact::ExtremaDistance(faces, faceBox, X, reach,
        [&](size_t f) { return (gap && allSolids) || m.Faces[f].Solid == solid; }, &at, &atFace,
        grid);
    };
    // The faces that bound a sample's sphere: its solid's, or every solid's (--gap --all-solids).
    auto bounding = [&](const brt::Sample& s) -> const TopoDS_Shape& {
      if (gap && allSolids)
        return allFaces;
      return bySolid[static_cast<size_t>(m.Faces[s.Face].Solid + 1)];
    };

    brt::SolverOptions options;
    options.Certify = certify;
    options.Exterior = gap;
    options.AllSolids = gap && allSolids;
    options.Chain = chain;
    const brt::SolverData data = brt::PrepareSolver(m, options);
    std::vector<brt::Sample> all = brt::SamplesFromMesh(m, data);
    if (gap)
      for (brt::Sample& s : all)
        brt::ReverseSample(s); // the outward normal
    std::mt19937 rng(seed);
    std::vector<size_t> pick(all.size());
    for (size_t i = 0; i < pick.size(); ++i)
      pick[i] = i;
    std::shuffle(pick.begin(), pick.end(), rng);
    pick.resize(std::min(count, pick.size()));
    if (!indices.empty())
    {
      pick.clear();
      for (size_t i : indices)
        if (i < all.size())
          pick.push_back(i);
    }
    std::sort(pick.begin(), pick.end());
    std::vector<brt::Sample> samples;
    for (size_t i : pick)
      samples.push_back(all[i]);
    if (ray)
    {
      // Ours: the drawn samples' rays (a ray depends on its sample alone).
      brt::NativeSolver native(m, data);
      std::vector<double> ours;
      native.RayThickness(samples, ours);
      // As ours counts: beyond twice the patches' accuracy (2 slack, 4 tolerances) from O.
      const double sMin = 4.0 * m.Tolerance;
      std::vector<std::unique_ptr<IntCurvesFace_ShapeIntersector>> rays(
        static_cast<size_t>(solids) + 1);
      std::map<brt::exact::RayAgreement, size_t> tally;
      double largestRel = 0.0;
      std::vector<std::pair<double, size_t>> worstRay;
      std::vector<double> exactRay(samples.size(), std::numeric_limits<double>::quiet_NaN());
      std::vector<brt::exact::RayAgreement> kind(samples.size());
      for (size_t k = 0; k < samples.size(); ++k)
      {
        const brt::Sample& sm = samples[k];
        std::unique_ptr<IntCurvesFace_ShapeIntersector>& in =
          rays[static_cast<size_t>(m.Faces[static_cast<size_t>(sm.Face)].Solid + 1)];
        if (!in)
        {
          in = std::make_unique<IntCurvesFace_ShapeIntersector>();
          in->Load(bounding(sm), m.Tolerance);
        }
        const gp_Pnt O(sm.Point[0], sm.Point[1], sm.Point[2]);
        const gp_Dir d(sm.Direction[0], sm.Direction[1], sm.Direction[2]);
        kind[k] =
          brt::exact::CompareRay(ours[k], *in, bounding(sm), O, d, sMin, m.Tolerance, &exactRay[k]);
        ++tally[kind[k]];
        const bool both = std::isfinite(ours[k]) && std::isfinite(exactRay[k]);
        const double rel = both ? std::fabs(ours[k] - exactRay[k]) / exactRay[k]
                                : std::numeric_limits<double>::infinity();
        if (both)
          largestRel = std::max(largestRel, rel);
        if (kind[k] != brt::exact::RayAgreement::Within && kind[k] != brt::exact::RayAgreement::Neither &&
          kind[k] != brt::exact::RayAgreement::ExactFailed)
          worstRay.emplace_back(rel, k);
      }
      using A = brt::exact::RayAgreement;
      const size_t bothHit = tally[A::Within] + tally[A::Glancing] + tally[A::Grazing] +
        tally[A::ExactOff] + tally[A::ExactTouch] + tally[A::Other];
      std::printf("%-34s %7zu rays: %zu hit on both, %zu within 1e-4 relative (%.2f%%), largest %.3g; "
                  "of the others, the same hit within twice the tolerance across the face "
                  "(glancing) %zu, ours nearer at a face within twice the tolerance (grazing) %zu, "
                  "OpenCASCADE's point off the faces %zu, OpenCASCADE's nearer hit a touch (tangent, "
                  "or on a face's boundary) %zu, other %zu; ours alone %zu, OpenCASCADE's alone %zu, "
                  "neither %zu; OpenCASCADE's intersector failed on %zu\n",
        name.c_str(), samples.size(), bothHit, tally[A::Within],
        bothHit ? 100.0 * tally[A::Within] / bothHit : 0.0, largestRel, tally[A::Glancing],
        tally[A::Grazing], tally[A::ExactOff], tally[A::ExactTouch], tally[A::Other],
        tally[A::OursAlone], tally[A::ExactAlone], tally[A::Neither], tally[A::ExactFailed]);
      std::sort(worstRay.begin(), worstRay.end(), std::greater<>());
      for (int i = 0; i < list && i < static_cast<int>(worstRay.size()); ++i)
      {
        const size_t k = worstRay[static_cast<size_t>(i)].second;
        const brt::Sample& sm = samples[k];
        std::printf("    sample %zu (face %d): ours %.9g, OpenCASCADE %.9g: %s\n", pick[k], sm.Face,
          ours[k], exactRay[k], brt::exact::RayAgreementName(kind[k]));
        // OpenCASCADE's hits along the ray up to ours (or all where ours met nothing): the
        // face, whether the ray crosses there or touches (tangent; on the face's boundary), and
        // the cosine between the ray and the face's normal.
        IntCurvesFace_ShapeIntersector& in =
          *rays[static_cast<size_t>(m.Faces[static_cast<size_t>(sm.Face)].Solid + 1)];
        try
        {
          in.Perform(gp_Lin(gp_Pnt(sm.Point[0], sm.Point[1], sm.Point[2]),
                       gp_Dir(sm.Direction[0], sm.Direction[1], sm.Direction[2])),
            sMin, RealLast());
        }
        catch (const Standard_Failure&)
        {
          continue;
        }
        for (int j = 1; in.IsDone() && j <= in.NbPnt(); ++j)
        {
          if (std::isfinite(ours[k]) && in.WParameter(j) > ours[k] * (1.0 + 1e-4))
            continue;
          int hitFace = -1;
          for (size_t g = 0; g < faces.size(); ++g)
            if (faces[g].IsSame(in.Face(j)))
              hitFace = static_cast<int>(g);
          BRepAdaptor_Surface S(in.Face(j));
          gp_Pnt P;
          gp_Vec Du, Dv;
          S.D1(in.UParameter(j), in.VParameter(j), P, Du, Dv);
          const gp_Vec n = Du.Crossed(Dv);
          const double cosine = n.Magnitude() > 0.0
            ? n.Normalized().Dot(gp_Vec(sm.Direction[0], sm.Direction[1], sm.Direction[2]))
            : 0.0;
          std::printf("      OpenCASCADE's hit at %.9g on face %d: %s%s, cos %.2g\n", in.WParameter(j),
            hitFace,
            in.Transition(j) == IntCurveSurface_Tangent ? "tangent"
                                                          : (in.Transition(j) == IntCurveSurface_In ? "in" : "out"),
            in.State(j) == TopAbs_ON ? " on the face's boundary" : "", cosine);
        }
      }
      continue;
    }
    // Every sample, as the filter solves them, unless --solve-drawn.
    const std::vector<brt::Sample>& toSolve = solveDrawn ? samples : all;
    std::vector<brt::SampleResult> res(toSolve.size());
    if (device == "native" || device == "reference")
      brt::SolveReference(m, data, options, toSolve, res);
    else
    {
#ifdef BRT_HAVE_OPENCL
      try
      {
        brt::OpenCLSolver cl(device, useDouble);
        cl.Upload(m, data);
        cl.Solve(m, data, options, toSolve, res);
      }
      catch (const brt::OpenCLError& e)
      {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 2;
      }
#else
      std::fprintf(stderr, "error: built without OpenCL\n");
      return 2;
#endif
    }
    // Every sample flagged as the filter flags it: the failed share a user sees over the part.
    std::string everyLine;
    if (!solveDrawn)
    {
      std::vector<brt::SampleResult> every = res;
      brt::CheckResults(m, all, every);
      std::map<std::string, size_t> why;
      size_t failedAll = 0;
      std::string newly; // flagged here, solved by the solver: the first few, with their 2t
      int shown = 0;
      for (size_t i = 0; i < every.size(); ++i)
      {
        const brt::SampleResult& r = every[i];
        if (r.Type != brt::ContactType::Failed)
          continue;
        ++failedAll;
        ++why[brt::FailReasonName(r.Reason)];
        if (res[i].Type != brt::ContactType::Failed && shown++ < 6)
          newly += (newly.empty() ? "" : ", ") + std::to_string(i) + " (2t " +
            std::to_string(res[i].Thickness) + ")";
      }
      everyLine = "    every sample, flagged as the filter flags them: " + std::to_string(failedAll) +
        " of " + std::to_string(every.size()) + " failed";
      for (const auto& w : why)
        everyLine += "; " + w.first + " " + std::to_string(w.second);
      if (!newly.empty())
        everyLine += "; flagged after the solve, first: " + newly;
      everyLine += "\n";
    }
    if (!solveDrawn)
    {
      std::vector<brt::SampleResult> drawn;
      for (size_t i : pick)
        drawn.push_back(res[i]);
      res = std::move(drawn);
    }
    // As the filter does: samples on open shells or non-manifold solids, and impossible values,
    // are flagged failed, so that the figures are those a user sees (in the gap, a sphere beyond
    // its solid's box is an open gap: checked below with the infinite ones).
    brt::CheckResults(m, samples, res);
    const double allowed = 3.0 * m.Tolerance; // the clearance (2x) and the patches (1x)
    size_t solved = 0, overlapping = 0, secondNearer = 0, secondOnly = 0;
    // A solid rebuilt from its faces (one shell), for OpenCASCADE's classifier.
    auto solidOf = [&](int solid) {
      TopoDS_Shell shell;
      b.MakeShell(shell);
      for (size_t f = 0; f < faces.size(); ++f)
        if (m.Faces[f].Solid == solid)
          b.Add(shell, faces[f]);
      TopoDS_Solid out;
      b.MakeSolid(out);
      b.Add(out, shell);
      return out;
    };
    // A sphere of the thickness lies in the material: its centre inside the sample's solid (by
    // OpenCASCADE's classifier on that solid rebuilt from its faces). The distance above cannot
    // tell a sphere in the air that touches the boundary from outside (one that passed through a
    // wall thinner than the solver resolves) from a sphere inside.
    std::vector<TopoDS_Solid> ownSolid(static_cast<size_t>(solids));
    std::vector<std::unique_ptr<BRepClass3d_SolidClassifier>> ownClassifier(
      static_cast<size_t>(solids)); // loaded once per solid
    std::vector<std::unique_ptr<IntCurvesFace_ShapeIntersector>> ownRays(
      static_cast<size_t>(solids));
    std::vector<size_t> outside;
    size_t classifierAlone = 0; // centres the classifier alone calls outside (the rays: inside)
    auto centreOutside = [&](const brt::Sample& s, const brt::SampleResult& r) {
      const int solid = m.Faces[static_cast<size_t>(s.Face)].Solid;
      // A sphere no larger than twice the allowance lies within it of the boundary: its centre
      // may lie on either side as far as the classifier (at the tolerance) can tell.
      if (gap || solid < 0 || r.Radius <= 2.0 * allowed)
        return false;
      std::unique_ptr<BRepClass3d_SolidClassifier>& cl = ownClassifier[static_cast<size_t>(solid)];
      if (!cl)
      {
        ownSolid[static_cast<size_t>(solid)] = solidOf(solid);
        cl = std::make_unique<BRepClass3d_SolidClassifier>(ownSolid[static_cast<size_t>(solid)]);
      }
      const gp_Pnt C(r.Center[0], r.Center[1], r.Center[2]);
      cl->Perform(C, m.Tolerance);
      // (ON: within the tolerance of the boundary, where the distance above decides.)
      if (cl->State() != TopAbs_OUT)
        return false;
      // A second opinion: the classifier's ray can graze an edge and call a region OUT amid
      // points it calls IN (on the Original Prusa i3's fan shroud and adapter, three centres
      // whose diameters it called IN from 1e-3 r to 1.99 r from O, a ball of 0.03-0.1 r around
      // them OUT, and no boundary within the sphere). Seven rays from the centre in fixed
      // directions, their crossings of the solid's faces counted: the centre is outside where
      // most cross an even number of times.
      std::unique_ptr<IntCurvesFace_ShapeIntersector>& rays = ownRays[static_cast<size_t>(solid)];
      if (!rays)
      {
        rays = std::make_unique<IntCurvesFace_ShapeIntersector>();
        rays->Load(ownSolid[static_cast<size_t>(solid)], m.Tolerance);
      }
      static const double directions[7][3] = { { 0.5377, 0.6143, 0.5773 },
        { -0.7071, 0.2013, 0.6778 }, { 0.1093, -0.9641, 0.2421 }, { -0.3312, -0.4119, -0.8488 },
        { 0.8867, -0.1732, -0.4287 }, { -0.2488, 0.9134, -0.3221 }, { 0.6519, 0.3047, -0.6944 } };
      int evenVotes = 0;
      for (const auto& u : directions)
      {
        // (OpenCASCADE's intersector throws on some damaged faces, Standard_NullObject on a
        // SolidWorks export with its vertices 0.4 mm off its edges: that ray casts no vote.)
        try
        {
          rays->Perform(gp_Lin(C, gp_Dir(u[0], u[1], u[2])), 0.0, RealLast());
        }
        catch (const Standard_Failure&)
        {
          continue;
        }
        std::vector<double> at;
        for (int i = 1; rays->IsDone() && i <= rays->NbPnt(); ++i)
          at.push_back(rays->WParameter(i));
        std::sort(at.begin(), at.end());
        // A crossing at an edge is found on both of its faces: once.
        const size_t crossings = static_cast<size_t>(std::distance(at.begin(),
          std::unique(at.begin(), at.end(),
            [&](double x, double y) { return y - x <= m.Tolerance; })));
        evenVotes += crossings % 2 == 0 ? 1 : 0;
      }
      if (evenVotes >= 4)
        return true;
      ++classifierAlone;
      return false;
    };
    double largest = 0.0;
    std::map<std::string, size_t> reasons;
    std::vector<std::pair<double, size_t>> worst;
    std::vector<double> deepestFromO(samples.size(), 0.0); // |P - O| of the deepest point
    std::vector<int> deepestFace(samples.size(), -1);      // the face it lies on (-1: an edge or vertex)
    std::vector<gp_Pnt> deepestAt(samples.size());          // the deepest point itself
    for (size_t k = 0; k < samples.size(); ++k)
    {
      const brt::SampleResult& r = res[k];
      if (r.Type == brt::ContactType::Failed)
      {
        ++reasons[brt::FailReasonName(r.Reason)];
        continue;
      }
      ++solved;
      const TopoDS_Shape& own = bounding(samples[k]);
      // BRepExtrema's distance, its in-face points checked by the face classifiers
      // (CheckedDistance).
      const gp_Pnt centre(r.Center[0], r.Center[1], r.Center[2]);
      gp_Pnt firstAt;
      TopoDS_Face firstFace;
      const double first = brt::exact::CheckedDistance(own, centre, grid, &firstAt, &firstFace);
      if (first < 0.0)
        continue;
      double overlap = r.Radius - first;
      // The second distance, where it finds a point nearer than BRepExtrema's.
      gp_Pnt secondAt;
      int secondFace = -1;
      const double second = secondDistance(samples[k], centre, r.Radius, secondAt, secondFace);
      const gp_Pnt O(samples[k].Point[0], samples[k].Point[1], samples[k].Point[2]);
      if (second < first - 1e-9 * (1.0 + r.Radius))
      {
        ++secondNearer;
        if (r.Radius - second > allowed && r.Radius - second > 1e-4 * r.Radius &&
          !(overlap > allowed && overlap > 1e-4 * r.Radius))
          ++secondOnly;
        overlap = r.Radius - second;
        deepestFromO[k] = secondAt.Distance(O);
        deepestFace[k] = secondFace;
        deepestAt[k] = secondAt;
      }
      else
      {
        deepestFromO[k] = firstAt.Distance(O);
        deepestAt[k] = firstAt;
        if (!firstFace.IsNull())
          for (size_t f = 0; f < faces.size(); ++f)
            if (faces[f].IsSame(firstFace))
              deepestFace[k] = static_cast<int>(f);
      }
      if (overlap > allowed && overlap > 1e-4 * r.Radius)
      {
        ++overlapping;
        worst.emplace_back(overlap, k);
      }
      largest = std::max(largest, overlap);
      if (centreOutside(samples[k], r))
        outside.push_back(k);
    }
    char otherSolidLine[400] = "";
    if (gap && allSolids)
    {
      // Samples on or in another solid (gap 0): the point 5 tolerances out along the outward
      // normal must be inside (or on) another solid, by OpenCASCADE's classifier on that solid
      // rebuilt from its faces.
      std::vector<TopoDS_Solid> solidShapes(static_cast<size_t>(solids));
      for (int sIdx = 0; sIdx < solids; ++sIdx)
        solidShapes[static_cast<size_t>(sIdx)] = solidOf(sIdx);
      size_t onOther = 0, confirmed = 0, centresInside = 0, finite = 0;
      for (size_t k = 0; k < samples.size(); ++k)
      {
        if (res[k].Type != brt::ContactType::OtherSolid)
        {
          // A finite gap's centre lies in the air: outside every solid (one inside another solid,
          // an interference that put no face in the sphere, would be a wrong gap).
          if (res[k].Type == brt::ContactType::Failed)
            continue;
          ++finite;
          const gp_Pnt c(res[k].Center[0], res[k].Center[1], res[k].Center[2]);
          bool in = false;
          for (int sIdx = 0; sIdx < solids && !in; ++sIdx)
          {
            BRepClass3d_SolidClassifier cl(solidShapes[static_cast<size_t>(sIdx)], c, m.Tolerance);
            in = cl.State() == TopAbs_IN;
          }
          centresInside += in;
          continue;
        }
        ++onOther;
        const double e = 5.0 * m.Tolerance;
        const gp_Pnt q(samples[k].Point[0] + e * samples[k].Direction[0],
          samples[k].Point[1] + e * samples[k].Direction[1],
          samples[k].Point[2] + e * samples[k].Direction[2]);
        const int own = m.Faces[samples[k].Face].Solid;
        bool in = false;
        for (int sIdx = 0; sIdx < solids && !in; ++sIdx)
        {
          if (sIdx == own)
            continue;
          BRepClass3d_SolidClassifier c(solidShapes[static_cast<size_t>(sIdx)], q, m.Tolerance);
          in = c.State() == TopAbs_IN || c.State() == TopAbs_ON;
        }
        confirmed += in;
      }
      std::snprintf(otherSolidLine, sizeof(otherSolidLine),
        "    on or in another solid (gap 0): %zu samples, %zu confirmed inside another solid by "
        "OpenCASCADE's classifier; finite gaps whose centre lies inside a solid: %zu of %zu\n",
        onOther, confirmed, centresInside, finite);
    }
    const size_t failed = samples.size() - solved;
    std::string why;
    for (const auto& r : reasons)
      why += (why.empty() ? "" : "; ") + r.first + " " + std::to_string(r.second);
    std::printf("%-34s %7zu %8zu %8zu %9zu %9.2f%% %9.3g  %s\n", name.c_str(), samples.size(),
      solved, failed, overlapping, 100.0 * overlapping / std::max<size_t>(solved, 1), largest,
      why.c_str());
    std::fputs(everyLine.c_str(), stdout);
    std::fputs(otherSolidLine, stdout);
    std::printf("    second distance (every extremum on the faces and edges near the centre%s): "
                "nearer than BRepExtrema's on %zu solved samples; overlaps it alone finds: %zu "
                "(counted above)\n", grid > 0 ? ", and a grid over each face" : "", secondNearer,
      secondOnly);
    // The file's own tolerance at a point: the largest tolerance of a face, edge or vertex of
    // the bounding faces whose tolerance zone holds it. A STEP file places a boundary only
    // within those tolerances (an edge of tolerance 2e-3 may lie that far off the faces it
    // joins); an overlap within the allowance plus the tolerance at the deepest point or at O is
    // counted apart, as one the file itself leaves undecided (docs/Solver.md, item 14).
    auto fileTolerance = [&](const TopoDS_Shape& own, const gp_Pnt& X) {
      double tol = 0.0;
      const TopoDS_Vertex V = BRepBuilderAPI_MakeVertex(X).Vertex();
      for (const TopAbs_ShapeEnum kind : { TopAbs_FACE, TopAbs_EDGE, TopAbs_VERTEX })
        for (TopExp_Explorer ex(own, kind); ex.More(); ex.Next())
        {
          const TopoDS_Shape& sub = ex.Current();
          const double t = kind == TopAbs_FACE ? BRep_Tool::Tolerance(TopoDS::Face(sub))
            : kind == TopAbs_EDGE              ? BRep_Tool::Tolerance(TopoDS::Edge(sub))
                                               : BRep_Tool::Tolerance(TopoDS::Vertex(sub));
          if (!(t > tol))
            continue;
          Bnd_Box bb;
          BRepBndLib::Add(sub, bb);
          bb.Enlarge(t);
          if (bb.IsOut(X))
            continue;
          BRepExtrema_DistShapeShape d(V, sub, Extrema_ExtFlag_MIN);
          if (d.IsDone() && d.NbSolution() > 0 && d.Value() <= t)
            tol = t;
        }
      return tol;
    };
    if (!gap)
    {
      // A centre outside whose sphere lies within the file's own tolerance at the centre (the
      // largest tolerance of a face, edge or vertex whose zone holds it, at least t): the file
      // places its boundary there no more precisely than the sphere, and the classifier and the
      // rays read that zone as they may. Counted apart, as the overlaps are. (The Prusa MINI's
      // filament spur's two, t = 3.2e-3 and 2.1e-3, lie beyond it: the nearest edge, of
      // tolerance 2.1e-3, is 3.3e-3 from the first's centre.)
      size_t outsideBeyondFile = 0;
      for (const size_t k : outside)
      {
        const brt::SampleResult& r = res[k];
        const gp_Pnt C(r.Center[0], r.Center[1], r.Center[2]);
        outsideBeyondFile += fileTolerance(bounding(samples[k]), C) < r.Radius ? 1 : 0;
      }
      std::printf("    centre outside its solid (OpenCASCADE's classifier, and most of seven rays "
        "from it): %zu of %zu solved samples, %zu beyond the file's own tolerance there",
        outside.size(), solved, outsideBeyondFile);
      for (size_t j = 0; j < outside.size() && j < static_cast<size_t>(std::max(list, 1)); ++j)
      {
        const brt::SampleResult& r = res[outside[j]];
        std::printf("%s sample %zu (2t %.6g, face %d, opposite face %d)", j ? "," : ":",
          pick[outside[j]], r.Thickness, samples[outside[j]].Face, r.OppositeFace);
      }
      std::printf("; the classifier alone (the rays: inside): %zu\n", classifierAlone);
    }
    {
      // The drawn samples' O on their own face: a display-mesh vertex off its face (or a
      // boundary vertex nudged off it, SamplesFromMesh) starts its sphere where no wall is.
      // OpenCASCADE's face classifier at (U, V), then its distance from O to the face; those
      // farther than the file's own tolerance at O (a face's gap between its edges' pcurves,
      // which the reader bridges, holds O within it) are counted apart.
      // A second opinion, OpenCASCADE's other 2D classifier (BRepTopAdaptor_FClass2d): the face
      // classifier called points 0.0025-0.0027 mm inside a reflex corner or beside a hole's
      // vertex outside, in a band where it flips as the point moves by 0.005 (Prusa's extruder
      // body, sample 10775; the MMU2S idler, sample 8024), and the distance follows it. Such
      // samples are counted apart, not as off their face.
      size_t off = 0, offBeyondFile = 0, farthestAt = 0, faceClassifierAlone = 0;
      double farthest = 0.0;
      std::map<int, std::unique_ptr<BRepTopAdaptor_FClass2d>> second;
      for (size_t k = 0; k < samples.size(); ++k)
      {
        const TopoDS_Face& F = faces[static_cast<size_t>(samples[k].Face)];
        const gp_Pnt2d uv(samples[k].U, samples[k].V);
        BRepClass_FaceClassifier inFace(F, uv, 1e-9);
        if (inFace.State() != TopAbs_OUT)
          continue;
        const auto& o = samples[k].Point;
        const gp_Pnt O(o[0], o[1], o[2]);
        BRepExtrema_DistShapeShape d(BRepBuilderAPI_MakeVertex(O).Vertex(), F);
        if (!d.IsDone() || !(d.Value() > m.Tolerance))
          continue;
        std::unique_ptr<BRepTopAdaptor_FClass2d>& c2 = second[samples[k].Face];
        if (!c2)
          c2.reset(new BRepTopAdaptor_FClass2d(F, 1e-9));
        if (c2->Perform(uv) == TopAbs_IN)
        {
          ++faceClassifierAlone;
          continue;
        }
        ++off;
        offBeyondFile += d.Value() > fileTolerance(bounding(samples[k]), O) ? 1 : 0;
        if (d.Value() > farthest)
        {
          farthest = d.Value();
          farthestAt = pick[k];
        }
      }
      std::printf("    O off its own face by more than the tolerance (OpenCASCADE's face classifier, "
        "its distance and its 2D classifier): %zu of %zu samples", off, samples.size());
      if (off > 0)
        std::printf(", %zu beyond the file's own tolerance there; the farthest %.3g (sample %zu)",
          offBeyondFile, farthest, farthestAt);
      std::printf("; the face classifier alone (the 2D classifier: inside): %zu\n",
        faceClassifierAlone);
    }
    std::sort(worst.rbegin(), worst.rend());
    size_t beyondFile = 0;
    std::vector<double> tolThere(samples.size(), 0.0);
    for (const auto& w : worst)
    {
      const size_t k = w.second;
      const TopoDS_Shape& own = bounding(samples[k]);
      const gp_Pnt O(samples[k].Point[0], samples[k].Point[1], samples[k].Point[2]);
      tolThere[k] = std::max(fileTolerance(own, deepestAt[k]), fileTolerance(own, O));
      if (w.first > allowed + tolThere[k])
        ++beyondFile;
    }
    if (!worst.empty())
      std::printf("    overlaps beyond the allowance plus the file's own tolerance at the deepest "
                  "point or at O (the largest face, edge or vertex tolerance whose zone holds "
                  "it): %zu of %zu\n", beyondFile, worst.size());
    for (size_t w = 0; w < worst.size() && static_cast<int>(w) < list; ++w)
    {
      const size_t k = worst[w].second;
      const brt::SampleResult& r = res[k];
      std::printf("    sample %zu (face %d at %.4f %.4f %.4f): 2t = %.6g, %s, sphere %.3g into "
                  "the exact faces (%s %d), %.3g from O; the file's tolerance there %.3g\n",
        pick[k], samples[k].Face, samples[k].Point[0], samples[k].Point[1], samples[k].Point[2],
        r.Thickness, brt::ContactTypeName(r.Type), worst[w].first,
        deepestFace[k] >= 0 ? "face" : "edge or vertex", deepestFace[k], deepestFromO[k],
        tolThere[k]);
    }
    if (exactCount > 0)
    {
      // Exact thickness by the solver's definition (docs/Solver.md, step 0), computed apart:
      // the largest sphere tangent at O that no point of the exact faces enters deeper than
      // the clearance delta, by bisection on t of g(t) = dist(O + t d, faces) - t >= -delta
      // (g is about 0 up to the maximal radius and falls beyond it; sub-clearance steps in the
      // faces, a STEP file's gaps, leave it at -1e-4 or so, which delta ignores as the solver
      // does), then eq. 1's radius through the exact foot point P nearest to that centre,
      // |P - O|^2 / (2 d.(P - O)), which is what the solver reports.
      const double delta = 2.0 * m.Tolerance;
      // The distance from O + t d to the faces, less t: BRepExtrema's, or the second distance's
      // where that is nearer (as for the overlaps above).
      auto nearest = [&](const TopoDS_Shape& own, const brt::Sample& s, double t, gp_Pnt* foot) {
        const gp_Pnt X(s.Point[0] + t * s.Direction[0], s.Point[1] + t * s.Direction[1],
          s.Point[2] + t * s.Direction[2]);
        gp_Pnt at;
        double value = brt::exact::CheckedDistance(own, X, grid, &at);
        if (value < 0.0)
          return -1.0;
        gp_Pnt secondAt;
        int secondFace = -1;
        const double second = secondDistance(s, X, value, secondAt, secondFace);
        if (second < value)
        {
          value = second;
          at = secondAt;
        }
        if (foot)
          *foot = at;
        return value - t;
      };
      size_t checked = 0, agree = 0;
      std::vector<std::pair<double, size_t>> diffs;
      std::vector<double> clearanceValue(samples.size(), 0.0); // before the shrinking ball
      std::vector<double> strictValue(samples.size(), 0.0);    // after it
      size_t agreeClearance = 0, agreeStrict = 0, missEdgeZone = 0, osculatingStrict = 0;
      for (size_t k = 0; k < samples.size() && checked < exactCount; ++k)
      {
        const brt::SampleResult& r = res[k];
        const bool failedHere = r.Type == brt::ContactType::Failed;
        if (r.Type == brt::ContactType::OtherSolid || (failedHere && indices.empty()))
          continue;
        const TopoDS_Shape& own = bounding(samples[k]);
        double lo = 0.0, hi = std::max(2.0 * r.Radius, 1e-6);
        if (failedHere)
          hi = 1e-3 * data.Scale;
        while (nearest(own, samples[k], hi, nullptr) >= -delta && hi < 1e4)
          hi *= 2.0;
        for (int it = 0; it < 60 && hi - lo > 1e-10 * hi; ++it)
        {
          const double mid = 0.5 * (lo + hi);
          (nearest(own, samples[k], mid, nullptr) >= -delta ? lo : hi) = mid;
        }
        gp_Pnt P;
        if (nearest(own, samples[k], lo, &P) < -1.0 + 1e-12)
          continue;
        // Eq. 1's diameter through a boundary point P (0 where P is not in front of O).
        // Points within delta of O's tangent plane count as O's own face (a STEP file's faces
        // step by up to about 1e-4 there), as in the solver's t_delta.
        auto throughP = [&](const gp_Pnt& Q, double minDepth) {
          const double w[3] = { Q.X() - samples[k].Point[0], Q.Y() - samples[k].Point[1],
            Q.Z() - samples[k].Point[2] };
          const double dn = w[0] * samples[k].Direction[0] + w[1] * samples[k].Direction[1] +
            w[2] * samples[k].Direction[2];
          return dn > minDepth ? (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]) / dn : 0.0;
        };
        double exact = throughP(P, 0.0);
        if (!(exact > 0.0))
          exact = 2.0 * lo;
        clearanceValue[k] = exact;
        // Then the shrinking ball on the exact faces: the sphere through P, the nearest face point
        // to its centre, the sphere through that, until it settles. The clearance's sphere holds
        // boundary up to delta deep; this ends at the maximal sphere itself, the one the exact
        // finish reports on analytic faces (its radius differs from the clearance's by up to
        // delta^2 / (2 t), a lot for spheres of a few delta).
        for (int it = 0; it < 30 && exact > 0.0; ++it)
        {
          gp_Pnt Q;
          const double g = nearest(own, samples[k], 0.5 * exact, &Q);
          // Empty within 1e-7 of its radius (O itself is at that distance): maximal.
          if (g < -1.0 + 1e-12 || g >= -1e-7 * 0.5 * exact)
            break;
          const double next = throughP(Q, delta);
          if (!(next > 0.0) || !(next < exact))
            break;
          const bool settled = exact - next <= 1e-13 * exact;
          exact = next;
          if (settled)
            break;
        }
        // The shrinking ball leaves out the points next to O's tangent plane, so it cannot see O's
        // own face bound the sphere by its curvature at O: no sphere tangent at O is in the
        // material beyond the radius 1 / kappa, kappa the face's largest curvature at O towards
        // d (OpenCASCADE's GeomLProp_SLProps on the face's exact surface at the sample's (u, v)).
        {
          Handle(Geom_Surface) S = BRep_Tool::Surface(faces[static_cast<size_t>(samples[k].Face)]);
          GeomLProp_SLProps props(S, samples[k].U, samples[k].V, 2, 1e-9);
          if (props.IsNormalDefined() && props.IsCurvatureDefined())
          {
            const gp_Dir n = props.Normal();
            const double along = n.X() * samples[k].Direction[0] +
              n.Y() * samples[k].Direction[1] + n.Z() * samples[k].Direction[2];
            const double kappa = along > 0.0 ? props.MaxCurvature() : -props.MinCurvature();
            if (kappa > 0.0 && 2.0 / kappa < exact)
            {
              exact = 2.0 / kappa;
              ++osculatingStrict;
            }
          }
        }
        // Two definitions, each a value of its own: the clearance's sphere (the solver's
        // definition, docs/Solver.md step 0) and the strict maximal sphere after the shrinking
        // ball (what the exact finish reports on analytic faces). They differ by up to
        // delta^2 / (2 t) and, where a file's faces step by about 1e-4 along a flat arc, more:
        // a sample agrees when it matches either.
        if (failedHere)
        {
          // A failed sample: what it should have been (--indices only).
          std::printf("    sample %zu (face %d at %.6g %.6g %.6g): failed (%s), exact 2t = %.6g "
                      "(clearance's sphere %.6g)\n",
            pick[k], samples[k].Face, samples[k].Point[0], samples[k].Point[1],
            samples[k].Point[2], brt::FailReasonName(r.Reason), exact, clearanceValue[k]);
          continue;
        }
        strictValue[k] = exact;
        const double relC = std::fabs(r.Thickness - clearanceValue[k]) / std::max(clearanceValue[k], 1e-12);
        const double relS = std::fabs(r.Thickness - exact) / std::max(exact, 1e-12);
        ++checked;
        agreeClearance += relC <= 1e-4;
        agreeStrict += relS <= 1e-4;
        agree += relC <= 1e-4 || relS <= 1e-4;
        // A miss whose sphere a corner bounds (an edge zone: the map's own class, left out of the
        // thin share by default) is one a user does not read as a thin wall.
        if (!(relC <= 1e-4 || relS <= 1e-4))
          missEdgeZone += brt::IsEdgeZone(samples[k].Point.data(), r);
        const double nearer = relC < relS ? clearanceValue[k] : exact;
        diffs.emplace_back(r.Thickness - nearer, k);
      }
      std::sort(diffs.begin(), diffs.end(),
        [](const auto& x, const auto& y) { return std::fabs(x.first) > std::fabs(y.first); });
      std::printf("    exact thickness on %zu solved samples: %zu within 1e-4 relative (%.1f%%) of "
                  "the clearance's or the strict sphere (%zu and %zu of each; the strict one "
                  "bounded by O's own face's curvature at O on %zu); of the others, %zu in edge "
                  "zones\n",
        checked, agree, 100.0 * agree / std::max<size_t>(checked, 1), agreeClearance, agreeStrict,
        osculatingStrict, missEdgeZone);
      for (size_t w = 0; w < diffs.size() && static_cast<int>(w) < list; ++w)
      {
        const size_t k = diffs[w].second;
        std::printf("    sample %zu (face %d): ours 2t = %.6g, exact %.6g (%s; clearance's "
                    "sphere %.6g, strict %.6g%s)\n",
          pick[k], samples[k].Face, res[k].Thickness, res[k].Thickness - diffs[w].first,
          brt::ContactTypeName(res[k].Type), clearanceValue[k], strictValue[k],
          brt::IsEdgeZone(samples[k].Point.data(), res[k]) ? "; edge zone" : "");
      }
    }
    if (gap)
    {
      // Every sample the solver finds facing nothing (or nothing nearer than the model is large:
      // an open gap, docs/Solver.md): the exact sphere tangent at O from outside must stay empty
      // (no face nearer its centre than its radius, less the clearance) up to a radius of the
      // bounding-box diagonal. The spheres are nested, so the largest one decides.
      const double delta = 2.0 * m.Tolerance, far = data.Scale;
      size_t infinite = 0, confirmed = 0;
      for (size_t k = 0; k < samples.size(); ++k)
      {
        if (res[k].Type != brt::ContactType::Failed ||
          (res[k].Reason != brt::FailReason::NoOppositePoint &&
            res[k].Reason != brt::FailReason::Unbounded))
          continue;
        ++infinite;
        bool empty = true;
        for (double t = far; t <= far && empty; t *= 2.0)
        {
          const brt::Sample& s = samples[k];
          const double dist = brt::exact::CheckedDistance(bounding(s), gp_Pnt(s.Point[0] +
            t * s.Direction[0], s.Point[1] + t * s.Direction[1], s.Point[2] + t * s.Direction[2]));
          empty = dist >= t - delta;
        }
        confirmed += empty;
        if (!empty && list > 0)
          std::printf("    sample %zu (face %d at %.4f %.4f %.4f): infinite gap, but a face enters "
                      "the exact sphere\n",
            pick[k], samples[k].Face, samples[k].Point[0], samples[k].Point[1], samples[k].Point[2]);
      }
      std::printf("    infinite gap on %zu samples: %zu confirmed empty up to a radius of the diagonal\n",
        infinite, confirmed);
    }
    std::fflush(stdout);
  }
  return status;
}
