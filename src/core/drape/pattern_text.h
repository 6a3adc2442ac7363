// Internal to the core: how pattern messages name numbers and panels (one wording everywhere).
#pragma once

#include "virtual_tryon/core/drape/pattern.h"

#include <sstream>
#include <string>

namespace virtual_tryon {
namespace pattern_text {

inline std::string num(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

inline std::string panelLabel(const Pattern& pattern, int p) {
  return "panel '" + pattern.panels[static_cast<std::size_t>(p)].name + "' (index " + std::to_string(p) + ")";
}

}  // namespace pattern_text
}  // namespace virtual_tryon
