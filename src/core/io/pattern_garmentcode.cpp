// GarmentCode's pattern specification JSON read into a Pattern (see the header for the rules).
#include "virtual_tryon/core/io/pattern_garmentcode.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

namespace virtual_tryon {

namespace {

using Json = nlohmann::ordered_json;  // keeps the panels in the file's order

constexpr double kPi = 3.14159265358979323846;
constexpr double kMaxGatherRatio = 2.0;  // validatePattern's length ratio for these patterns
constexpr std::size_t kMaxSpecificationBytes = std::size_t(64) << 20;

struct ReadError {
  std::string message;
};

[[noreturn]] void fail(const std::string& message) { throw ReadError{message}; }

std::string kind(const Json& j) {
  if (j.is_null()) return "null";
  if (j.is_boolean()) return "a boolean";
  if (j.is_number()) return "a number";
  if (j.is_string()) return "a string";
  if (j.is_array()) return "a list of " + std::to_string(j.size());
  return "an object";
}

double number(const Json& j, const std::string& where) {
  if (!j.is_number()) fail(where + ": expected a number, got " + kind(j));
  const double v = j.get<double>();
  if (!std::isfinite(v)) fail(where + ": not a finite number");
  return v;
}

int index(const Json& j, const std::string& where) {
  if (!j.is_number_integer()) fail(where + ": expected an integer index, got " + kind(j));
  const long long v = j.get<long long>();
  if (v < 0 || v > (1 << 30)) fail(where + ": index " + std::to_string(v) + " out of range");
  return int(v);
}

Eigen::Vector2d pair(const Json& j, const std::string& where) {
  if (!j.is_array() || j.size() != 2) fail(where + ": expected a pair [x, y], got " + kind(j));
  return {number(j[0], where + "[0]"), number(j[1], where + "[1]")};
}

Eigen::Vector3d triple(const Json& j, const std::string& where) {
  if (!j.is_array() || j.size() != 3) fail(where + ": expected [x, y, z], got " + kind(j));
  return {number(j[0], where + "[0]"), number(j[1], where + "[1]"), number(j[2], where + "[2]")};
}

bool flag(const Json& j, const std::string& where) {
  if (j.is_boolean()) return j.get<bool>();
  if (j.is_number_integer() && (j.get<long long>() == 0 || j.get<long long>() == 1)) return j.get<long long>() == 1;
  fail(where + ": expected 0, 1, true or false, got " + kind(j));
}

struct PanelIn {
  std::string name;
  std::vector<Eigen::Vector2d> vertices;   // panel units
  std::vector<GarmentCodeEdge> edges;      // loop order as in the file
  std::vector<int> edge_start;             // vertex index each edge starts at
  Eigen::Vector3d translation = Eigen::Vector3d::Zero(), rotation = Eigen::Vector3d::Zero();
  std::vector<int> segments;               // per edge, samples - 1
  std::vector<int> first_node;             // per edge, the outline index of its start
  int outline_points = 0;
};

std::string edgeName(const PanelIn& p, int e) { return "panel '" + p.name + "' edge " + std::to_string(e); }

void readCurvature(const Json& c, bool relative, PanelIn& p, GarmentCodeEdge& e, int ei,
                   std::vector<std::string>& warnings) {
  const std::string where = edgeName(p, ei) + ": curvature";
  auto point = [&](const Json& j, const std::string& w) {
    const Eigen::Vector2d v = pair(j, w);
    return relative ? garmentCodeRelativeToAbsolute(e.start, e.end, v) : v;
  };
  if (c.is_array()) {  // the first dataset's bare quadratic control point
    e.type = GarmentCodeEdge::Type::Quadratic;
    e.control[0] = point(c, where);
    return;
  }
  if (!c.is_object()) fail(where + ": expected an object {type, params}, got " + kind(c));
  if (!c.contains("type") || !c["type"].is_string()) fail(where + ".type: missing or not a string");
  if (!c.contains("params") || !c["params"].is_array()) fail(where + ".params: missing or not a list");
  const std::string type = c["type"].get<std::string>();
  const Json& params = c["params"];
  auto expect = [&](std::size_t n) {
    if (params.size() != n)
      fail(where + ".params: a " + type + " curve takes " + std::to_string(n) + " values, got " +
           std::to_string(params.size()));
  };
  if (type == "quadratic") {
    expect(1);
    e.type = GarmentCodeEdge::Type::Quadratic;
    e.control[0] = point(params[0], where + ".params[0]");
  } else if (type == "cubic") {
    expect(2);
    e.type = GarmentCodeEdge::Type::Cubic;
    e.control[0] = point(params[0], where + ".params[0]");
    e.control[1] = point(params[1], where + ".params[1]");
  } else if (type == "circle") {
    expect(3);
    e.type = GarmentCodeEdge::Type::Circle;
    e.radius = number(params[0], where + ".params[0] (radius)");
    if (!(e.radius > 0)) fail(where + ".params[0] (radius): must be > 0, got " + std::to_string(e.radius));
    e.large_arc = flag(params[1], where + ".params[1] (large arc)");
    e.right = flag(params[2], where + ".params[2] (right)");
    const double halfChord = 0.5 * (e.end - e.start).norm();
    if (e.radius < halfChord * (1 - 1e-9))
      warnings.push_back(where + ": radius " + std::to_string(e.radius) + " is shorter than half the chord (" +
                         std::to_string(halfChord) + "): drawn as a half circle, as SVG does");
  } else {
    fail(where + ".type: '" + type + "' is not one of quadratic, cubic, circle");
  }
}

PanelIn readPanel(const std::string& name, const Json& j, bool relative, std::vector<std::string>& warnings) {
  PanelIn p;
  p.name = name;
  const std::string where = "panel '" + name + "'";
  if (!j.is_object()) fail(where + ": expected an object, got " + kind(j));
  if (!j.contains("vertices") || !j["vertices"].is_array()) fail(where + ".vertices: missing or not a list");
  if (!j.contains("edges") || !j["edges"].is_array()) fail(where + ".edges: missing or not a list");
  const Json& V = j["vertices"];
  const Json& E = j["edges"];
  if (V.size() > kMaxOutlinePoints || E.size() > kMaxOutlinePoints)
    fail(where + ": more than " + std::to_string(kMaxOutlinePoints) + " vertices or edges");
  if (V.size() < 2 || E.size() < 2) fail(where + ": needs at least 2 vertices and 2 edges");
  for (std::size_t i = 0; i < V.size(); ++i) p.vertices.push_back(pair(V[i], where + ".vertices[" + std::to_string(i) + "]"));
  if (j.contains("translation")) p.translation = triple(j["translation"], where + ".translation");
  if (j.contains("rotation")) p.rotation = triple(j["rotation"], where + ".rotation");
  std::vector<int> used(V.size(), 0);
  for (std::size_t ei = 0; ei < E.size(); ++ei) {
    const Json& ej = E[ei];
    const std::string ew = edgeName(p, int(ei));
    if (!ej.is_object()) fail(ew + ": expected an object, got " + kind(ej));
    if (!ej.contains("endpoints") || !ej["endpoints"].is_array() || ej["endpoints"].size() != 2)
      fail(ew + ".endpoints: missing or not a pair of vertex indices");
    const int a = index(ej["endpoints"][0], ew + ".endpoints[0]");
    const int b = index(ej["endpoints"][1], ew + ".endpoints[1]");
    for (int v : {a, b})
      if (v >= int(V.size()))
        fail(ew + ".endpoints: vertex " + std::to_string(v) + " out of range (the panel has " +
             std::to_string(V.size()) + " vertices)");
    if (a == b) fail(ew + ".endpoints: starts and ends at vertex " + std::to_string(a));
    GarmentCodeEdge e;
    e.start = p.vertices[a];
    e.end = p.vertices[b];
    if (ej.contains("curvature")) readCurvature(ej["curvature"], relative, p, e, int(ei), warnings);
    p.edges.push_back(e);
    p.edge_start.push_back(a);
    ++used[a];
    if (ei > 0 && E[ei - 1]["endpoints"][1].get<long long>() != a)
      fail(ew + ".endpoints: starts at vertex " + std::to_string(a) + ", not where edge " + std::to_string(ei - 1) +
           " ends: the edges must form one loop in order");
  }
  if (E.back()["endpoints"][1].get<long long>() != p.edge_start.front())
    fail(edgeName(p, int(E.size()) - 1) + ".endpoints: the last edge must end where edge 0 starts");
  for (std::size_t v = 0; v < V.size(); ++v)
    if (used[v] != 1)
      fail(where + ".vertices[" + std::to_string(v) + "]: used by " + std::to_string(used[v]) +
           " edge starts, expected 1 (the edges must form one loop through every vertex)");
  return p;
}

struct StitchIn {
  int panel[2] = {-1, -1}, edge[2] = {-1, -1};
  bool right_wrong = false;
};

std::vector<StitchIn> readStitches(const Json& pattern, const std::map<std::string, int>& panelIndex,
                                   const std::vector<PanelIn>& panels) {
  std::vector<StitchIn> out;
  if (!pattern.contains("stitches")) return out;
  const Json& S = pattern["stitches"];
  if (!S.is_array()) fail("pattern.stitches: expected a list, got " + kind(S));
  if (S.size() > kMaxPatternSeams) fail("pattern.stitches: more than " + std::to_string(kMaxPatternSeams));
  std::map<std::pair<int, int>, int> sewn;
  for (std::size_t si = 0; si < S.size(); ++si) {
    const std::string where = "stitch " + std::to_string(si);
    const Json& s = S[si];
    if (!s.is_array() || s.size() < 2 || s.size() > 3)
      fail(where + ": expected [{panel, edge}, {panel, edge}] with an optional \"right_wrong\", got " + kind(s));
    StitchIn st;
    for (int side = 0; side < 2; ++side) {
      const std::string sw = where + " side " + std::to_string(side);
      const Json& j = s[side];
      if (!j.is_object() || !j.contains("panel") || !j["panel"].is_string() || !j.contains("edge"))
        fail(sw + ": expected {\"panel\": NAME, \"edge\": INDEX}, got " + kind(j));
      const std::string name = j["panel"].get<std::string>();
      const auto it = panelIndex.find(name);
      if (it == panelIndex.end()) fail(sw + ": no panel named '" + name + "'");
      const int e = index(j["edge"], sw + ".edge");
      if (e >= int(panels[it->second].edges.size()))
        fail(sw + ": panel '" + name + "' has no edge " + std::to_string(e) + " (it has " +
             std::to_string(panels[it->second].edges.size()) + ")");
      const auto key = std::make_pair(it->second, e);
      if (sewn.count(key))
        fail(sw + ": panel '" + name + "' edge " + std::to_string(e) + " is already sewn by stitch " +
             std::to_string(sewn[key]));
      sewn[key] = int(si);
      st.panel[side] = it->second;
      st.edge[side] = e;
    }
    if (s.size() == 3) {
      if (!s[2].is_string()) fail(where + "[2]: expected the string \"right_wrong\", got " + kind(s[2]));
      if (s[2].get<std::string>() != "right_wrong")
        fail(where + "[2]: '" + s[2].get<std::string>() + "' is not \"right_wrong\"");
      st.right_wrong = true;
    }
    out.push_back(st);
  }
  return out;
}

int segmentsFor(double length, double spacing) {
  return std::max(1, int(std::ceil(length / spacing - 1e-9)));
}

// Samples per edge: curved edges at <= spacing; both edges of a stitch get the longer one's count
// (a straight pair keeps one segment).
void chooseSegments(std::vector<PanelIn>& panels, const std::vector<StitchIn>& stitches, double spacingUnits) {
  for (PanelIn& p : panels) {
    p.segments.assign(p.edges.size(), 1);
    for (std::size_t e = 0; e < p.edges.size(); ++e)
      if (p.edges[e].type != GarmentCodeEdge::Type::Line) p.segments[e] = segmentsFor(edgeLength(p.edges[e]), spacingUnits);
  }
  for (const StitchIn& s : stitches) {
    int& a = panels[s.panel[0]].segments[s.edge[0]];
    int& b = panels[s.panel[1]].segments[s.edge[1]];
    a = b = std::max(a, b);
  }
  std::size_t total = 0;
  for (PanelIn& p : panels) {
    p.outline_points = 0;
    for (int k : p.segments) p.outline_points += k;
    if (p.outline_points > int(kMaxOutlinePoints))
      fail("panel '" + p.name + "': its outline sampled at the spacing has " + std::to_string(p.outline_points) +
           " points, more than " + std::to_string(kMaxOutlinePoints) + " (a larger spacing would do)");
    total += std::size_t(p.outline_points);
  }
  if (total > kMaxPatternOutlinePoints)
    fail("pattern: its outlines sampled at the spacing have " + std::to_string(total) + " points, more than " +
         std::to_string(kMaxPatternOutlinePoints));
}

PatternPanel buildPanel(PanelIn& p, double toMetres) {
  PatternPanel out;
  out.name = p.name;
  out.outline.resize(p.outline_points, 2);
  p.first_node.assign(p.edges.size(), 0);
  int row = 0;
  for (std::size_t e = 0; e < p.edges.size(); ++e) {
    p.first_node[e] = row;
    const MatrixX2d S = sampleEdge(p.edges[e], p.segments[e]);
    for (int k = 0; k < p.segments[e]; ++k) out.outline.row(row++) = S.row(k) * toMetres;
  }
  const Eigen::Matrix3d R = garmentCodeRotation(p.rotation);
  out.placement.pose = Eigen::Isometry3d::Identity();
  out.placement.pose.linear() = R;
  out.placement.pose.translation() = p.translation * toMetres;
  if (outlineSignedArea(out.outline) < 0) {  // mirror: same 3D points, counter-clockwise, same side out
    out.outline.col(0) *= -1;
    out.placement.pose.linear() = R * Eigen::Vector3d(-1, 1, -1).asDiagonal();
  }
  return out;
}

// The outline indices edge e of panel p walks through, start to end.
std::vector<int> edgeNodes(const PanelIn& p, int e) {
  std::vector<int> nodes;
  for (int k = 0; k <= p.segments[e]; ++k) nodes.push_back((p.first_node[e] + k) % p.outline_points);
  return nodes;
}

void addSeams(const std::vector<PanelIn>& panels, const StitchIn& s, Pattern& out, GarmentCodeStitch& report) {
  const PanelIn& pa = panels[s.panel[0]];
  const PanelIn& pb = panels[s.panel[1]];
  const std::vector<int> a = edgeNodes(pa, s.edge[0]);
  std::vector<int> b = edgeNodes(pb, s.edge[1]);
  if (!s.right_wrong) std::reverse(b.begin(), b.end());  // GarmentCode: start of one meets end of the other
  const int k = int(a.size()) - 1;
  // Pieces shorter than half of either outline (a stretch walks the shorter way round).
  const int limit = std::min(pa.outline_points, pb.outline_points);
  int pieces = 1;
  while (2 * ((k + pieces - 1) / pieces) >= limit && pieces < k) ++pieces;
  for (int q = 0; q < pieces; ++q) {
    const int j0 = int(std::lround(double(q) * k / pieces)), j1 = int(std::lround(double(q + 1) * k / pieces));
    PatternSeam seam;
    seam.a = {s.panel[0], a[j0], a[j1]};
    seam.b = {s.panel[1], b[j0], b[j1]};
    report.seams.push_back(int(out.seams.size()));
    out.seams.push_back(seam);
  }
  report.segments = k;
}

void parse(const std::string& text, const GarmentCodeReadParams& params, Pattern& out, GarmentCodeReport& report) {
  if (!(params.spacing > 0) || !std::isfinite(params.spacing)) fail("spacing: must be > 0 metres");
  if (text.size() > kMaxSpecificationBytes)
    fail("the specification is " + std::to_string(text.size()) + " bytes, more than " +
         std::to_string(kMaxSpecificationBytes));
  Json root;
  try {
    root = Json::parse(text);
  } catch (const Json::parse_error& e) {
    fail(std::string("not valid JSON: ") + e.what());
  }
  if (!root.is_object()) fail("expected a JSON object at the top, got " + kind(root));
  bool relative = true;
  if (root.contains("properties")) {
    const Json& props = root["properties"];
    if (!props.is_object()) fail("properties: expected an object, got " + kind(props));
    if (props.contains("units_in_meter")) {
      report.units_in_meter = number(props["units_in_meter"], "properties.units_in_meter");
      if (!(report.units_in_meter > 0)) fail("properties.units_in_meter: must be > 0");
    } else {
      report.warnings.push_back("properties.units_in_meter: missing, centimetres assumed (100)");
    }
    if (props.contains("curvature_coords")) {
      const Json& c = props["curvature_coords"];
      if (!c.is_string() || (c.get<std::string>() != "relative" && c.get<std::string>() != "absolute"))
        fail("properties.curvature_coords: expected \"relative\" or \"absolute\", got " + kind(c));
      relative = c.get<std::string>() == "relative";
    }
  }
  if (!root.contains("pattern") || !root["pattern"].is_object()) fail("pattern: missing or not an object");
  const Json& pattern = root["pattern"];
  if (!pattern.contains("panels") || !pattern["panels"].is_object() || pattern["panels"].empty())
    fail("pattern.panels: missing, empty or not an object of named panels");
  const Json& P = pattern["panels"];
  if (P.size() > kMaxPatternPanels) fail("pattern.panels: more than " + std::to_string(kMaxPatternPanels) + " panels");
  std::vector<PanelIn> panels;
  std::map<std::string, int> panelIndex;
  for (auto it = P.begin(); it != P.end(); ++it) {
    panelIndex[it.key()] = int(panels.size());
    panels.push_back(readPanel(it.key(), it.value(), relative, report.warnings));
  }
  const std::vector<StitchIn> stitches = readStitches(pattern, panelIndex, panels);
  const double toMetres = 1.0 / report.units_in_meter;
  chooseSegments(panels, stitches, params.spacing / toMetres);

  Pattern result;
  for (PanelIn& p : panels) {
    result.panels.push_back(buildPanel(p, toMetres));
    report.panel_names.push_back(p.name);
  }
  for (const StitchIn& s : stitches) {
    GarmentCodeStitch st;
    st.panel_a = panels[s.panel[0]].name;
    st.panel_b = panels[s.panel[1]].name;
    st.edge_a = s.edge[0];
    st.edge_b = s.edge[1];
    st.right_wrong = s.right_wrong;
    st.length_a = edgeLength(panels[s.panel[0]].edges[s.edge[0]]) * toMetres;
    st.length_b = edgeLength(panels[s.panel[1]].edges[s.edge[1]]) * toMetres;
    addSeams(panels, s, result, st);
    const double longer = std::max(st.length_a, st.length_b), shorter = std::min(st.length_a, st.length_b);
    if (longer > params.warn_length_ratio * shorter) {
      std::ostringstream w;
      w << "stitch " << report.stitches.size() << ": panel '" << st.panel_a << "' edge " << st.edge_a << " is "
        << st.length_a * 100 << " cm long and panel '" << st.panel_b << "' edge " << st.edge_b << " "
        << st.length_b * 100 << " cm: the seam takes in " << (longer - shorter) * 100 << " cm";
      report.warnings.push_back(w.str());
    }
    report.stitches.push_back(st);
  }
  const std::string problem = validatePattern(result, kMaxGatherRatio);
  if (!problem.empty()) fail(problem);
  out = std::move(result);
}

}  // namespace

bool parseGarmentCodeJson(const std::string& text, const GarmentCodeReadParams& params, Pattern& pattern,
                          GarmentCodeReport& report, std::string& error) {
  GarmentCodeReport r;
  Pattern p;
  try {
    parse(text, params, p, r);
  } catch (const ReadError& e) {
    error = e.message;
    return false;
  } catch (const std::exception& e) {  // a JSON accessor on an unexpected type: a malformed file
    error = std::string("malformed pattern specification: ") + e.what();
    return false;
  }
  pattern = std::move(p);
  report = std::move(r);
  error.clear();
  return true;
}

bool readGarmentCodeJson(const std::string& path, const GarmentCodeReadParams& params, Pattern& pattern,
                         GarmentCodeReport& report, std::string& error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = path + ": cannot open";
    return false;
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (!parseGarmentCodeJson(text.str(), params, pattern, report, error)) {
    error = path + ": " + error;
    return false;
  }
  if (pattern.name.empty()) {
    std::string stem = path.substr(path.find_last_of('/') + 1);
    stem = stem.substr(0, stem.find_last_of('.'));
    const std::string suffix = "_specification";
    if (stem.size() > suffix.size() && stem.compare(stem.size() - suffix.size(), suffix.size(), suffix) == 0)
      stem.resize(stem.size() - suffix.size());
    pattern.name = stem;
  }
  return true;
}

Eigen::Matrix3d garmentCodeRotation(const Eigen::Vector3d& degrees) {
  const Eigen::Vector3d a = degrees * kPi / 180;
  return (Eigen::AngleAxisd(a.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(a.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(a.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

bool looksLikeJson(const std::string& text) {
  for (char c : text) {
    if (c == ' ' || c == '\t' || c == '\n' || c == '\r') continue;
    return c == '{';
  }
  return false;
}

}  // namespace virtual_tryon
