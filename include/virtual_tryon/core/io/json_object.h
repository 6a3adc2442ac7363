// A JSON object written field by field in the order given (stable key order), for reports.
// Strings are escaped; a non-finite double is written as null; doubles with 9 significant digits.
#pragma once

#include <cmath>
#include <cstddef>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

namespace virtual_tryon {
namespace json {

inline std::string quoted(const std::string& s) {
  std::ostringstream o;
  o << '"';
  for (char c : s) {
    switch (c) {
      case '"': o << "\\\""; break;
      case '\\': o << "\\\\"; break;
      case '\n': o << "\\n"; break;
      case '\t': o << "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20)
          o << "\\u" << std::hex << std::setw(4) << std::setfill('0') << static_cast<int>(c) << std::dec;
        else
          o << c;
    }
  }
  o << '"';
  return o.str();
}

class Obj {
 public:
  Obj& add(const char* k, const std::string& v) { return raw(k, quoted(v)); }
  Obj& add(const char* k, bool v) { return raw(k, v ? "true" : "false"); }
  Obj& add(const char* k, std::size_t v) { return raw(k, std::to_string(v)); }
  Obj& add(const char* k, int v) { return raw(k, std::to_string(v)); }
  Obj& add(const char* k, const std::vector<std::string>& v) {
    std::string a = "[";
    for (std::size_t i = 0; i < v.size(); ++i) a += (i ? ", " : "") + quoted(v[i]);
    return raw(k, a + "]");
  }
  Obj& json(const char* k, const std::string& v) { return raw(k, v); }  // v: JSON text
  Obj& add(const char* k, double v) {
    if (!std::isfinite(v)) return raw(k, "null");
    std::ostringstream o;
    o << std::setprecision(9) << v;
    return raw(k, o.str());
  }
  std::string str() const { return "{" + body_.str() + "}"; }

 private:
  Obj& raw(const char* k, const std::string& v) {
    if (!first_) body_ << ", ";
    first_ = false;
    body_ << quoted(k) << ": " << v;
    return *this;
  }
  std::ostringstream body_;
  bool first_ = true;
};

}  // namespace json
}  // namespace virtual_tryon
