// BRepThickness: the exception for bad input files.
#pragma once

#include <stdexcept>

namespace brt
{
/// Bad input: the message names the file and the reason, ready to show to the user.
class InputError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};
} // namespace brt
