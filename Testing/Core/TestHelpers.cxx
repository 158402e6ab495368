#include "TestHelpers.h"

#include "Bezier.h"
#include "TrimClassifier.h"

#include <BRepClass_FaceClassifier.hxx>
#include <BRep_Tool.hxx>
#include <Geom_Surface.hxx>
#include <TopoDS.hxx>
#include <gp_Pnt2d.hxx>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <unistd.h>

namespace brt::test
{
std::string DataFile(const std::string& name)
{
  return std::string(BRT_DATA_DIR) + "/" + name;
}

std::vector<std::string> DataModels()
{
  std::vector<std::string> out;
  for (const auto& e : std::filesystem::directory_iterator(BRT_DATA_DIR))
  {
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    if (ext == ".step" || ext == ".stp")
      out.push_back(e.path().filename().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

PatchCheck CheckPatches(const BRepModel& m, const std::vector<TopoDS_Face>& faces, int perFace)
{
  PatchCheck r;
  std::mt19937_64 rng(12345);
  for (size_t f = 0; f < m.Faces.size(); ++f)
  {
    const Face& F = m.Faces[f];
    if (F.PatchCount == 0)
      continue;
    Handle(Geom_Surface) s = BRep_Tool::Surface(faces[f]);
    std::uniform_real_distribution<double> U(F.Domain[0], F.Domain[1]), V(F.Domain[2], F.Domain[3]);
    for (int k = 0; k < perFace; ++k)
    {
      const double u = U(rng), v = V(rng);
      const PatchEval e = EvaluatePatch(m.Patches[FindPatch(m, static_cast<int>(f), u, v)], u, v);
      const gp_Pnt q = s->Value(u, v);
      const double d = std::hypot(e.P[0] - q.X(), e.P[1] - q.Y(), e.P[2] - q.Z());
      if (d > r.MaxDeviation)
      {
        r.MaxDeviation = d;
        r.WorstFace = static_cast<int>(f);
      }
      ++r.Samples;
    }
  }
  return r;
}

TrimCheck CheckTrims(const BRepModel& m, const std::vector<TopoDS_Face>& faces, long points)
{
  TrimCheck r;
  for (const TrimLoop& loop : m.Loops)
  {
    for (int k = 0; k < loop.SegmentCount; ++k)
    {
      const auto& a = m.TrimSegments[loop.FirstSegment + k].ControlPoints;
      const auto& b =
        m.TrimSegments[loop.FirstSegment + (k + 1) % loop.SegmentCount].ControlPoints;
      if (!loop.Open)
        r.MaxClosureGap = std::max(r.MaxClosureGap, std::hypot(a[6] - b[0], a[7] - b[1]));
    }
  }
  std::mt19937_64 rng(777);
  std::uniform_int_distribution<size_t> pickFace(0, m.Faces.size() - 1);
  for (long k = 0; k < points; ++k)
  {
    const size_t f = pickFace(rng);
    const Face& F = m.Faces[f];
    std::uniform_real_distribution<double> U(F.Domain[0], F.Domain[1]), V(F.Domain[2], F.Domain[3]);
    const double u = U(rng), v = V(rng);
    const TopoDS_Face ff = TopoDS::Face(faces[f].Oriented(TopAbs_FORWARD));
    BRepClass_FaceClassifier occ(ff, gp_Pnt2d(u, v), 1e-9);
    const TopAbs_State state = occ.State();
    if (state == TopAbs_ON)
    {
      ++r.OnBoundary;
      continue;
    }
    if (state != TopAbs_IN && state != TopAbs_OUT)
      continue;
    ++r.Compared;
    const TrimProjection ours = ClassifyPoint(m, static_cast<int>(f), u, v);
    if (ours.Inside == (state == TopAbs_IN))
      continue;
    std::ostringstream d;
    d << "face " << f << " (" << SurfaceKindName(F.Kind) << ", loops " << F.LoopCount
      << ") uv=(" << u << ", " << v << "): OpenCASCADE " << (state == TopAbs_IN ? "IN" : "OUT")
      << ", trimming segments " << (ours.Inside ? "IN" : "OUT") << ", distance to boundary "
      << ours.Distance << (ours.Corner ? " (corner rule)" : "");
    // Within the conversion's parametric tolerance of the boundary both answers are right.
    if (ours.Distance <= 10.0 * F.UVTolerance)
      ++r.NearBoundary;
    else
      r.Disagreements.push_back(d.str());
  }
  return r;
}
namespace
{
/// The folders TempDir made, removed with their content when the test process exits normally.
struct TempDirs
{
  std::vector<std::filesystem::path> Made;
  ~TempDirs()
  {
    for (const auto& d : Made)
    {
      std::error_code ec;
      std::filesystem::remove_all(d, ec);
    }
  }
};
}

std::string TempDir(const std::string& prefix)
{
  static TempDirs dirs;
  const std::filesystem::path d =
    std::filesystem::temp_directory_path() / (prefix + "-" + std::to_string(::getpid()));
  if (std::filesystem::create_directories(d))
    dirs.Made.push_back(d);
  return d.string();
}

std::string ReadAll(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}
} // namespace brt::test
