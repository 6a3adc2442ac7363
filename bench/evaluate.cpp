// The evaluation report's measurements (issue #5): error against run time for the resolver and the
// drape, stability on stiff cases, extreme cases, and what a scene does not pay for. Writes CSV
// files and summary.json into OUT_DIR; scripts/plot_evaluation.py turns them into PNG plots and
// report.md (scripts/evaluate.sh does both).
//
// Usage: evaluate [--quick] [--data DIR] [--patterns DIR] [--out DIR] [--only SECTIONS]
//   --quick     procedural scenes only, small sizes: a few seconds (the test suite runs this)
//   --data      the shared meshes (default ../shared/data or $VT_DATA); skipped with a note if absent
//   --patterns  the pattern folder (default: the source tree's config/patterns)
//   --out       output folder (default ./evaluation)
//   --only      comma-separated subset of resolver,drape,stability,extreme,lean
#include "evaluation/common.h"

#include <sys/stat.h>
#include <sys/utsname.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>

#ifndef VIRTUAL_TRYON_SOURCE_DIR
#define VIRTUAL_TRYON_SOURCE_DIR "."
#endif

namespace {

bool makeDirs(const std::string& path) {
  std::string p;
  for (std::size_t i = 0; i <= path.size(); ++i) {
    if (i == path.size() || path[i] == '/') {
      if (!p.empty()) mkdir(p.c_str(), 0755);
    }
    if (i < path.size()) p += path[i];
  }
  struct stat st;
  return stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

std::string cpuModel() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

std::string loadAverage() {
  std::ifstream in("/proc/loadavg");
  std::string a, b, c;
  in >> a >> b >> c;
  return a + " " + b + " " + c;
}

int usage(const char* msg) {
  std::fprintf(stderr, "evaluate: %s\nusage: evaluate [--quick] [--data DIR] [--patterns DIR] [--out DIR] "
                       "[--only resolver,drape,stability,extreme,lean]\n", msg);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  eval::Options o;
  o.data = std::getenv("VT_DATA") ? std::getenv("VT_DATA") : "../shared/data";
  o.patterns = std::string(VIRTUAL_TRYON_SOURCE_DIR) + "/config/patterns";
  o.out = "evaluation";
  std::string only = "resolver,drape,stability,extreme,lean";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> const char* { return i + 1 < argc ? argv[++i] : nullptr; };
    if (a == "--quick") {
      o.quick = true;
    } else if (a == "--data" || a == "--patterns" || a == "--out" || a == "--only") {
      const char* v = value();
      if (!v) return usage(("missing value for " + a).c_str());
      (a == "--data" ? o.data : a == "--patterns" ? o.patterns : a == "--out" ? o.out : only) = v;
    } else if (a == "--help" || a == "-h") {
      usage("help");
      return 0;
    } else {
      return usage(("unknown argument " + a).c_str());
    }
  }
  if (!makeDirs(o.out)) return usage(("cannot create " + o.out).c_str());
  o.data_found = !o.quick && access((o.data + "/body_hm08.obj").c_str(), R_OK) == 0;

  auto& s = eval::summary();
  s.set("mode", std::string(o.quick ? "quick" : "full"));
  s.set("data_dir", o.data);
  s.set("data_found", o.data_found);
  if (o.quick) s.note("quick mode: procedural scenes only, small sizes; numbers show the tool works, not results");
  else if (!o.data_found) s.note("no shared data at " + o.data + ": body_hm08 parts skipped");
  char host[256] = "";
  gethostname(host, sizeof host - 1);
  struct utsname un;
  uname(&un);
  s.set("machine", std::string(host) + ", " + un.sysname + " " + un.release + ", " + cpuModel() + ", " +
                       std::to_string(sysconf(_SC_NPROCESSORS_ONLN)) + " cores online");
  const std::time_t t = std::time(nullptr);
  char date[64];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M:%S UTC", std::gmtime(&t));
  s.set("date", std::string(date));
  s.set("sections", only);
  s.set("load_average_start", loadAverage());

  const double t0 = eval::now();
  auto want = [&](const char* name) { return ("," + only + ",").find(std::string(",") + name + ",") != std::string::npos; };
  struct Section {
    const char* name;
    void (*run)(const eval::Options&);
  };
  const Section sections[] = {{"resolver", eval::resolverSection}, {"drape", eval::drapeSection},
                              {"stability", eval::stabilitySection}, {"extreme", eval::extremeSection},
                              {"lean", eval::leanSection}};
  for (const Section& sec : sections) {
    if (!want(sec.name)) continue;
    const double ts = eval::now();
    sec.run(o);
    s.set(std::string("seconds.") + sec.name, eval::now() - ts);
  }
  s.set("seconds.total", eval::now() - t0);
  s.set("load_average_end", loadAverage());
  if (!s.write(o.out + "/summary.json")) return usage("cannot write summary.json");
  std::printf("%s\n", o.out.c_str());
  return 0;
}
