// Shared helpers of the core tests: the models of Data/ and checks against OpenCASCADE.
#pragma once

#include "BRepConverter.h"
#include "BRepModel.h"

#include <TopoDS_Face.hxx>

#include <string>
#include <vector>

namespace brt::test
{
/// All STEP files in Data/, sorted.
std::vector<std::string> DataModels();
std::string DataFile(const std::string& name);
/// A folder of this test process's own under the system's temporary folder (made once, removed
/// with its content when the process exits normally).
std::string TempDir(const std::string& prefix);
/// The whole content of a file.
std::string ReadAll(const std::string& path);

struct PatchCheck
{
  double MaxDeviation = 0.0; ///< max |Bezier(u,v) - S(u,v)| over all samples
  int WorstFace = -1;
  long Samples = 0;
};
/// Compares every face's patches with its exact surface at `perFace` random (u,v).
PatchCheck CheckPatches(const BRepModel& m, const std::vector<TopoDS_Face>& faces, int perFace);

struct TrimCheck
{
  long Compared = 0;        ///< points both classifiers call IN or OUT
  long OnBoundary = 0;      ///< points OpenCASCADE calls ON (skipped)
  long NearBoundary = 0;    ///< disagreements within the conversion's UV tolerance band
  std::vector<std::string> Disagreements; ///< disagreements farther from the boundary
  double MaxClosureGap = 0.0; ///< largest gap between consecutive segments after welding
};
/// Classifies `points` random (u,v) (faces drawn uniformly, (u,v) uniform in the face's
/// bounds) with the cubic trimming segments and with BRepClass_FaceClassifier.
TrimCheck CheckTrims(const BRepModel& m, const std::vector<TopoDS_Face>& faces, long points);
} // namespace brt::test
