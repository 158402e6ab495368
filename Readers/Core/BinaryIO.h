// BRepThickness: raw binary I/O of plain vectors and strings, shared by the model files
// (ModelIO.h) and the solve files (Filters/Core/SolverIO.h). Same-architecture files only.
#pragma once

#include <cstdint>
#include <istream>
#include <ostream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace brt
{
namespace binary
{
/// Largest vector read back (bytes): a corrupt count fails instead of allocating terabytes.
constexpr std::uint64_t MaxBytes = std::uint64_t(1) << 34;

template <class T>
void Put(std::ostream& out, const std::vector<T>& v)
{
  static_assert(std::is_trivially_copyable<T>::value, "raw dump needs trivially copyable items");
  const std::uint64_t n = v.size();
  out.write(reinterpret_cast<const char*>(&n), sizeof n);
  out.write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(n * sizeof(T)));
}

template <class T>
void Get(std::istream& in, std::vector<T>& v)
{
  static_assert(std::is_trivially_copyable<T>::value, "raw dump needs trivially copyable items");
  std::uint64_t n = 0;
  in.read(reinterpret_cast<char*>(&n), sizeof n);
  if (!in || n > MaxBytes / sizeof(T))
    throw std::runtime_error("corrupt file (bad vector length)");
  v.resize(n);
  in.read(reinterpret_cast<char*>(v.data()), static_cast<std::streamsize>(n * sizeof(T)));
  if (!in)
    throw std::runtime_error("corrupt file (truncated)");
}

inline void PutString(std::ostream& out, const std::string& s)
{
  Put(out, std::vector<char>(s.begin(), s.end()));
}

inline std::string GetString(std::istream& in)
{
  std::vector<char> c;
  Get(in, c);
  return std::string(c.begin(), c.end());
}
} // namespace binary
} // namespace brt
