// BRepThickness: the reader's output contract read back (docs/DataContract.md). The inverse of
// vtkSTEPReader's FillPolyData: field arrays -> B-Rep, points/triangles/point arrays -> display
// mesh. Not wrapped; used by the filters of this module.
#pragma once

#include "BRepModel.h"

#include <stdexcept>
#include <string>

class vtkPolyData;

namespace brt
{

/// The input does not follow the contract; the message names the array and the problem.
class ContractError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/// Whether `input` carries the converted B-Rep at all (the field array BezierPatches).
bool HasBRepFieldData(vtkPolyData* input);

/// The B-Rep and the display mesh of `input`. Every index is checked against the sizes it refers
/// to, so a damaged or foreign file gives a ContractError rather than a crash in the solver.
BRepModel ModelFromPolyData(vtkPolyData* input);

struct MidsurfaceInput;
/// The display mesh and the per-sample results of a thickness map (vtkThicknessFilter's port 0)
/// for BuildMidsurface and BuildSkeleton. False, with the array's name in `missing`, when the
/// input lacks one of the point arrays they need.
bool BRepMidsurfaceInput(vtkPolyData* input, MidsurfaceInput& out, std::string& missing);

} // namespace brt
