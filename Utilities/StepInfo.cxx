// Reads and converts STEP files and prints what the reader produces and how long it took.
// Usage: brt_step_info [options] FILE.step [FILE.step ...]  (--help lists the options)
#include "BRepConverter.h"
#include "StepFile.h"
#include "StepIsolation.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <map>

namespace
{
const char* const Usage =
  "usage: brt_step_info [options] FILE.step [FILE.step ...]\n"
  "Reads, heals and converts each STEP file as the BRepThickness reader does and prints what it\n"
  "produces (solids, faces, patches, trimming segments, edges, mesh points, deviations, times)\n"
  "and its warnings. Bad files give one error line each; the exit status is 1 if any failed.\n"
  "  --tolerance T     Bezier conversion tolerance in mm (default 1e-4)\n"
  "  --max-edge L      longest display mesh edge in mm (default: 1/50 of the diagonal)\n"
  "  --delaunay        refine the display mesh with Delaunay flips (the reader's\n"
  "                    DelaunayRefinement)\n"
  "  --sliver-ratio R  without --delaunay, a face whose bisection mesh would hold more than R\n"
  "                    times the vertices of its flipped mesh and more than --sliver-vertices\n"
  "                    gets the flipped one (default 4; 0: bisection on every face)\n"
  "  --sliver-vertices N  (default 10000)\n"
  "  --time-limit S    seconds each file may take (default 300, 0: none)\n"
  "  --in-process      read in this process instead of the worker process (a file that\n"
  "                    crashes OpenCASCADE then crashes this program; for debugging)\n"
  "  --help            this text\n";
} // namespace

int main(int argc, char** argv)
{
  brt::ConversionOptions options;
  brt::IsolationOptions isolation;
  bool inProcess = false;
  int status = 0, files = 0;
  for (int i = 1; i < argc; ++i)
    if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h"))
    {
      std::fputs(Usage, stdout);
      return 0;
    }
  std::printf("%-34s %6s %6s %7s %7s %6s %9s %9s %9s %7s %7s %7s %7s\n", "file", "solids",
    "faces", "patches", "trimseg", "edges", "meshpts", "maxdev", "maxgap", "read_s", "heal_s",
    "conv_s", "mesh_s");
  for (int i = 1; i < argc; ++i)
  {
    if (!std::strcmp(argv[i], "--tolerance") && i + 1 < argc)
    {
      options.Tolerance = std::atof(argv[++i]);
      continue;
    }
    if (!std::strcmp(argv[i], "--max-edge") && i + 1 < argc)
    {
      options.MaxEdgeLength = std::atof(argv[++i]);
      continue;
    }
    if (!std::strcmp(argv[i], "--delaunay"))
    {
      options.DelaunayRefinement = true;
      continue;
    }
    if (!std::strcmp(argv[i], "--sliver-vertices") && i + 1 < argc)
    {
      options.SliverVertices = std::atoi(argv[++i]);
      continue;
    }
    if (!std::strcmp(argv[i], "--sliver-ratio") && i + 1 < argc)
    {
      options.SliverRatio = std::atof(argv[++i]);
      continue;
    }
    if (!std::strcmp(argv[i], "--time-limit") && i + 1 < argc)
    {
      isolation.TimeLimit = std::atof(argv[++i]);
      continue;
    }
    if (!std::strcmp(argv[i], "--in-process"))
    {
      inProcess = true;
      continue;
    }
    if (argv[i][0] == '-' && argv[i][1] == '-')
    {
      std::fprintf(stderr, "error: unknown option %s\n%s", argv[i], Usage);
      return 2;
    }
    ++files;
    try
    {
      const brt::BRepModel m = inProcess ? brt::ConvertStepFile(argv[i], options)
                                         : brt::ConvertStepFileIsolated(argv[i], options, isolation);
      const auto& s = m.Stats;
      const char* name = std::strrchr(argv[i], '/') ? std::strrchr(argv[i], '/') + 1 : argv[i];
      std::printf("%-34s %6d %6d %7d %7d %6d %9zu %9.2e %9.2e %7.2f %7.2f %7.2f %7.2f\n", name,
        s.Solids, s.Faces, s.Patches, s.TrimSegments, s.Edges, m.Mesh.NumberOfPoints(),
        s.MaxPatchDeviation, s.MaxLoopGap, s.ReadSeconds, s.HealSeconds, s.ConvertSeconds,
        s.MeshSeconds);
      std::map<std::string, int> kinds;
      for (const auto& f : m.Faces)
        ++kinds[std::string(brt::SurfaceKindName(f.Kind)) +
          // an analytic kind with the file's B-spline degrees: found in a B-spline or Bezier
          (f.Kind <= brt::SurfaceKind::Torus && f.DegreeU > 0 ? "(in a bspline)"
            : f.Rational                                    ? "(rational)"
                                                            : "")];
      if (s.FlippedFaces > 0)
        std::printf("  display mesh: %d faces flipped (their bisection beyond %g times and %d "
                    "vertices)\n",
          s.FlippedFaces, options.SliverRatio, options.SliverVertices);
      if (s.RemeshedFaces > 0)
        std::printf("  display mesh: %d faces meshed again alone (BRepMesh left them without "
                    "one)\n",
          s.RemeshedFaces);
      std::printf("  surfaces:");
      for (const auto& k : kinds)
        std::printf(" %s=%d", k.first.c_str(), k.second);
      std::printf("\n");
      for (const auto& w : s.Warnings)
        std::printf("  warning: %s\n", w.c_str());
    }
    catch (const std::exception& e)
    {
      std::fprintf(stderr, "error: %s\n", e.what());
      status = 1;
    }
  }
  if (files == 0)
  {
    std::fputs(Usage, stderr);
    return 2;
  }
  return status;
}
