#include "common.h"

#include "virtual_tryon/core/scenes/procedural_body.h"

#include <algorithm>
#include <cstdarg>
#include <iomanip>

namespace eval {

Csv::Csv(const std::string& path, const std::vector<std::string>& header)
    : path_(path), out_(path), columns_(header.size()) {
  for (std::size_t i = 0; i < header.size(); ++i) out_ << (i ? "," : "") << header[i];
  out_ << "\n";
  out_.flush();
}

void Csv::row(const std::vector<Cell>& cells) {
  if (cells.size() != columns_)
    std::fprintf(stderr, "evaluate: %s: row of %zu cells for %zu columns\n", path_.c_str(), cells.size(), columns_);
  for (std::size_t i = 0; i < cells.size(); ++i) out_ << (i ? "," : "") << cells[i].text();
  out_ << "\n";
  out_.flush();
}

namespace {
std::string jsonString(const std::string& s) {
  std::ostringstream o;
  o << '"';
  for (char c : s) {
    if (c == '"' || c == '\\') o << '\\' << c;
    else if (c == '\n') o << "\\n";
    else if (static_cast<unsigned char>(c) < 0x20) o << ' ';
    else o << c;
  }
  o << '"';
  return o.str();
}
}  // namespace

void Summary::set(const std::string& key, double v) {
  if (!std::isfinite(v)) {
    values_[key] = "null";
    return;
  }
  std::ostringstream o;
  o << std::setprecision(9) << v;
  values_[key] = o.str();
}
void Summary::set(const std::string& key, bool v) { values_[key] = v ? "true" : "false"; }
void Summary::set(const std::string& key, const std::string& v) { values_[key] = jsonString(v); }

bool Summary::write(const std::string& path) const {
  std::ofstream out(path);
  out << "{\n";
  for (const auto& [k, v] : values_) out << "  " << jsonString(k) << ": " << v << ",\n";
  out << "  \"notes\": [";
  for (std::size_t i = 0; i < notes_.size(); ++i) out << (i ? ",\n    " : "\n    ") << jsonString(notes_[i]);
  out << "\n  ]\n}\n";
  return static_cast<bool>(out);
}

Summary& summary() {
  static Summary s;
  return s;
}

void progress(const char* fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  std::fprintf(stderr, "evaluate: ");
  std::vfprintf(stderr, fmt, ap);
  std::fprintf(stderr, "\n");
  va_end(ap);
}

Timing timeRuns(int runs, const std::function<void()>& f) {
  std::vector<double> t;
  for (int r = 0; r < std::max(1, runs); ++r) {
    const double t0 = now();
    f();
    t.push_back(now() - t0);
  }
  std::sort(t.begin(), t.end());
  return {t[t.size() / 2], t.front(), t.back()};
}

}  // namespace eval
