// BRepThickness: binary dump of a prepared solve (model, solver data, samples), so that the
// solver can be benchmarked on a machine without OpenCASCADE (brt_thickness_bench built with -DBRT_SOLVER_ONLY=ON).
// Same-architecture files only; not a storage format.
#pragma once

#include "Solver.h"

#include <string>

namespace brt
{
void WriteSolve(const std::string& path, const BRepModel& model, const SolverData& data,
  const std::vector<Sample>& samples);
/// Throws std::runtime_error naming the file if it cannot be read.
void ReadSolve(const std::string& path, BRepModel& model, SolverData& data,
  std::vector<Sample>& samples);
} // namespace brt
