// meshPattern: panels into regular grids of mass points (Vassilev et al. 2001, sec. 1 and 3),
// springs, triangles and seam pairs. The rules are spelled out in pattern.h.
#include "virtual_tryon/core/drape/pattern.h"

#include "core/drape/boundary_band.h"
#include "core/drape/outline_nodes.h"
#include "core/drape/pattern_text.h"
#include "core/geometry/polygon2d.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <unordered_set>
#include <set>
#include <sstream>
#include <utility>

namespace virtual_tryon {

namespace {

using polygon2d::Vec2;

constexpr double kOnOutline = 1e-9;               // metres: a node this close counts as inside
constexpr double kMaxGridNodes = 2e7;             // per panel, before clipping
constexpr double kInnerMargin = 0.5;              // * spacing: grid nodes at least this far inside
constexpr double kOutlineTolerance = 0.005;       // * spacing: outline nodes' chords this close

using pattern_text::num;
using pattern_text::panelLabel;

// Link bits stored at grid node (i, j).
enum : std::uint8_t { kLinkU = 1, kLinkV = 2 };

struct PanelGrid {
  int nx = 0, ny = 0;
  double x0 = 0, y0 = 0, h = 0;
  std::vector<char> kept, used;
  std::vector<std::uint8_t> link;
  std::vector<int> node;  // node index (panel-local until meshPattern numbers the cloth) or -1
  int nodeCount = 0;      // the panel's grid nodes
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

// Quads that meet others at a corner only (diagonal neighbours with both cells beside them empty)
// would make the grid's edge touch itself; one of each such pair is dropped, until none is left.
void removeCornerTouches(PanelGrid& g, std::vector<std::array<int, 4>>& quads) {
  std::vector<int> cell(static_cast<std::size_t>(g.nx) * static_cast<std::size_t>(g.ny), -1);
  for (std::size_t q = 0; q < quads.size(); ++q) cell[static_cast<std::size_t>(quads[q][0])] = static_cast<int>(q);
  auto has = [&](int i, int j) { return i >= 0 && j >= 0 && i < g.nx && j < g.ny && cell[g.at(i, j)] >= 0; };
  bool changed = true;
  while (changed) {
    changed = false;
    for (int j = 0; j + 1 < g.ny; ++j)
      for (int i = 0; i + 1 < g.nx; ++i) {
        // The four cells round grid node (i + 1, j + 1).
        const bool a = has(i, j), b = has(i + 1, j), c = has(i, j + 1), d = has(i + 1, j + 1);
        if ((a && d && !b && !c) || (b && c && !a && !d)) {
          cell[g.at(a ? i : i + 1, j)] = -1;
          changed = true;
        }
      }
  }
  std::vector<std::array<int, 4>> keep;
  for (const auto& q : quads)
    if (cell[static_cast<std::size_t>(q[0])] >= 0) keep.push_back(q);
  quads.swap(keep);
  std::fill(g.used.begin(), g.used.end(), 0);
  for (const auto& q : quads)
    for (int c : q) g.used[static_cast<std::size_t>(c)] = 1;
}

// Grid nodes, links, quads of one panel (indices local to the grid). meshPattern has checked the
// grid's size (gridSize) before any grid is built.
void buildGrid(const Pattern& pattern, int p, double h, PanelGrid& g, std::vector<std::array<int, 4>>& quads) {
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
  g.used.assign(count, 0);
  g.link.assign(count, 0);
  g.node.assign(count, -1);

  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const Vec2 q = g.uv(i, j);
      const std::size_t k = static_cast<std::size_t>(g.at(i, j));
      g.kept[k] = polygon2d::strictlyInside(q, P) && polygon2d::distanceToOutline(q, P) >= kInnerMargin * h;
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
  removeCornerTouches(g, quads);
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
                std::vector<PanelGrid>& grids, std::vector<LocalQuads>& localQuads, std::string& error) {
  const int np = static_cast<int>(pattern.panels.size());
  grids.resize(static_cast<std::size_t>(np));
  localQuads.resize(static_cast<std::size_t>(np));
  int total = 0;
  for (int p = 0; p < np; ++p) {
    PanelGrid& g = grids[static_cast<std::size_t>(p)];
    buildGrid(pattern, p, spacing, g, localQuads[static_cast<std::size_t>(p)]);
    for (std::size_t k = 0; k < g.used.size(); ++k)
      if (g.used[k]) g.node[k] = g.nodeCount++;  // panel-local; meshPattern adds the panel's base
    total += g.nodeCount;
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
void allocateCloth(double spacing, int total, const std::vector<LocalQuads>& localQuads, std::size_t bandTriangles,
                   ClothMesh& cloth) {
  cloth.spacing = spacing;
  cloth.X.resize(total, 3);
  cloth.UV.resize(total, 2);
  cloth.panel.resize(static_cast<std::size_t>(total));
  std::size_t quadCount = 0;
  for (const auto& q : localQuads) quadCount += q.size();
  cloth.quads.reserve(quadCount);
  // <= 2 + 2 + 2 per grid node, and a few per band node
  cloth.springs.reserve(static_cast<std::size_t>(8) * static_cast<std::size_t>(total));
  cloth.F.resize(static_cast<Eigen::Index>(2 * quadCount + bandTriangles), 3);
}

// The grid nodes of panel p: flat and placed positions.
void placeGridNodes(const PanelGrid& g, int p, const PanelPlacement& placement, ClothMesh& cloth) {
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const int n = g.id(i, j);
      if (n < 0) continue;
      const Vec2 uv = g.uv(i, j);
      cloth.UV.row(n) = uv.transpose();
      cloth.X.row(n) = placement.place(uv).transpose();
      cloth.panel[static_cast<std::size_t>(n)] = p;
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

// The edge loops of a panel's grid region (its quads), as grid-local node indices, each
// counter-clockwise round the region (a hole in the region: clockwise).
std::vector<std::vector<int>> gridEdgeLoops(const LocalQuads& quads) {
  auto key = [](int a, int b) { return (static_cast<long long>(a) << 32) | static_cast<unsigned>(b); };
  std::unordered_set<long long> half;
  half.reserve(4 * quads.size());
  for (const auto& q : quads)
    for (int k = 0; k < 4; ++k) half.insert(key(q[k], q[(k + 1) % 4]));
  std::map<int, int> next;  // ordered: the loops come out in the same order every time
  for (const auto& q : quads)
    for (int k = 0; k < 4; ++k)
      if (!half.count(key(q[(k + 1) % 4], q[k]))) next[q[k]] = q[(k + 1) % 4];
  std::vector<std::vector<int>> loops;
  std::unordered_set<int> seen;
  for (const auto& start : next) {
    if (seen.count(start.first)) continue;
    std::vector<int> loop;
    int v = start.first;
    while (!seen.count(v) && next.count(v)) {
      seen.insert(v);
      loop.push_back(v);
      v = next[v];
    }
    if (loop.size() >= 3) loops.push_back(loop);
  }
  return loops;
}

double loopArea(const std::vector<Vec2>& pts, const std::vector<int>& loop) {
  double a = 0;
  for (std::size_t i = 0; i < loop.size(); ++i) a += polygon2d::cross(pts[loop[i]], pts[loop[(i + 1) % loop.size()]]);
  return 0.5 * a;
}

// One panel's band: the triangles between its outline loop (global nodes loopBase ..
// loopBase + loop size - 1) and its grid's edge, as global node indices, counter-clockwise in uv.
bool bandTriangles(const Pattern& pattern, int p, const PanelGrid& g, const LocalQuads& quads,
                   const std::vector<Vec2>& loopUv, int loopBase, std::vector<std::array<int, 3>>& out,
                   std::string& error) {
  std::vector<Vec2> pts(loopUv);
  std::vector<int> global;
  for (std::size_t i = 0; i < loopUv.size(); ++i) global.push_back(loopBase + static_cast<int>(i));
  std::map<int, int> local;  // grid cell index -> point index
  auto pointOf = [&](int cell) {
    auto it = local.find(cell);
    if (it != local.end()) return it->second;
    const int id = static_cast<int>(pts.size());
    pts.push_back(g.uv(cell % g.nx, cell / g.nx));
    global.push_back(g.node[static_cast<std::size_t>(cell)]);
    local[cell] = id;
    return id;
  };
  std::vector<std::vector<int>> outer(1), islands;
  for (std::size_t i = 0; i < loopUv.size(); ++i) outer[0].push_back(static_cast<int>(i));
  for (const auto& loop : gridEdgeLoops(quads)) {
    std::vector<int> l;
    for (int c : loop) l.push_back(pointOf(c));
    if (loopArea(pts, l) > 0) {
      std::reverse(l.begin(), l.end());  // the region's edge is a hole of the band
      outer.push_back(l);
    } else {
      std::reverse(l.begin(), l.end());  // a hole of the region is a piece of band of its own
      islands.push_back({l});
    }
  }
  std::vector<std::vector<std::vector<int>>> polygons{outer};
  for (const auto& l : islands) polygons.push_back({l});
  for (const auto& poly : polygons) {
    std::vector<std::array<int, 3>> tris;
    if (!boundary_band::triangulateBand(pts, poly, tris)) {
      error = panelLabel(pattern, p) + ": its boundary band cannot be triangulated at spacing " + num(g.h) +
              " m (outline loop of " + std::to_string(loopUv.size()) + " nodes)";
      return false;
    }
    for (const auto& t : tris) out.push_back({global[t[0]], global[t[1]], global[t[2]]});
  }
  return true;
}

// Springs along every band edge that is not a grid spring yet (structural), and across every
// edge between two band triangles (flexion, between the two opposite corners).
void addBandSprings(const std::vector<std::array<int, 3>>& tris, ClothMesh& cloth) {
  auto key = [](int a, int b) { return std::make_pair(std::min(a, b), std::max(a, b)); };
  // The springs already there between band nodes (grid springs along the grid's edge).
  std::vector<char> inBand(static_cast<std::size_t>(cloth.X.rows()), 0);
  for (const auto& t : tris)
    for (int v : t) inBand[static_cast<std::size_t>(v)] = 1;
  std::set<std::pair<int, int>> have;
  for (const Spring& s : cloth.springs)
    if (inBand[static_cast<std::size_t>(s.a)] && inBand[static_cast<std::size_t>(s.b)]) have.insert(key(s.a, s.b));
  std::map<std::pair<int, int>, std::vector<int>> opposite;
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k) {
      const auto e = key(t[k], t[(k + 1) % 3]);
      opposite[e].push_back(t[(k + 2) % 3]);
      if (have.insert(e).second) addSpring(cloth, e.first, e.second, SpringType::Structural);
    }
  // Flexion only where the two triangles make a convex quad: then the spring stays on the cloth
  // (across a notch it would not).
  auto uvOf = [&](int n) { return Vec2(cloth.UV(n, 0), cloth.UV(n, 1)); };
  for (const auto& e : opposite) {
    if (e.second.size() != 2) continue;
    const Vec2 a = uvOf(e.first.first), b = uvOf(e.first.second), c = uvOf(e.second[0]), d = uvOf(e.second[1]);
    const bool convex = polygon2d::orient(c, d, a) * polygon2d::orient(c, d, b) < 0 &&
                        polygon2d::orient(a, b, c) * polygon2d::orient(a, b, d) < 0;
    if (convex && have.insert(key(e.second[0], e.second[1])).second)
      addSpring(cloth, e.second[0], e.second[1], SpringType::Flexion);
  }
}
}  // namespace

bool meshPattern(const Pattern& input, double spacing, ClothMesh& cloth, std::string& error,
                 const MeshLimits& limits) {
  cloth = ClothMesh();
  error.clear();
  if (!(std::isfinite(spacing) && spacing > 0)) {
    error = "grid spacing must be a finite number > 0, got " + num(spacing);
    return false;
  }
  error = validatePattern(input);
  if (!error.empty()) return false;
  Pattern pattern = input;  // outlines counter-clockwise (the outline loops run that way)
  normalizePattern(pattern);
  if (!checkGridSizes(pattern, spacing, limits, error)) return false;

  std::vector<PanelGrid> grids;
  std::vector<LocalQuads> localQuads;
  if (!buildGrids(pattern, spacing, limits, grids, localQuads, error)) return false;
  outline_nodes::OutlineSampling outline;
  if (!outline_nodes::sampleOutlines(pattern, spacing, kOutlineTolerance * spacing, outline, error)) return false;
  const std::size_t np = pattern.panels.size();
  // Numbering panel by panel, each panel's outline nodes right after its grid nodes (springs then
  // join nearby rows of the node arrays).
  std::vector<int> loopBase(np, 0);
  int total = 0;
  for (std::size_t p = 0; p < np; ++p) {
    for (int& n : grids[p].node)
      if (n >= 0) n += total;
    total += grids[p].nodeCount;
    loopBase[p] = total;
    total += static_cast<int>(outline.loops[p].uv.size());
  }
  if (static_cast<std::size_t>(total) > limits.max_vertices) {
    error = "spacing " + num(spacing) + " m gives a cloth of " + std::to_string(total) +
            " nodes, over the limit of " + std::to_string(limits.max_vertices) +
            " vertices (MeshLimits::max_vertices); use a coarser spacing";
    return false;
  }
  std::vector<std::vector<std::array<int, 3>>> band(np);
  std::size_t bandCount = 0;
  for (std::size_t p = 0; p < np; ++p) {
    if (!bandTriangles(pattern, static_cast<int>(p), grids[p], localQuads[p], outline.loops[p].uv, loopBase[p],
                       band[p], error))
      return false;
    bandCount += band[p].size();
  }
  allocateCloth(spacing, total, localQuads, bandCount, cloth);

  for (std::size_t p = 0; p < np; ++p) {
    const PanelGrid& g = grids[p];
    placeGridNodes(g, static_cast<int>(p), pattern.panels[p].placement, cloth);
    for (std::size_t i = 0; i < outline.loops[p].uv.size(); ++i) {
      const int n = loopBase[p] + static_cast<int>(i);
      cloth.UV.row(n) = outline.loops[p].uv[i].transpose();
      cloth.X.row(n) = pattern.panels[p].placement.place(outline.loops[p].uv[i]).transpose();
      cloth.panel[static_cast<std::size_t>(n)] = static_cast<int>(p);
    }
    addQuads(g, localQuads[p], cloth);
    addGridSprings(g, cloth);
  }
  Eigen::Index row = static_cast<Eigen::Index>(2 * cloth.quads.size());
  std::vector<std::array<int, 3>> allBand;
  allBand.reserve(bandCount);
  for (std::size_t p = 0; p < np; ++p)
    for (const auto& t : band[p]) {
      cloth.F.row(row++) << t[0], t[1], t[2];
      allBand.push_back(t);
    }
  addBandSprings(allBand, cloth);
  for (std::size_t k = 0; k < pattern.seams.size(); ++k) {
    const PatternSeam& seam = pattern.seams[k];
    for (const auto& pr : outline.seam_pairs[k]) {
      SeamPair sp;
      sp.a = loopBase[seam.a.panel] + pr.first;
      sp.b = loopBase[seam.b.panel] + pr.second;
      sp.seam = static_cast<int>(k);
      if (sp.a != sp.b) cloth.seam_pairs.push_back(sp);
    }
    cloth.seam_stage.push_back(seam.stage);
  }
  return true;
}

}  // namespace virtual_tryon
