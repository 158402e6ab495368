// BRepThickness: reading a STEP file into an OpenCASCADE shape, with input validation.
#pragma once

#include <stdexcept>
#include <string>

class TopoDS_Shape;

namespace brt
{

/// Bad input: the message names the file and the reason, ready to show to the user.
class InputError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/// Cheap checks that need no STEP parsing: the path exists, is a regular non-empty readable file,
/// starts with the ISO-10303-21 header and ends with its END-ISO-10303-21 terminator.
/// Throws InputError on the first problem found.
void CheckStepFile(const std::string& path);

struct StepReadResult
{
  std::string LengthUnit = "mm"; ///< unit of the returned shape (OpenCASCADE converts to mm)
  std::string Schema;            ///< FILE_SCHEMA of the file (AP203/AP214/AP242 names)
  int Roots = 0;                 ///< transferable roots found
  double Seconds = 0.0;
};

/// Reads all roots of a STEP file (AP203, AP214, AP242) into one shape, in millimetres.
/// Throws InputError if the file is not a readable STEP file or holds no face.
TopoDS_Shape ReadStepFile(const std::string& path, StepReadResult* info = nullptr);

} // namespace brt
