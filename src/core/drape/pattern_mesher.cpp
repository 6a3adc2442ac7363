// meshPattern: panels into regular grids of mass points (Vassilev et al. 2001, sec. 1 and 3),
// springs, triangles and seam pairs. The rules are spelled out in pattern.h.
#include "virtual_tryon/core/drape/pattern.h"

#include "core/drape/pattern_text.h"
#include "core/geometry/polygon2d.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <set>
#include <sstream>
#include <utility>

namespace virtual_tryon {

namespace {

using polygon2d::Vec2;

constexpr double kOnOutline = 1e-9;               // metres: a node this close counts as inside
constexpr double kMaxGridNodes = 2e7;             // per panel, before clipping
constexpr double kNearStretch = 0.75;             // * spacing: boundary nodes "near" a stretch

using pattern_text::num;
using pattern_text::panelLabel;

// Link bits stored at grid node (i, j).
enum : std::uint8_t { kLinkU = 1, kLinkV = 2 };

struct PanelGrid {
  int nx = 0, ny = 0;
  double x0 = 0, y0 = 0, h = 0;
  std::vector<char> kept, onOutline, used;
  std::vector<std::uint8_t> link;
  std::vector<int> node;  // global node index or -1
  bool convex = true;
  const MatrixX2d* outline = nullptr;

  int at(int i, int j) const { return j * nx + i; }
  Vec2 uv(int i, int j) const { return Vec2(x0 + i * h, y0 + j * h); }
  bool isUsed(int i, int j) const {
    return i >= 0 && j >= 0 && i < nx && j < ny && used[static_cast<std::size_t>(at(i, j))];
  }
  int id(int i, int j) const { return node[static_cast<std::size_t>(at(i, j))]; }  // global index or -1
  bool linked(int i, int j, std::uint8_t bit) const {
    return (link[static_cast<std::size_t>(at(i, j))] & bit) != 0;
  }

  // The segment between two kept grid nodes stays inside the outline.
  bool segmentInside(const Vec2& p, const Vec2& q) const {
    if (convex) return true;
    const MatrixX2d& P = *outline;
    const Eigen::Index n = P.rows();
    for (Eigen::Index e = 0; e < n; ++e)
      if (polygon2d::segmentsCross(p, q, polygon2d::point(P, e), polygon2d::point(P, (e + 1) % n), 1e-12))
        return false;
    return polygon2d::insideOrOn(Vec2(0.5 * (p + q)), P, kOnOutline);
  }
};

// Grid size of a panel at spacing h (nodes along u and v, before clipping); may be huge or inf.
void gridSize(const MatrixX2d& P, double h, double& cx, double& cy) {
  const Eigen::Vector2d lo = P.colwise().minCoeff().transpose(), hi = P.colwise().maxCoeff().transpose();
  const Eigen::Vector2d size = hi - lo;
  cx = std::floor(size.x() / h + 1e-9) + 1;
  cy = std::floor(size.y() / h + 1e-9) + 1;
}

// Grid nodes, links, quads of one panel (indices local to the grid). meshPattern has checked the
// grid's size (gridSize) before any grid is built.
bool buildGrid(const Pattern& pattern, int p, double h, PanelGrid& g, std::vector<std::array<int, 4>>& quads,
               std::string& error) {
  const MatrixX2d& P = pattern.panels[static_cast<std::size_t>(p)].outline;
  g.outline = &P;
  g.h = h;
  const Eigen::Vector2d lo = P.colwise().minCoeff().transpose(), hi = P.colwise().maxCoeff().transpose();
  const Eigen::Vector2d size = hi - lo;
  g.nx = static_cast<int>(std::floor(size.x() / h + 1e-9)) + 1;
  g.ny = static_cast<int>(std::floor(size.y() / h + 1e-9)) + 1;
  g.x0 = lo.x() + 0.5 * (size.x() - (g.nx - 1) * h);
  g.y0 = lo.y() + 0.5 * (size.y() - (g.ny - 1) * h);
  g.convex = polygon2d::isConvex(P);
  const std::size_t count = static_cast<std::size_t>(g.nx) * static_cast<std::size_t>(g.ny);
  g.kept.assign(count, 0);
  g.onOutline.assign(count, 0);
  g.used.assign(count, 0);
  g.link.assign(count, 0);
  g.node.assign(count, -1);

  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const Vec2 q = g.uv(i, j);
      const std::size_t k = static_cast<std::size_t>(g.at(i, j));
      if (polygon2d::distanceToOutline(q, P) <= kOnOutline) {
        g.onOutline[k] = 1;
        g.kept[k] = 1;
      } else {
        g.kept[k] = polygon2d::strictlyInside(q, P);
      }
    }
  auto kept = [&](int i, int j) { return g.kept[static_cast<std::size_t>(g.at(i, j))] != 0; };
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      if (!kept(i, j)) continue;
      std::uint8_t& l = g.link[static_cast<std::size_t>(g.at(i, j))];
      if (i + 1 < g.nx && kept(i + 1, j) && g.segmentInside(g.uv(i, j), g.uv(i + 1, j))) l |= kLinkU;
      if (j + 1 < g.ny && kept(i, j + 1) && g.segmentInside(g.uv(i, j), g.uv(i, j + 1))) l |= kLinkV;
    }
  auto link = [&](int i, int j) { return g.link[static_cast<std::size_t>(g.at(i, j))]; };
  for (int j = 0; j + 1 < g.ny; ++j)
    for (int i = 0; i + 1 < g.nx; ++i) {
      if ((link(i, j) & (kLinkU | kLinkV)) != (kLinkU | kLinkV)) continue;
      if (!(link(i + 1, j) & kLinkV) || !(link(i, j + 1) & kLinkU)) continue;
      quads.push_back({g.at(i, j), g.at(i + 1, j), g.at(i + 1, j + 1), g.at(i, j + 1)});
      for (int c : quads.back()) g.used[static_cast<std::size_t>(c)] = 1;
    }
  if (quads.empty()) {
    error = panelLabel(pattern, p) + ": no grid quad fits at spacing " + num(h) + " m (outline bounding box " +
            num(size.x()) + " x " + num(size.y()) + " m)";
    return false;
  }
  return true;
}

// Distance from p along the unit axis direction d to the first outline edge it meets, or
// infinity.
double rayToOutline(const Vec2& p, const Vec2& d, const MatrixX2d& P) {
  double best = INFINITY;
  const Eigen::Index n = P.rows();
  for (Eigen::Index e = 0; e < n; ++e) {
    const Vec2 a = polygon2d::point(P, e), b = polygon2d::point(P, (e + 1) % n);
    const Vec2 ab = b - a;
    const double den = polygon2d::cross(d, ab);
    if (std::abs(den) < 1e-15) continue;  // parallel: a neighbouring edge meets the ray instead
    const double t = polygon2d::cross(a - p, ab) / den;   // along the ray
    const double s = polygon2d::cross(a - p, d) / den;    // along the edge
    if (t > 0 && s >= -1e-12 && s <= 1 + 1e-12) best = std::min(best, t);
  }
  return best;
}

// Where a node goes in the flat panel: its grid point, moved out onto the outline along each
// grid axis on which it has no neighbour, when the outline lies less than two spacings away that
// way (a boundary node then sits on the cut edge instead of up to two spacings inside it).
Vec2 snappedUv(const PanelGrid& g, int i, int j) {
  Vec2 uv = g.uv(i, j);
  if (g.onOutline[static_cast<std::size_t>(g.at(i, j))]) return uv;
  const bool left = g.isUsed(i - 1, j) && g.linked(i - 1, j, kLinkU),
             right = g.isUsed(i + 1, j) && g.linked(i, j, kLinkU);
  const bool down = g.isUsed(i, j - 1) && g.linked(i, j - 1, kLinkV),
             up = g.isUsed(i, j + 1) && g.linked(i, j, kLinkV);
  auto push = [&](bool missing, const Vec2& d) -> Vec2 {
    if (!missing) return Vec2::Zero();
    const double t = rayToOutline(uv, d, *g.outline);
    // Under two spacings: the missing neighbour may be a kept node dropped for want of a quad.
    return t < 2 * g.h ? Vec2(t * d) : Vec2::Zero();
  };
  const Vec2 du = push(left != right, Vec2(left ? 1.0 : -1.0, 0.0));
  const Vec2 dv = push(down != up, Vec2(0.0, down ? 1.0 : -1.0));
  // A corner node moved both ways can land outside a slanted edge: then it moves one way only
  // (the longer move that stays inside), or stays.
  for (const Vec2& c : {Vec2(uv + du + dv), Vec2(uv + (du.norm() >= dv.norm() ? du : dv)),
                        Vec2(uv + (du.norm() >= dv.norm() ? dv : du))})
    if (polygon2d::insideOrOn(c, *g.outline, kOnOutline)) return c;
  return uv;
}

using LocalQuads = std::vector<std::array<int, 4>>;  // one panel's quads, grid-local indices

// Sizes before any grid is allocated: all grids together at most 4 x max_vertices nodes.
bool checkGridSizes(const Pattern& pattern, double spacing, const MeshLimits& limits, std::string& error) {
  const int np = static_cast<int>(pattern.panels.size());
  double gridNodes = 0;
  for (int p = 0; p < np; ++p) {
    double cx = 0, cy = 0;
    gridSize(pattern.panels[static_cast<std::size_t>(p)].outline, spacing, cx, cy);
    if (!(cx * cy <= kMaxGridNodes)) {
      error = panelLabel(pattern, p) + ": spacing " + num(spacing) + " m gives a " + num(cx) + " x " +
              num(cy) + " grid, more than " + std::to_string(static_cast<long long>(kMaxGridNodes)) +
              " nodes";
      return false;
    }
    gridNodes += cx * cy;
  }
  const double budget = 4.0 * static_cast<double>(limits.max_vertices);
  if (!(gridNodes <= budget)) {
    error = "spacing " + num(spacing) + " m gives grids of " + num(gridNodes) +
            " nodes over all panels, more than " + num(budget) +
            " (4 x MeshLimits::max_vertices); use a coarser spacing or check the outline units";
    return false;
  }
  return true;
}

// Every panel's grid and quads, and the nodes in use numbered panel after panel (`total` of them);
// false (with `error`) when a panel holds no quad or the cloth is over limits.max_vertices.
bool buildGrids(const Pattern& pattern, double spacing, const MeshLimits& limits,
                std::vector<PanelGrid>& grids, std::vector<LocalQuads>& localQuads, int& total,
                std::string& error) {
  const int np = static_cast<int>(pattern.panels.size());
  grids.resize(static_cast<std::size_t>(np));
  localQuads.resize(static_cast<std::size_t>(np));
  total = 0;
  for (int p = 0; p < np; ++p) {
    PanelGrid& g = grids[static_cast<std::size_t>(p)];
    if (!buildGrid(pattern, p, spacing, g, localQuads[static_cast<std::size_t>(p)], error)) return false;
    for (std::size_t k = 0; k < g.used.size(); ++k)
      if (g.used[k]) g.node[k] = total++;
  }
  if (static_cast<std::size_t>(total) > limits.max_vertices) {
    error = "spacing " + num(spacing) + " m gives a cloth of " + std::to_string(total) +
            " nodes, over the limit of " + std::to_string(limits.max_vertices) +
            " vertices (MeshLimits::max_vertices); use a coarser spacing";
    return false;
  }
  return true;
}

// The cloth's arrays sized for `total` nodes and the quads of all panels.
void allocateCloth(double spacing, int total, const std::vector<LocalQuads>& localQuads, ClothMesh& cloth) {
  cloth.spacing = spacing;
  cloth.X.resize(total, 3);
  cloth.UV.resize(total, 2);
  cloth.panel.resize(static_cast<std::size_t>(total));
  std::size_t quadCount = 0;
  for (const auto& q : localQuads) quadCount += q.size();
  cloth.quads.reserve(quadCount);
  // <= 2 + 2 + 2 per node
  cloth.springs.reserve(static_cast<std::size_t>(6) * static_cast<std::size_t>(total));
  cloth.F.resize(static_cast<Eigen::Index>(2 * quadCount), 3);
}

// The nodes of panel p: flat (snapped) and placed positions; its boundary nodes (a grid axis
// without a linked neighbour, or on the outline) go to `boundary`.
void placeNodes(const PanelGrid& g, int p, const PanelPlacement& placement, ClothMesh& cloth,
                std::vector<int>& boundary) {
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const int n = g.id(i, j);
      if (n < 0) continue;
      const Vec2 uv = snappedUv(g, i, j);
      cloth.UV.row(n) = uv.transpose();
      cloth.X.row(n) = placement.place(uv).transpose();
      cloth.panel[static_cast<std::size_t>(n)] = p;
      const bool inner = g.isUsed(i - 1, j) && g.linked(i - 1, j, kLinkU) && g.isUsed(i + 1, j) &&
                         g.linked(i, j, kLinkU) && g.isUsed(i, j - 1) && g.linked(i, j - 1, kLinkV) &&
                         g.isUsed(i, j + 1) && g.linked(i, j, kLinkV);
      if (!inner || g.onOutline[static_cast<std::size_t>(g.at(i, j))]) boundary.push_back(n);
    }
}

// Each quad of the panel and its two triangles, in global node indices.
void addQuads(const PanelGrid& g, const LocalQuads& quads, ClothMesh& cloth) {
  for (const auto& q : quads) {
    const std::array<int, 4> c = {
        g.node[static_cast<std::size_t>(q[0])], g.node[static_cast<std::size_t>(q[1])],
        g.node[static_cast<std::size_t>(q[2])], g.node[static_cast<std::size_t>(q[3])]};
    const Eigen::Index t = static_cast<Eigen::Index>(2 * cloth.quads.size());
    cloth.F.row(t) << c[0], c[1], c[2];
    cloth.F.row(t + 1) << c[0], c[2], c[3];
    cloth.quads.push_back(c);
  }
}

// A spring at its flat rest length.
void addSpring(ClothMesh& cloth, int a, int b, SpringType type) {
  Spring s;
  s.a = a;
  s.b = b;
  s.rest = (cloth.UV.row(a) - cloth.UV.row(b)).norm();
  s.type = type;
  cloth.springs.push_back(s);
}

// The panel's structural, shear and flexion springs (its nodes' uv must be set).
void addGridSprings(const PanelGrid& g, ClothMesh& cloth) {
  // Structural: linked grid neighbours.
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      if (!g.isUsed(i, j)) continue;
      if (g.isUsed(i + 1, j) && g.linked(i, j, kLinkU))
        addSpring(cloth, g.id(i, j), g.id(i + 1, j), SpringType::Structural);
      if (g.isUsed(i, j + 1) && g.linked(i, j, kLinkV))
        addSpring(cloth, g.id(i, j), g.id(i, j + 1), SpringType::Structural);
    }
  // Shear: both diagonals of each grid cell whose ends are nodes (and whose segment stays inside).
  for (int j = 0; j + 1 < g.ny; ++j)
    for (int i = 0; i + 1 < g.nx; ++i) {
      if (g.isUsed(i, j) && g.isUsed(i + 1, j + 1) && g.segmentInside(g.uv(i, j), g.uv(i + 1, j + 1)))
        addSpring(cloth, g.id(i, j), g.id(i + 1, j + 1), SpringType::Shear);
      if (g.isUsed(i + 1, j) && g.isUsed(i, j + 1) && g.segmentInside(g.uv(i + 1, j), g.uv(i, j + 1)))
        addSpring(cloth, g.id(i + 1, j), g.id(i, j + 1), SpringType::Shear);
    }
  // Flexion: two apart, the middle node present and both halves linked.
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      if (!g.isUsed(i, j)) continue;
      if (g.isUsed(i + 2, j) && g.isUsed(i + 1, j) && g.linked(i, j, kLinkU) && g.linked(i + 1, j, kLinkU))
        addSpring(cloth, g.id(i, j), g.id(i + 2, j), SpringType::Flexion);
      if (g.isUsed(i, j + 2) && g.isUsed(i, j + 1) && g.linked(i, j, kLinkV) && g.linked(i, j + 1, kLinkV))
        addSpring(cloth, g.id(i, j), g.id(i, j + 2), SpringType::Flexion);
    }
}

// How many of the boundary nodes `cand` lie near the stretch polyline `pl`.
int nodesNearStretch(const std::vector<Vec2>& pl, const std::vector<int>& cand, const MatrixX2d& UV,
                     double spacing) {
  // Near: within 0.75 spacing, or within one spacing alongside the stretch (its closest point
  // not one of the stretch's ends). The second part catches the boundary nodes of a grid that
  // is not aligned with a slanted stretch: a boundary node's missing neighbour lies across the
  // outline, so such a node can be up to one spacing away.
  int near = 0;
  for (int n : cand) {
    const Vec2 uv = UV.row(n).transpose();
    double d = INFINITY;
    bool atEnd = false;
    for (std::size_t e = 0; e + 1 < pl.size(); ++e) {
      const Vec2 ab = pl[e + 1] - pl[e];
      const double t = std::clamp((uv - pl[e]).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      const double de = (uv - (pl[e] + t * ab)).norm();
      if (de < d) {
        d = de;
        atEnd = (e == 0 && t <= 0) || (e + 2 == pl.size() && t >= 1);
      }
    }
    if (d <= kNearStretch * spacing || (d <= spacing * (1 + 1e-9) && !atEnd)) ++near;
  }
  return near;
}

// `samples` points evenly spaced by arc length along `pl`, each mapped to its nearest node of
// `cand`.
std::vector<int> sampleStretch(const std::vector<Vec2>& pl, const std::vector<int>& cand, int samples,
                               const MatrixX2d& UV) {
  std::vector<int> mapped;
  std::vector<double> cum(pl.size(), 0.0);
  for (std::size_t e = 1; e < pl.size(); ++e) cum[e] = cum[e - 1] + (pl[e] - pl[e - 1]).norm();
  std::size_t e = 0;
  for (int s = 0; s < samples; ++s) {
    const double t = cum.back() * s / (samples - 1);
    while (e + 2 < pl.size() && cum[e + 1] < t) ++e;
    const double segLen = cum[e + 1] - cum[e];
    const double f = segLen > 0 ? std::clamp((t - cum[e]) / segLen, 0.0, 1.0) : 0.0;
    const Vec2 q = pl[e] + f * (pl[e + 1] - pl[e]);
    int best = -1;
    double bestD = INFINITY;
    for (int n : cand) {
      const double d = (UV.row(n).transpose() - q).squaredNorm();
      if (d < bestD) {
        bestD = d;
        best = n;
      }
    }
    mapped.push_back(best);
  }
  return mapped;
}

// The node pairs of seam k: both stretches sampled at as many points as the more crowded side has
// boundary nodes near it, matched sample by sample. False (with `error`) when fewer than two
// distinct pairs come out.
bool addSeam(const Pattern& pattern, std::size_t k, double spacing,
             const std::vector<std::vector<int>>& boundary, ClothMesh& cloth, std::string& error) {
  const PatternSeam& seam = pattern.seams[k];
  std::vector<Vec2> poly[2];
  int near[2] = {0, 0};
  const OutlineStretch* st[2] = {&seam.a, &seam.b};
  for (int side = 0; side < 2; ++side) {
    const MatrixX2d& P = pattern.panels[static_cast<std::size_t>(st[side]->panel)].outline;
    for (int v : stretchVertices(pattern, *st[side])) poly[side].push_back(polygon2d::point(P, v));
    near[side] = nodesNearStretch(poly[side], boundary[static_cast<std::size_t>(st[side]->panel)], cloth.UV,
                                  spacing);
  }
  const int samples = std::max(near[0], near[1]);
  std::vector<int> mapped[2];
  for (int side = 0; side < 2 && samples >= 2; ++side)
    mapped[side] = sampleStretch(poly[side], boundary[static_cast<std::size_t>(st[side]->panel)], samples,
                                 cloth.UV);
  std::set<std::pair<int, int>> seen;
  std::size_t before = cloth.seam_pairs.size();
  for (std::size_t s = 0; s < mapped[0].size(); ++s) {
    const int a = mapped[0][s], b = mapped[1][s];
    if (a == b || !seen.insert({a, b}).second) continue;
    SeamPair sp;
    sp.a = a;
    sp.b = b;
    sp.seam = static_cast<int>(k);
    cloth.seam_pairs.push_back(sp);
  }
  cloth.seam_stage.push_back(pattern.seams[k].stage);
  const std::size_t made = cloth.seam_pairs.size() - before;
  if (made < 2) {
    error = "seam " + std::to_string(k) + ": only " + std::to_string(made) + " distinct node pair" +
            (made == 1 ? "" : "s") + " at spacing " + num(spacing) + " m (boundary nodes within " +
            num(kNearStretch) + " * spacing: " + std::to_string(near[0]) + " of " +
            panelLabel(pattern, seam.a.panel) + " near a, " + std::to_string(near[1]) + " of " +
            panelLabel(pattern, seam.b.panel) + " near b); a seam needs at least 2, use a finer spacing";
    return false;
  }
  return true;
}

}  // namespace

bool meshPattern(const Pattern& pattern, double spacing, ClothMesh& cloth, std::string& error,
                 const MeshLimits& limits) {
  cloth = ClothMesh();
  error.clear();
  if (!(std::isfinite(spacing) && spacing > 0)) {
    error = "grid spacing must be a finite number > 0, got " + num(spacing);
    return false;
  }
  error = validatePattern(pattern);
  if (!error.empty()) return false;
  if (!checkGridSizes(pattern, spacing, limits, error)) return false;

  std::vector<PanelGrid> grids;
  std::vector<LocalQuads> localQuads;
  int total = 0;
  if (!buildGrids(pattern, spacing, limits, grids, localQuads, total, error)) return false;
  allocateCloth(spacing, total, localQuads, cloth);

  // Boundary nodes per panel (global indices).
  const std::size_t np = pattern.panels.size();
  std::vector<std::vector<int>> boundary(np);
  for (std::size_t p = 0; p < np; ++p) {
    const PanelGrid& g = grids[p];
    placeNodes(g, static_cast<int>(p), pattern.panels[p].placement, cloth, boundary[p]);
    addQuads(g, localQuads[p], cloth);
    addGridSprings(g, cloth);
  }

  for (std::size_t k = 0; k < pattern.seams.size(); ++k)
    if (!addSeam(pattern, k, spacing, boundary, cloth, error)) {
      cloth = ClothMesh();
      return false;
    }
  return true;
}

}  // namespace virtual_tryon
