// The YAML pattern format (config/patterns/README.md): reading with key-path errors, writing.
#include "virtual_tryon/core/io/pattern_yaml.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <initializer_list>
#include <map>
#include <sstream>

namespace virtual_tryon {

namespace {

std::string where(const YAML::Node& node) {
  const YAML::Mark m = node.Mark();
  if (m.is_null() || m.line < 0) return "";
  return " (line " + std::to_string(m.line + 1) + ", column " + std::to_string(m.column + 1) + ")";
}

std::string describe(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Undefined:
    case YAML::NodeType::Null: return "nothing";
    case YAML::NodeType::Scalar: {
      const std::string& text = node.Scalar();
      return "'" + (text.size() > 40 ? text.substr(0, 37) + "..." : text) + "'";
    }
    case YAML::NodeType::Sequence: return "a list of " + std::to_string(node.size()) + " item" + (node.size() == 1 ? "" : "s");
    case YAML::NodeType::Map: return "a map";
  }
  return "something else";
}

std::string quoteList(std::initializer_list<const char*> keys) {
  std::string s;
  for (const char* k : keys) s += (s.empty() ? "" : ", ") + std::string(k);
  return s;
}

class Reader {
 public:
  std::string error;

  bool fail(const std::string& path, const YAML::Node& node, const std::string& message) {
    error = path + ": " + message + where(node);
    return false;
  }

  // A map whose keys are all in `allowed` (no duplicates) and include every one of `required`.
  bool checkMap(const YAML::Node& node, const std::string& path, std::initializer_list<const char*> allowed,
                std::initializer_list<const char*> required) {
    if (!node.IsMap()) return fail(path, node, "expected a map with keys " + quoteList(allowed) + ", got " + describe(node));
    std::map<std::string, int> seen;
    for (const auto& kv : node) {
      if (!kv.first.IsScalar()) return fail(path, kv.first, "expected keys to be plain names, got " + describe(kv.first));
      const std::string key = kv.first.Scalar();
      bool ok = false;
      for (const char* a : allowed) ok = ok || key == a;
      if (!ok) return fail(path, kv.first, "unknown key '" + key + "' (expected " + quoteList(allowed) + ")");
      if (seen[key]++ > 0) return fail(path, kv.first, "duplicate key '" + key + "'");
    }
    for (const char* r : required)
      if (!seen.count(r)) return fail(path, node, "missing key '" + std::string(r) + "'");
    return true;
  }

  bool number(const YAML::Node& node, const std::string& path, double& out) {
    if (!node.IsScalar()) return fail(path, node, "expected a number, got " + describe(node));
    try {
      out = node.as<double>();
    } catch (const YAML::Exception&) {
      return fail(path, node, "expected a number, got " + describe(node));
    }
    if (!std::isfinite(out)) return fail(path, node, "expected a finite number, got " + describe(node));
    return true;
  }

  bool integer(const YAML::Node& node, const std::string& path, const std::string& what, int& out) {
    if (node.IsScalar()) {
      try {
        out = node.as<int>();
        return true;
      } catch (const YAML::Exception&) {
      }
    }
    return fail(path, node, "expected " + what + ", got " + describe(node));
  }

  // A list of exactly `n` numbers; `what` describes it ("a pair of numbers [u, v]").
  bool numbers(const YAML::Node& node, const std::string& path, int n, const std::string& what, double* out) {
    if (!node.IsSequence() || static_cast<int>(node.size()) != n)
      return fail(path, node, "expected " + what + ", got " + describe(node));
    for (int k = 0; k < n; ++k)
      if (!number(node[static_cast<std::size_t>(k)], path + "[" + std::to_string(k) + "]", out[k])) return false;
    return true;
  }

  bool placement(const YAML::Node& node, const std::string& path, PanelPlacement& pl) {
    if (!checkMap(node, path, {"translation", "rotation_rpy", "rotation_quaternion", "wrap_radius"}, {})) return false;
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    if (node["translation"] &&
        !numbers(node["translation"], path + ".translation", 3, "a list of 3 numbers [x, y, z] (metres)", t.data()))
      return false;
    if (node["rotation_rpy"] && node["rotation_quaternion"])
      return fail(path, node, "give either rotation_rpy or rotation_quaternion, not both");
    if (node["rotation_rpy"]) {
      double rpy[3];
      if (!numbers(node["rotation_rpy"], path + ".rotation_rpy", 3, "a list of 3 numbers [roll, pitch, yaw] (radians)", rpy))
        return false;
      R = (Eigen::AngleAxisd(rpy[2], Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(rpy[1], Eigen::Vector3d::UnitY()) *
           Eigen::AngleAxisd(rpy[0], Eigen::Vector3d::UnitX()))
              .toRotationMatrix();
    }
    if (node["rotation_quaternion"]) {
      double q[4];
      const std::string qp = path + ".rotation_quaternion";
      if (!numbers(node["rotation_quaternion"], qp, 4, "a list of 4 numbers [x, y, z, w]", q)) return false;
      Eigen::Quaterniond quat(q[3], q[0], q[1], q[2]);
      if (!(quat.norm() > 1e-12)) return fail(qp, node["rotation_quaternion"], "the quaternion is zero");
      R = quat.normalized().toRotationMatrix();
    }
    double r = 0;
    if (node["wrap_radius"]) {
      if (!number(node["wrap_radius"], path + ".wrap_radius", r)) return false;
      if (r < 0)
        return fail(path + ".wrap_radius", node["wrap_radius"],
                    "expected a radius >= 0 (0: flat), got " + describe(node["wrap_radius"]));
    }
    pl.pose = Eigen::Isometry3d::Identity();
    pl.pose.linear() = R;
    pl.pose.translation() = t;
    pl.wrap_radius = r;
    return true;
  }

  bool panel(const YAML::Node& node, const std::string& path, PatternPanel& panel) {
    if (!checkMap(node, path, {"name", "outline", "placement"}, {"name", "outline"})) return false;
    const YAML::Node name = node["name"];
    if (!name.IsScalar() || name.Scalar().empty())
      return fail(path + ".name", name, "expected a non-empty panel name, got " + describe(name));
    panel.name = name.Scalar();
    const YAML::Node outline = node["outline"];
    const std::string op = path + ".outline";
    if (!outline.IsSequence())
      return fail(op, outline, "expected a list of [u, v] points (metres, counter-clockwise), got " + describe(outline));
    if (outline.size() > kMaxOutlinePoints)
      return fail(op, outline, "the outline has " + std::to_string(outline.size()) + " points, more than the limit of " +
                                   std::to_string(kMaxOutlinePoints));
    panel.outline.resize(static_cast<Eigen::Index>(outline.size()), 2);
    for (std::size_t i = 0; i < outline.size(); ++i) {
      double uv[2];
      if (!numbers(outline[i], op + "[" + std::to_string(i) + "]", 2, "a pair of numbers [u, v]", uv)) return false;
      panel.outline(static_cast<Eigen::Index>(i), 0) = uv[0];
      panel.outline(static_cast<Eigen::Index>(i), 1) = uv[1];
    }
    if (outline.size() < 3)
      return fail(op, outline, "expected at least 3 points, got " + std::to_string(outline.size()));
    panel.placement = PanelPlacement();
    if (node["placement"] && !placement(node["placement"], path + ".placement", panel.placement)) return false;
    return true;
  }

  bool stretch(const YAML::Node& node, const std::string& path, const Pattern& pattern, OutlineStretch& s) {
    if (!checkMap(node, path, {"panel", "from", "to"}, {"panel", "from", "to"})) return false;
    const YAML::Node ref = node["panel"];
    const int np = static_cast<int>(pattern.panels.size());
    if (!ref.IsScalar()) return fail(path + ".panel", ref, "expected a panel name or index, got " + describe(ref));
    s.panel = -1;
    for (int p = 0; p < np && s.panel < 0; ++p)
      if (pattern.panels[static_cast<std::size_t>(p)].name == ref.Scalar()) s.panel = p;
    if (s.panel < 0) {
      int index = 0;
      bool isIndex = false;
      try {
        index = ref.as<int>();
        isIndex = true;
      } catch (const YAML::Exception&) {
      }
      if (!isIndex) {
        std::string names;
        for (const PatternPanel& p : pattern.panels) names += (names.empty() ? "'" : ", '") + p.name + "'";
        return fail(path + ".panel", ref, "unknown panel '" + ref.Scalar() + "' (panels: " + names + ")");
      }
      if (index < 0 || index >= np)
        return fail(path + ".panel", ref,
                    "panel index " + std::to_string(index) + " is out of range (the pattern has " + std::to_string(np) +
                        " panel" + (np == 1 ? "" : "s") + ", 0.." + std::to_string(np - 1) + ")");
      s.panel = index;
    }
    const PatternPanel& panel = pattern.panels[static_cast<std::size_t>(s.panel)];
    const int n = static_cast<int>(panel.outline.rows());
    for (const char* key : {"from", "to"}) {
      int& v = std::string(key) == "from" ? s.from : s.to;
      const std::string kp = path + "." + key;
      if (!integer(node[key], kp, "an outline point index (a whole number)", v)) return false;
      if (v < 0 || v >= n)
        return fail(kp, node[key],
                    "outline point " + std::to_string(v) + " is out of range for panel '" + panel.name + "' (" +
                        std::to_string(n) + " points, 0.." + std::to_string(n - 1) + ")");
    }
    if (s.from == s.to)
      return fail(path, node, "from == to (" + std::to_string(s.from) + "); a stretch needs two distinct outline points");
    return true;
  }

  bool pattern(const YAML::Node& root, Pattern& out) {
    if (!checkMap(root, "pattern", {"name", "panels", "seams"}, {"panels"})) return false;
    if (root["name"]) {
      if (!root["name"].IsScalar()) return fail("name", root["name"], "expected a pattern name, got " + describe(root["name"]));
      out.name = root["name"].Scalar();
    }
    const YAML::Node panels = root["panels"];
    if (!panels.IsSequence()) return fail("panels", panels, "expected a list of panels, got " + describe(panels));
    if (panels.size() == 0) return fail("panels", panels, "the list is empty; a pattern needs at least one panel");
    if (panels.size() > kMaxPatternPanels)
      return fail("panels", panels, "the pattern has " + std::to_string(panels.size()) + " panels, more than the limit of " +
                                        std::to_string(kMaxPatternPanels));
    for (std::size_t i = 0; i < panels.size(); ++i) {
      const std::string pp = "panels[" + std::to_string(i) + "]";
      PatternPanel p;
      if (!panel(panels[i], pp, p)) return false;
      for (std::size_t j = 0; j < out.panels.size(); ++j)
        if (out.panels[j].name == p.name)
          return fail(pp + ".name", panels[i]["name"],
                      "duplicate panel name '" + p.name + "' (also panels[" + std::to_string(j) + "])");
      out.panels.push_back(std::move(p));
    }
    if (root["seams"] && !root["seams"].IsNull()) {
      const YAML::Node seams = root["seams"];
      if (!seams.IsSequence()) return fail("seams", seams, "expected a list of seams, got " + describe(seams));
      if (seams.size() > kMaxPatternSeams)
        return fail("seams", seams, "the pattern has " + std::to_string(seams.size()) + " seams, more than the limit of " +
                                        std::to_string(kMaxPatternSeams));
      for (std::size_t k = 0; k < seams.size(); ++k) {
        const std::string sp = "seams[" + std::to_string(k) + "]";
        PatternSeam s;
        if (!checkMap(seams[k], sp, {"a", "b", "stage"}, {"a", "b"})) return false;
        if (!stretch(seams[k]["a"], sp + ".a", out, s.a) || !stretch(seams[k]["b"], sp + ".b", out, s.b)) return false;
        if (seams[k]["stage"]) {
          if (!integer(seams[k]["stage"], sp + ".stage", "a sewing stage (a whole number >= 0)", s.stage)) return false;
          if (s.stage < 0) return fail(sp + ".stage", seams[k]["stage"], "a sewing stage must be >= 0");
        }
        out.seams.push_back(s);
      }
    }
    error = validatePattern(out);
    return error.empty();
  }
};

// Shortest decimal that reads back as exactly `x`.
std::string number(double x) {
  if (x == 0) return "0";
  char buf[40];
  for (int precision = 15; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*g", precision, x);
    if (std::strtod(buf, nullptr) == x) break;
  }
  return buf;
}

std::string list(std::initializer_list<double> xs) {
  std::string s = "[";
  for (double x : xs) s += (s.size() > 1 ? ", " : "") + number(x);
  return s + "]";
}

// A plain YAML scalar when it is safe, else double-quoted with escapes.
std::string scalar(const std::string& s) {
  bool plain = !s.empty() && s.back() != ' ' && s != "null" && s != "Null" && s != "NULL";
  for (std::size_t i = 0; i < s.size() && plain; ++i) {
    const char c = s[i];
    const bool alnum = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
    plain = alnum || (i > 0 && (c == '.' || c == '-' || c == ' '));
  }
  if (plain) return s;
  std::string q = "\"";
  for (unsigned char c : s) {
    if (c == '"' || c == '\\') {
      q += '\\';
      q += static_cast<char>(c);
    } else if (c < 0x20 || c == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      q += buf;
    } else {
      q += static_cast<char>(c);
    }
  }
  return q + "\"";
}

}  // namespace

bool parsePatternYaml(const std::string& text, Pattern& pattern, std::string& error) {
  error.clear();
  try {
    YAML::Node root;
    try {
      root = YAML::Load(text);
    } catch (const YAML::ParserException& e) {
      error = "YAML syntax error at line " + std::to_string(e.mark.line + 1) + ", column " +
              std::to_string(e.mark.column + 1) + ": " + e.msg;
      return false;
    }
    Reader reader;
    Pattern result;
    if (!reader.pattern(root, result)) {
      error = reader.error;
      return false;
    }
    pattern = std::move(result);
    return true;
  } catch (const YAML::Exception& e) {
    error = std::string("YAML error: ") + e.what();
  } catch (const std::exception& e) {
    error = std::string("error reading the pattern: ") + e.what();
  } catch (...) {
    error = "unknown error reading the pattern";
  }
  return false;
}

bool readPatternYaml(const std::string& path, Pattern& pattern, std::string& error) {
  error.clear();
  try {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
      error = path + ": cannot open the pattern file";
      return false;
    }
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) {
      error = path + ": error reading the pattern file";
      return false;
    }
    if (!parsePatternYaml(text.str(), pattern, error)) {
      error = path + ": " + error;
      return false;
    }
    return true;
  } catch (const std::exception& e) {
    error = path + ": " + e.what();
  } catch (...) {
    error = path + ": unknown error reading the pattern file";
  }
  return false;
}

std::string patternToYaml(const Pattern& pattern) {
  std::ostringstream out;
  out << "# Garment pattern (virtual_tryon); format: config/patterns/README.md\n";
  out << "name: " << (pattern.name.empty() ? "\"\"" : scalar(pattern.name)) << "\n";
  out << "panels:\n";
  for (const PatternPanel& p : pattern.panels) {
    out << "  - name: " << (p.name.empty() ? "\"\"" : scalar(p.name)) << "\n";
    out << "    outline: [";
    for (Eigen::Index i = 0; i < p.outline.rows(); ++i)
      out << (i ? ", " : "") << list({p.outline(i, 0), p.outline(i, 1)});
    out << "]\n";
    const Eigen::Vector3d t = p.placement.pose.translation();
    const Eigen::Matrix3d R = p.placement.pose.linear();
    const bool hasT = !t.isZero(0), hasR = !R.isIdentity(0), hasW = p.placement.wrap_radius != 0;
    if (!hasT && !hasR && !hasW) continue;
    out << "    placement:\n";
    if (hasT) out << "      translation: " << list({t.x(), t.y(), t.z()}) << "\n";
    if (hasR) {
      // Roll-pitch-yaw when it reads back to the same matrix (readable), else the quaternion.
      const double roll = std::atan2(R(2, 1), R(2, 2));
      const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
      const double yaw = std::atan2(R(1, 0), R(0, 0));
      const Eigen::Matrix3d back = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                                       .toRotationMatrix();
      if ((back - R).cwiseAbs().maxCoeff() <= 1e-15) {
        out << "      rotation_rpy: " << list({roll, pitch, yaw}) << "\n";
      } else {
        const Eigen::Quaterniond q(R);
        out << "      rotation_quaternion: " << list({q.x(), q.y(), q.z(), q.w()}) << "\n";
      }
    }
    if (hasW) out << "      wrap_radius: " << number(p.placement.wrap_radius) << "\n";
  }
  // Seams name panels by name when names are unique and non-empty, else by index.
  bool byName = true;
  for (std::size_t i = 0; i < pattern.panels.size(); ++i) {
    byName = byName && !pattern.panels[i].name.empty();
    for (std::size_t j = 0; j < i; ++j) byName = byName && pattern.panels[i].name != pattern.panels[j].name;
  }
  auto ref = [&](const OutlineStretch& s) {
    std::string panel = std::to_string(s.panel);
    if (byName && s.panel >= 0 && s.panel < static_cast<int>(pattern.panels.size()))
      panel = scalar(pattern.panels[static_cast<std::size_t>(s.panel)].name);
    return "{panel: " + panel + ", from: " + std::to_string(s.from) + ", to: " + std::to_string(s.to) + "}";
  };
  if (pattern.seams.empty()) {
    out << "seams: []\n";
  } else {
    out << "seams:\n";
    for (const PatternSeam& s : pattern.seams) {
      out << "  - a: " << ref(s.a) << "\n    b: " << ref(s.b) << "\n";
      if (s.stage != 0) out << "    stage: " << s.stage << "\n";
    }
  }
  return out.str();
}

}  // namespace virtual_tryon
