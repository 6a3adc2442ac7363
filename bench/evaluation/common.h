// Shared by the evaluation's sections (bench/evaluate.cpp): options, CSV output, timing, the key
// numbers that go to summary.json, and the procedural scenes.
#pragma once

#include "virtual_tryon/core/geometry/mesh.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace vt = virtual_tryon;

namespace eval {

struct Options {
  bool quick = false;
  std::string out;       // output folder (CSV files and summary.json go here)
  std::string data;      // ../shared/data or $VT_DATA
  std::string patterns;  // config/patterns
  bool data_found = false;
  double extreme_timeout = 120;  // seconds before a forked extreme case counts as a hang
};

inline double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// One cell of a CSV file: numbers with 9 significant digits, non-finite as nan/inf/-inf.
class Cell {
 public:
  Cell(const std::string& s) : text_(quote(s)) {}
  Cell(const char* s) : text_(quote(s)) {}
  Cell(bool b) : text_(b ? "1" : "0") {}
  Cell(int v) : text_(std::to_string(v)) {}
  Cell(long v) : text_(std::to_string(v)) {}
  Cell(std::size_t v) : text_(std::to_string(v)) {}
  Cell(double v) {
    if (std::isnan(v)) {
      text_ = "nan";
    } else if (std::isinf(v)) {
      text_ = v > 0 ? "inf" : "-inf";
    } else {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.9g", v);
      text_ = buf;
    }
  }
  const std::string& text() const { return text_; }

 private:
  static std::string quote(const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
    return q + "\"";
  }
  std::string text_;
};

class Csv {
 public:
  Csv(const std::string& path, const std::vector<std::string>& header);
  void row(const std::vector<Cell>& cells);
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::ofstream out_;
  std::size_t columns_;
};

// Key numbers and invariants, written to summary.json at the end (flat keys "section.name").
class Summary {
 public:
  void set(const std::string& key, double v);
  void set(const std::string& key, bool v);
  void set(const std::string& key, const std::string& v);
  void set(const std::string& key, int v) { set(key, static_cast<double>(v)); }
  void set(const std::string& key, std::size_t v) { set(key, static_cast<double>(v)); }
  void note(const std::string& text) { notes_.push_back(text); }
  bool write(const std::string& path) const;

 private:
  std::map<std::string, std::string> values_;  // JSON text
  std::vector<std::string> notes_;
};
Summary& summary();

// Prints a progress line to stderr (the report itself goes to files).
void progress(const char* fmt, ...);

// Median, min and max of the run times of f() over `runs` calls.
struct Timing {
  double median = 0, min = 0, max = 0;
};
Timing timeRuns(int runs, const std::function<void()>& f);

// ---- procedural scenes ------------------------------------------------------------------------

// A tight top round the procedural body's torso, as a learned model might predict it: the body
// surface meshed again at `resolution`, moved out along its normals by 3 mm plus waves of +-12 mm
// (so the troughs dip up to 9 mm in), cut to the band between the hips and below the armpits.

// Section entry points.
void resolverSection(const Options& o);
void drapeSection(const Options& o);
void stabilitySection(const Options& o);
void extremeSection(const Options& o);
void leanSection(const Options& o);

}  // namespace eval

namespace eval {

// The resolver scenes of section 1: procedural ones always, body_hm08 with each garment when the
// data is there.
struct NamedScene {
  std::string name;
  std::string source;  // "procedural" or "body_hm08"
  std::string what;    // one line for the report
  vt::TriMesh body, garment;
};
std::vector<NamedScene> resolverScenes(const Options& o);

}  // namespace eval
