// BRepThickness: the reader's output contract read back (docs/DataContract.md). The inverse of
// vtkSTEPReader's FillPolyData: field arrays -> B-Rep, points/triangles/point arrays -> display
// mesh. Not wrapped; used by vtkThicknessFilter only.
#pragma once

#include "BRepModel.h"

#include <stdexcept>

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

} // namespace brt
