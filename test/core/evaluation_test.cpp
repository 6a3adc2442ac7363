// The evaluation tool keeps working: the quick evaluation (procedural scenes, a few seconds) writes
// every file, its key invariants hold, and the plotting script turns it into PNGs and report.md.
#include "test_helpers.h"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <string>
#include <vector>

using virtual_tryon_test::readText;

namespace {

bool exists(const std::string& path) {
  struct stat st;
  return stat(path.c_str(), &st) == 0 && st.st_size > 0;
}

int run(const std::string& cmd) {
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// A CSV file as rows of named cells (quoted cells may hold commas and doubled quotes).
std::vector<std::map<std::string, std::string>> readCsv(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  auto split = [](const std::string& l) {
    std::vector<std::string> cells(1);
    bool quoted = false;
    for (std::size_t i = 0; i < l.size(); ++i) {
      const char c = l[i];
      if (quoted) {
        if (c == '"' && i + 1 < l.size() && l[i + 1] == '"') {
          cells.back() += '"';
          ++i;
        } else if (c == '"') {
          quoted = false;
        } else {
          cells.back() += c;
        }
      } else if (c == '"') {
        quoted = true;
      } else if (c == ',') {
        cells.emplace_back();
      } else {
        cells.back() += c;
      }
    }
    return cells;
  };
  std::vector<std::map<std::string, std::string>> rows;
  if (!std::getline(in, line)) return rows;
  const std::vector<std::string> header = split(line);
  while (std::getline(in, line)) {
    const std::vector<std::string> cells = split(line);
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < header.size() && i < cells.size(); ++i) row[header[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

}  // namespace

TEST(Evaluation, QuickRunWritesTheReportAndItsInvariantsHold) {
  std::string tmpl = ::testing::TempDir() + "vt_evaluation_XXXXXX";
  ASSERT_NE(mkdtemp(&tmpl[0]), nullptr);
  const std::string out = tmpl;
  const std::string cmd = std::string(VIRTUAL_TRYON_EVALUATE) + " --quick --patterns " + VIRTUAL_TRYON_SOURCE_DIR +
                          "/config/patterns --out " + out + " >/dev/null 2>" + out + "/stderr.txt";
  ASSERT_EQ(run(cmd), 0) << readText(out + "/stderr.txt");

  for (const char* f : {"summary.json", "resolver_trace.csv", "resolver_table.csv", "drape_map_size.csv",
                        "drape_modes.csv", "drape_spacing.csv", "drape_dt.csv", "stability_cloth.csv",
                        "stability_edges.csv", "stability_zones.csv", "stability_scene_zones.csv", "extreme.csv",
                        "lean_calls.csv", "lean_few.csv"})
    EXPECT_TRUE(exists(out + "/" + f)) << f;

  const std::string summary = readText(out + "/summary.json");
  for (const char* key : {"\"resolver.ours_clean_all_procedural\": true",
                          "\"stability.automatic_dt_stable_in_every_cell\": true",
                          "\"stability.paper_bound_unstable_somewhere\": true",
                          "\"stability.zone_solves_finite_and_bounded\": true", "\"extreme.no_crash_no_hang\": true",
                          "\"lean.clean_garment_zero_iterations\": true",
                          "\"lean.drape_map_renders_after_two_drapes\": 1"})
    EXPECT_NE(summary.find(key), std::string::npos) << key << "\n" << summary;

  // Our resolver leaves nothing by the independent count on every procedural scene; the push-out
  // baseline leaves crossings somewhere (it tests no edge).
  const auto table = readCsv(out + "/resolver_table.csv");
  ASSERT_GE(table.size(), 9u);
  std::size_t pushOutLeft = 0;
  for (const auto& r : table) {
    if (r.at("method") == "ours") {
      EXPECT_EQ(r.at("garment_edge_after"), "0") << r.at("scene");
      EXPECT_EQ(r.at("body_edge_after"), "0") << r.at("scene");
      EXPECT_EQ(r.at("inside_after"), "0") << r.at("scene");
      EXPECT_EQ(r.at("converged"), "1") << r.at("scene");
    }
    if (r.at("method") == "push_out")
      pushOutLeft += std::stoul(r.at("garment_edge_after")) + std::stoul(r.at("body_edge_after"));
  }
  EXPECT_GT(pushOutLeft, 0u);
  // The automatic dt is stable in every stiffness cell; the measured edge lies between it and the
  // paper's bound.
  for (const auto& r : readCsv(out + "/stability_cloth.csv")) {
    if (r.at("automatic") == "1") {
      EXPECT_EQ(r.at("stable"), "1") << r.at("k_over_m_per_s2");
    }
  }
  for (const auto& r : readCsv(out + "/stability_edges.csv")) {
    EXPECT_GT(std::stod(r.at("measured_edge_factor")), std::stod(r.at("automatic_factor")));
    EXPECT_LT(std::stod(r.at("measured_edge_factor")), 1.0);
  }
  // Every extreme case ran to an answer: converged, or not converged with a reason.
  const auto extreme = readCsv(out + "/extreme.csv");
  EXPECT_GE(extreme.size(), 15u);
  for (const auto& r : extreme) {
    EXPECT_EQ(r.at("status"), "ok") << r.at("case");
    EXPECT_FALSE(r.at("reason").empty()) << r.at("case");
    if (r.at("case") == "inverted_body") {
      EXPECT_EQ(r.at("converged"), "0");
    }
  }

  // The plots and the report, when Debian's matplotlib is there (it is installed by setup.sh).
  if (run("/usr/bin/python3 -c 'import matplotlib' >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "no /usr/bin/python3 with matplotlib: plots not checked";
  }
  ASSERT_EQ(run("/usr/bin/python3 " + std::string(VIRTUAL_TRYON_SOURCE_DIR) + "/scripts/plot_evaluation.py " + out +
                " >/dev/null 2>" + out + "/plot_stderr.txt"),
            0)
      << readText(out + "/plot_stderr.txt");
  const std::string report = readText(out + "/report.md");
  ASSERT_FALSE(report.empty());
  for (const char* section : {"## 1. Resolver", "## 2. Drape", "## 3. Stability", "## 4. Extreme", "## 5. Leaving out"})
    EXPECT_NE(report.find(section), std::string::npos) << section;
  // Every image the report shows exists.
  std::size_t images = 0;
  for (std::size_t p = report.find("]("); p != std::string::npos; p = report.find("](", p + 2)) {
    const std::size_t end = report.find(')', p);
    const std::string name = report.substr(p + 2, end - p - 2);
    EXPECT_TRUE(exists(out + "/" + name)) << name;
    ++images;
  }
  EXPECT_GE(images, 10u);
}
