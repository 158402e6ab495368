// Helpers of the solver tests: convert a shape, solve, and summarise the results.
#pragma once

#include "BRepConverter.h"
#include "Solver.h"

#include <TopoDS_Shape.hxx>

#include <array>
#include <string>
#include <vector>

namespace brt::test
{
struct Solved
{
  BRepModel Model;
  SolverData Data;
  std::vector<Sample> Samples;
  std::vector<SampleResult> Results;
};

/// Converts `shape` with the given conversion tolerance and solves it with the reference.
Solved SolveShape(const TopoDS_Shape& shape, double tolerance, const SolverOptions& options = {});

/// Distance from each sample to the nearest rim: an edge that is neither a seam, nor degenerated,
/// nor the line where two faces of one analytic surface meet.
std::vector<double> RimDistances(const BRepModel& model, const std::vector<Sample>& samples);

/// The (u, v) on `face`'s patches nearest `point` (Gauss-Newton on |S(u, v) - point|^2 from each
/// patch's middle, clamped to the patch; the nearest kept), as a mesh sample carries it. Returns
/// the distance of that patch point from `point`.
double FaceParameters(const BRepModel& model, int face, const std::array<double, 3>& point,
  double* u, double* v);

/// Prints failed share and residual percentiles (median, 99th, max) per contact type.
void PrintResidualSummary(const std::string& name, const std::vector<SampleResult>& results);
} // namespace brt::test
