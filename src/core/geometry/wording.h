// Internal to the core: how messages about meshes write counts and lengths (one wording).
#pragma once

#include <cstddef>
#include <sstream>
#include <string>

namespace virtual_tryon {
namespace wording {

// "1 face", "3 faces".
inline std::string plural(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

// A length in metres with 4 significant digits.
inline std::string metres(double v) {
  std::ostringstream o;
  o.precision(4);
  o << v;
  return o.str();
}

}  // namespace wording
}  // namespace virtual_tryon
