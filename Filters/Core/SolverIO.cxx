#include "SolverIO.h"

#include "BinaryIO.h"
#include "ModelIO.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace brt
{
namespace
{
constexpr std::uint64_t Magic = 0x32564C4F53545242ull; // "BRTSOLV2": S1Point::OnEdge
constexpr std::uint64_t MagicV1 = 0x31564C4F53545242ull; // "BRTSOLV1": no edge points
// Version 1 files stay readable because OnEdge took the padding after Face.
static_assert(sizeof(S1Point) == 48, "S1Point layout changed: bump the solve file version");

/// A sample as the files store it (Sample before its Curvature, which follows the rest of a
/// file: files written before it stay readable).
struct SampleRecord
{
  int Face = -1;
  double U = 0.0, V = 0.0;
  std::array<double, 3> Point{};
  std::array<double, 3> Direction{};
};
static_assert(sizeof(SampleRecord) == 72, "SampleRecord layout changed: bump the solve file version");

/// The fields a Sample and a SampleRecord share, from one to the other.
template <class From, class To>
void CopySampleFields(const From& from, To& to)
{
  to.Face = from.Face;
  to.U = from.U;
  to.V = from.V;
  to.Point = from.Point;
  to.Direction = from.Direction;
}

using binary::Get;
using binary::Put;
} // namespace

void WriteSolve(const std::string& path, const BRepModel& m, const SolverData& d,
  const std::vector<Sample>& samples)
{
  std::ofstream out(path, std::ios::binary);
  if (!out)
    throw std::runtime_error("cannot write '" + path + "'");
  out.write(reinterpret_cast<const char*>(&Magic), sizeof Magic);
  PutGeometry(out, m);
  // S1Point's padding after OnEdge zeroed, so that one prepared model always writes the same
  // bytes (it carried whatever the heap held: two exports of one model differed byte for byte).
  std::vector<S1Point> s1(d.S1.size());
  if (!s1.empty())
    std::memset(static_cast<void*>(s1.data()), 0, s1.size() * sizeof(S1Point));
  for (size_t i = 0; i < s1.size(); ++i)
  {
    s1[i].Point = d.S1[i].Point;
    s1[i].Face = d.S1[i].Face;
    s1[i].OnEdge = d.S1[i].OnEdge;
    s1[i].U = d.S1[i].U;
    s1[i].V = d.S1[i].V;
  }
  Put(out, s1);
  Put(out, d.Nodes);
  Put(out, d.Breaks);
  Put(out, d.FaceBreaks);
  std::vector<SampleRecord> records(samples.size());
  std::vector<std::array<double, 2>> curvatures(samples.size());
  if (!records.empty())
    std::memset(static_cast<void*>(records.data()), 0, records.size() * sizeof(SampleRecord));
  for (size_t i = 0; i < samples.size(); ++i)
  {
    CopySampleFields(samples[i], records[i]);
    curvatures[i] = samples[i].Curvature;
  }
  Put(out, records);
  const std::vector<double> scalars{ d.Scale, d.Centre[0], d.Centre[1], d.Centre[2], d.S1Spacing,
    m.Tolerance };
  Put(out, scalars);
  Put(out, m.FaceExact); // after everything else: older files end before it
  Put(out, curvatures);  // and then the samples' curvatures: older files end before them
}

void ReadSolve(const std::string& path, BRepModel& m, SolverData& d, std::vector<Sample>& samples)
{
  std::ifstream in(path, std::ios::binary);
  std::uint64_t magic = 0;
  in.read(reinterpret_cast<char*>(&magic), sizeof magic);
  if (!in || (magic != Magic && magic != MagicV1))
    throw std::runtime_error("'" + path + "' is not a BRepThickness solve file");
  try
  {
    GetGeometry(in, m);
    Get(in, d.S1);
    if (magic == MagicV1)
      for (S1Point& p : d.S1)
        p.OnEdge = false; // the byte was padding then
    Get(in, d.Nodes);
    Get(in, d.Breaks);
    Get(in, d.FaceBreaks);
    std::vector<SampleRecord> records;
    Get(in, records);
    samples.assign(records.size(), Sample());
    for (size_t i = 0; i < records.size(); ++i)
      CopySampleFields(records[i], samples[i]);
    std::vector<double> scalars;
    Get(in, scalars);
    if (scalars.size() < 4 || scalars.size() > 6)
      throw std::runtime_error("corrupt solve file");
    d.Scale = scalars[0];
    d.Centre = { scalars[1], scalars[2], scalars[3] };
    // Files written before the spacing was kept: the default it had then.
    d.S1Spacing = scalars.size() >= 5 ? scalars[4] : d.Scale / 100.0;
    // Files written before the conversion tolerance was kept: the reader's default (the
    // clearance and the vertex table depend on it).
    m.Tolerance = scalars.size() >= 6 ? scalars[5] : BRepModel().Tolerance;
    // Files written before the exact surfaces were kept end here: no exact finish.
    m.FaceExact.clear();
    if (in.peek() != std::char_traits<char>::eof())
      Get(in, m.FaceExact);
    bool finite = m.FaceExact.empty() || m.FaceExact.size() == m.Faces.size();
    for (const auto& e : m.FaceExact)
      for (double x : e)
        finite = finite && std::isfinite(x);
    if (!finite)
      throw std::runtime_error("corrupt solve file (exact surfaces)");
    // Files written before the samples' curvatures were kept end here: no osculating bound.
    if (in.peek() != std::char_traits<char>::eof())
    {
      std::vector<std::array<double, 2>> curvatures;
      Get(in, curvatures);
      if (curvatures.size() != samples.size())
        throw std::runtime_error("corrupt solve file (curvatures)");
      for (size_t i = 0; i < samples.size(); ++i)
      {
        if (!std::isfinite(curvatures[i][0]) || !std::isfinite(curvatures[i][1]))
          throw std::runtime_error("corrupt solve file (curvatures)");
        samples[i].Curvature = curvatures[i];
      }
    }
  }
  catch (const std::runtime_error& e)
  {
    throw std::runtime_error("'" + path + "': " + e.what());
  }
  // The tree is built again rather than trusted: files written before the split root
  // (BVHNode) have none, and a tree that names points outside s1 would be read out of bounds.
  BuildS1Tree(m, d);
  BuildVertices(m, d);
  BuildPatchBoxes(m, d);
  BuildLoopCrossings(m, d);
  BuildWallPartners(m, d);
  m.Stats.Faces = static_cast<int>(m.Faces.size());
  m.Stats.Patches = static_cast<int>(m.Patches.size());
}
} // namespace brt
