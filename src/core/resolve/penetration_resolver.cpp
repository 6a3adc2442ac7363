#include "virtual_tryon/core/resolve/penetration_resolver.h"

#include "virtual_tryon/core/resolve/impact_zones.h"
#include "virtual_tryon/core/resolve/intersections.h"
#include "virtual_tryon/core/geometry/point_queries.h"
#include "virtual_tryon/core/resolve/stencils.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <queue>
#include <sstream>
#include <unordered_map>
#include <utility>

namespace virtual_tryon {
namespace {

using Clock = std::chrono::steady_clock;

// Wall clock of the call without the time spent in the observer.
class Stopwatch {
 public:
  Stopwatch() : start_(Clock::now()) {}
  double now() const { return std::chrono::duration<double>(Clock::now() - start_).count() - excluded_; }
  template <class F>
  void exclude(F&& f) {
    const auto t0 = Clock::now();
    f();
    excluded_ += std::chrono::duration<double>(Clock::now() - t0).count();
  }

 private:
  Clock::time_point start_;
  double excluded_ = 0;
};

double meanLength(const MatrixX3d& V, const MatrixX2i& E) {
  double sum = 0;
  for (Eigen::Index e = 0; e < E.rows(); ++e) sum += (V.row(E(e, 0)) - V.row(E(e, 1))).norm();
  return E.rows() ? sum / static_cast<double>(E.rows()) : 0.0;
}

// Garment connectivity a run needs, built once per call: the faces round each vertex, the
// neighbours over edges, and the connected pieces.
struct GarmentGraph {
  std::vector<int> vf_start, vf;              // faces of vertex v: vf[vf_start[v] .. vf_start[v+1])
  std::vector<int> adj_start, adj_v, adj_e;   // neighbours of v and the edge to each
  std::vector<int> piece;                     // per vertex; -1 for a vertex on no edge
  std::vector<int> piece_start, piece_members;
  int pieces = 0;

  GarmentGraph(const TriMesh& garment, const GarmentTopology& topo) {
    const int nv = static_cast<int>(garment.V.rows());
    vf_start.assign(static_cast<std::size_t>(nv) + 1, 0);
    for (Eigen::Index f = 0; f < garment.F.rows(); ++f)
      for (int k = 0; k < 3; ++k) ++vf_start[garment.F(f, k) + 1];
    for (int v = 0; v < nv; ++v) vf_start[v + 1] += vf_start[v];
    vf.resize(static_cast<std::size_t>(vf_start[nv]));
    std::vector<int> fill(vf_start.begin(), vf_start.end() - 1);
    for (Eigen::Index f = 0; f < garment.F.rows(); ++f)
      for (int k = 0; k < 3; ++k) vf[fill[garment.F(f, k)]++] = static_cast<int>(f);

    adj_start.assign(static_cast<std::size_t>(nv) + 1, 0);
    for (Eigen::Index e = 0; e < topo.edges.rows(); ++e) {
      ++adj_start[topo.edges(e, 0) + 1];
      ++adj_start[topo.edges(e, 1) + 1];
    }
    for (int v = 0; v < nv; ++v) adj_start[v + 1] += adj_start[v];
    adj_v.resize(static_cast<std::size_t>(adj_start[nv]));
    adj_e.resize(adj_v.size());
    fill.assign(adj_start.begin(), adj_start.end() - 1);
    for (Eigen::Index e = 0; e < topo.edges.rows(); ++e) {
      const int a = topo.edges(e, 0), b = topo.edges(e, 1);
      adj_v[fill[a]] = b;
      adj_e[fill[a]++] = static_cast<int>(e);
      adj_v[fill[b]] = a;
      adj_e[fill[b]++] = static_cast<int>(e);
    }

    piece.assign(static_cast<std::size_t>(nv), -1);
    piece_start.push_back(0);
    std::vector<int> stack;
    for (int s = 0; s < nv; ++s) {
      if (piece[s] >= 0 || adj_start[s] == adj_start[s + 1]) continue;
      piece[s] = pieces;
      stack.push_back(s);
      while (!stack.empty()) {
        const int u = stack.back();
        stack.pop_back();
        piece_members.push_back(u);
        for (int i = adj_start[u]; i < adj_start[u + 1]; ++i)
          if (piece[adj_v[i]] < 0) {
            piece[adj_v[i]] = pieces;
            stack.push_back(adj_v[i]);
          }
      }
      ++pieces;
      piece_start.push_back(static_cast<int>(piece_members.size()));
    }
  }
  int pieceSize(int p) const { return piece_start[p + 1] - piece_start[p]; }
};

// Inside/outside for every garment vertex of a closed body, with one ray test per connected
// piece: across a garment edge the side flips once per crossing of that edge with a body face.
std::vector<char> classifyInside(const Body& body, const TriMesh& garment, const GarmentTopology& topo,
                                 const GarmentGraph& g, const CrossingSet& crossings) {
  const int nv = static_cast<int>(garment.V.rows());
  std::vector<int> flips(static_cast<std::size_t>(topo.edges.rows()), 0);
  for (const auto& c : crossings.garment_edges) ++flips[c.edge];
  std::vector<char> inside(static_cast<std::size_t>(nv), 0), seen(static_cast<std::size_t>(nv), 0);
  std::queue<int> q;
  for (int p = 0; p < g.pieces; ++p) {
    const int s = g.piece_members[g.piece_start[p]];
    seen[s] = 1;
    inside[s] = pointInsideBody(body, garment.V.row(s).transpose()) ? 1 : 0;
    q.push(s);
    while (!q.empty()) {
      const int u = q.front();
      q.pop();
      for (int i = g.adj_start[u]; i < g.adj_start[u + 1]; ++i) {
        const int v = g.adj_v[i];
        if (seen[v]) continue;
        seen[v] = 1;
        inside[v] = static_cast<char>(inside[u] ^ (flips[g.adj_e[i]] & 1));
        q.push(v);
      }
    }
  }
  return inside;
}

// Re-detects only around the faces in `dirty`: crossings of untouched edges and faces stay.
void updateCrossings(const Body& body, const TriMesh& garment, const GarmentTopology& topo,
                     const std::vector<int>& dirty, std::vector<char>& dirtyFace,
                     std::vector<char>& dirtyEdge, CrossingSet& crossings) {
  for (int f : dirty) {
    dirtyFace[f] = 1;
    for (int k = 0; k < 3; ++k) dirtyEdge[topo.face_edges(f, k)] = 1;
  }
  auto& ge = crossings.garment_edges;
  ge.erase(std::remove_if(ge.begin(), ge.end(), [&](const EdgeFaceCrossing& c) { return dirtyEdge[c.edge] != 0; }),
           ge.end());
  auto& be = crossings.body_edges;
  be.erase(std::remove_if(be.begin(), be.end(), [&](const EdgeFaceCrossing& c) { return dirtyFace[c.face] != 0; }),
           be.end());
  for (int f : dirty) {
    dirtyFace[f] = 0;
    for (int k = 0; k < 3; ++k) dirtyEdge[topo.face_edges(f, k)] = 0;
  }
  CrossingSet fresh;
  detectCrossings(body, garment, topo, fresh, &dirty);
  ge.insert(ge.end(), fresh.garment_edges.begin(), fresh.garment_edges.end());
  be.insert(be.end(), fresh.body_edges.begin(), fresh.body_edges.end());
}

}  // namespace

ResolverReport resolvePenetrations(const Body& body, TriMesh& garment, const ResolverParams& params) {
  Stopwatch clock;
  ResolverReport rep;
  rep.body_closed = body.closed();
  std::ostringstream reason;
  if (body.closed() && body.signedVolume() < 0) {
    reason << "the body is inside out (closed, signed volume " << body.signedVolume()
           << " m^3 < 0): its faces must wind counter-clockwise seen from outside; nothing moved";
    rep.reason = reason.str();
    rep.seconds_total = clock.now();
    return rep;
  }
  const int nv = static_cast<int>(garment.V.rows());
  const GarmentTopology topo(garment);
  const GarmentGraph graph(garment, topo);
  const double d = params.clearance > 0 ? params.clearance
                                        : params.clearance_fraction * meanLength(garment.V, topo.edges);
  rep.clearance = d;
  const bool insideTest = params.check_inside && body.closed();

  double t0 = clock.now();
  CrossingSet crossings;
  detectCrossings(body, garment, topo, crossings);
  rep.seconds_detection += clock.now() - t0;
  rep.garment_edge_crossings_before = crossings.garment_edges.size();
  rep.body_edge_crossings_before = crossings.body_edges.size();

  // Inside flags before any move, and per piece how many of its vertices are inside. A vertex that
  // never moves keeps its flag; after a round only the moved vertices are classified again, from
  // a neighbour across the crossings of the edge between them (or one ray test for a region
  // with no known neighbour).
  std::vector<char> insideBefore, inside;
  std::vector<int> pieceInsideBefore;
  std::size_t insideCount = 0;
  if (insideTest) {
    t0 = clock.now();
    insideBefore = classifyInside(body, garment, topo, graph, crossings);
    pieceInsideBefore.assign(static_cast<std::size_t>(graph.pieces), 0);
    for (int v = 0; v < nv; ++v)
      if (insideBefore[v]) {
        ++rep.vertices_inside_before;
        ++pieceInsideBefore[graph.piece[v]];
      }
    inside = insideBefore;
    insideCount = rep.vertices_inside_before;
    rep.seconds_detection += clock.now() - t0;
  }
  // The error the run drives down, and judges progress and the best state by: crossings plus
  // garment vertices inside (the crossings alone can stay level while a deep region shrinks).
  auto error = [&] { return crossings.size() + insideCount; };

  // Per-vertex and per-face flags for the rounds (allocated here, with the first pass).
  std::vector<char> touched(static_cast<std::size_t>(nv), 0), logged(static_cast<std::size_t>(nv), 0);
  std::vector<char> faceMark(static_cast<std::size_t>(garment.F.rows()), 0);
  std::vector<char> dirtyFace(faceMark.size(), 0), dirtyEdge(static_cast<std::size_t>(topo.edges.rows()), 0);
  std::vector<char> unknown(static_cast<std::size_t>(nv), 0), everIllegal(static_cast<std::size_t>(nv), 0);
  std::vector<char> pieceMark(static_cast<std::size_t>(graph.pieces), 0);

  auto record = [&](ResolverIteration it) {
    it.iteration = rep.iterations;
    it.seconds = clock.now();
    it.garment_edge_crossings = crossings.garment_edges.size();
    it.body_edge_crossings = crossings.body_edges.size();
    it.vertices_inside = insideCount;
    rep.trace.push_back(it);
    if (params.on_iteration) clock.exclude([&] { params.on_iteration(rep.trace.back(), garment); });
  };
  record(ResolverIteration());

  // Every vertex that moved, with its start position (for the displacement statistics and the
  // inside test), and an undo log back to the state with the smallest error.
  std::vector<int> touchedList;
  std::vector<Eigen::RowVector3d> startPos;
  struct Undo {
    int v;
    Eigen::RowVector3d x;
    char inside;
  };
  std::vector<Undo> undo;
  CrossingSet bestCrossings = crossings;
  std::size_t best = error(), bestInside = insideCount;
  int sinceBest = 0;
  auto newBest = [&] {
    for (const auto& u : undo) logged[u.v] = 0;
    undo.clear();
    bestCrossings = crossings;
    best = error();
    bestInside = insideCount;
    sinceBest = 0;
  };
  auto restoreBest = [&] {
    if (error() <= best) return;
    for (auto it = undo.rbegin(); it != undo.rend(); ++it) {
      garment.V.row(it->v) = it->x;
      if (insideTest) inside[it->v] = it->inside;
    }
    for (const auto& u : undo) logged[u.v] = 0;
    undo.clear();
    crossings = bestCrossings;
    insideCount = bestInside;
  };
  std::vector<int> movedList;  // this step
  auto move = [&](int v, const Eigen::RowVector3d& to) {
    if (!touched[v]) {
      touched[v] = 1;
      touchedList.push_back(v);
      startPos.push_back(garment.V.row(v));
    }
    if (!logged[v]) {
      logged[v] = 1;
      undo.push_back({v, garment.V.row(v), insideTest ? inside[v] : char(0)});
    }
    garment.V.row(v) = to;
    movedList.push_back(v);
  };
  // Garment faces round the vertices moved in this step (each once), detected again; then the
  // moved vertices classified again.
  std::vector<int> dirty, queue;
  auto redetect = [&] {
    dirty.clear();
    std::sort(movedList.begin(), movedList.end());
    movedList.erase(std::unique(movedList.begin(), movedList.end()), movedList.end());
    for (int v : movedList)
      for (int i = graph.vf_start[v]; i < graph.vf_start[v + 1]; ++i)
        if (!faceMark[graph.vf[i]]) {
          faceMark[graph.vf[i]] = 1;
          dirty.push_back(graph.vf[i]);
        }
    for (int f : dirty) faceMark[f] = 0;
    std::sort(dirty.begin(), dirty.end());
    updateCrossings(body, garment, topo, dirty, dirtyFace, dirtyEdge, crossings);
    if (!insideTest) return;
    std::unordered_map<int, int> flips;
    for (const auto& c : crossings.garment_edges) ++flips[c.edge];
    auto parity = [&](int e) {
      const auto it = flips.find(e);
      return it == flips.end() ? 0 : (it->second & 1);
    };
    for (int v : movedList) {
      insideCount -= static_cast<std::size_t>(inside[v]);
      unknown[v] = 1;
    }
    auto spread = [&] {
      while (!queue.empty()) {
        const int u = queue.back();
        queue.pop_back();
        for (int i = graph.adj_start[u]; i < graph.adj_start[u + 1]; ++i) {
          const int w = graph.adj_v[i];
          if (!unknown[w]) continue;
          unknown[w] = 0;
          inside[w] = static_cast<char>(inside[u] ^ parity(graph.adj_e[i]));
          queue.push_back(w);
        }
      }
    };
    for (int v : movedList) {
      if (!unknown[v]) continue;
      for (int i = graph.adj_start[v]; i < graph.adj_start[v + 1]; ++i) {
        const int u = graph.adj_v[i];
        if (unknown[u]) continue;
        unknown[v] = 0;
        inside[v] = static_cast<char>(inside[u] ^ parity(graph.adj_e[i]));
        queue.push_back(v);
        spread();
        break;
      }
    }
    for (int v : movedList) {
      if (!unknown[v]) continue;
      unknown[v] = 0;
      inside[v] = pointInsideBody(body, garment.V.row(v).transpose()) ? 1 : 0;
      queue.push_back(v);
      spread();
    }
    for (int v : movedList) insideCount += static_cast<std::size_t>(inside[v]);
  };

  // With no crossing every piece lies wholly inside or wholly outside. Pieces no vertex of which
  // moved keep their status; a moved piece takes it from a vertex that did not move, or from one
  // ray test when all of them moved. Returns the vertices inside; `insidePieces` lists the moved
  // pieces now inside and the unmoved pieces that were inside from the start.
  auto insideNow = [&](std::vector<int>& insidePieces) {
    insidePieces.clear();
    std::size_t n = rep.vertices_inside_before;
    std::vector<int> movedPieces;
    for (int v : touchedList) {
      const int p = graph.piece[v];
      if (p < 0 || pieceMark[p]) continue;
      pieceMark[p] = 1;
      movedPieces.push_back(p);
    }
    for (int p : movedPieces) {
      n -= static_cast<std::size_t>(pieceInsideBefore[p]);
      int known = -1;
      for (int i = graph.piece_start[p]; i < graph.piece_start[p + 1]; ++i)
        if (!touched[graph.piece_members[i]]) {
          known = graph.piece_members[i];
          break;
        }
      const bool in = known >= 0 ? insideBefore[known] != 0
                                 : pointInsideBody(body, garment.V.row(graph.piece_members[graph.piece_start[p]]).transpose());
      if (in) {
        n += static_cast<std::size_t>(graph.pieceSize(p));
        insidePieces.push_back(p);
      }
    }
    for (int p = 0; p < graph.pieces && n > 0; ++p)
      if (!pieceMark[p] && pieceInsideBefore[p] > 0) insidePieces.push_back(p);
    for (int p : movedPieces) pieceMark[p] = 0;
    return n;
  };

  bool pushedOut = false;
  std::size_t infeasibleLastRound = 0;
  auto budgetSpent = [&] { return params.time_budget > 0 && clock.now() >= params.time_budget; };
  std::vector<int> insidePieces;
  auto describeBest = [&](std::ostringstream& o) {
    o << "best " << best << " (crossings + vertices inside), which is returned";
  };

  for (;;) {
    if (crossings.size() == 0) {
      if (!insideTest) {
        rep.converged = true;
        reason << "no edge-face crossing left";
        break;
      }
      t0 = clock.now();
      const std::size_t nInside = insideNow(insidePieces);
      rep.seconds_detection += clock.now() - t0;
      if (nInside == 0) {
        insideCount = 0;
        rep.converged = true;
        reason << "no edge-face crossing left, no garment vertex inside the body";
        break;
      }
      rep.vertices_inside_after = nInside;
      if (!params.push_out_inside || pushedOut || rep.iterations >= params.max_iterations) {
        reason << nInside << " garment vertices lie wholly inside the body with no crossing edge"
               << (params.push_out_inside ? " (still inside after pushing them out)" : "");
        break;
      }
      if (budgetSpent()) {
        rep.time_budget_spent = true;
        reason << "time budget " << params.time_budget << " s spent with " << nInside
               << " garment vertices wholly inside the body";
        break;
      }
      // Push each vertex of a piece wholly inside to its nearest body point plus the clearance.
      t0 = clock.now();
      movedList.clear();
      for (int p : insidePieces)
        for (int i = graph.piece_start[p]; i < graph.piece_start[p + 1]; ++i) {
          const int v = graph.piece_members[i];
          const ClosestPoint cp = closestPointOnBody(body, garment.V.row(v).transpose());
          move(v, (cp.point + d * body.faceNormals().row(cp.face).transpose()).transpose());
        }
      ResolverIteration it;
      it.push_out = true;
      it.moved_vertices = movedList.size();
      rep.seconds_solve += clock.now() - t0;
      pushedOut = true;
      rep.vertices_inside_after = 0;
      t0 = clock.now();
      redetect();
      rep.seconds_detection += clock.now() - t0;
      newBest();
      record(it);
      continue;
    }
    if (rep.iterations >= params.max_iterations) {
      reason << "iteration limit " << params.max_iterations << " reached with " << crossings.size()
             << " crossings and " << insideCount << " vertices inside left; ";
      describeBest(reason);
      restoreBest();
      break;
    }
    if (sinceBest >= params.stall_iterations) {
      reason << "no progress for " << params.stall_iterations << " iterations (" << crossings.size()
             << " crossings and " << insideCount << " vertices inside left; ";
      describeBest(reason);
      reason << ")";
      if (infeasibleLastRound > 0)
        reason << "; " << infeasibleLastRound
               << " impact zones have contradicting constraints, a configuration the body's "
                  "orientation cannot resolve (Sun et al. 2016, Fig. 5)";
      restoreBest();
      break;
    }
    if (budgetSpent()) {
      rep.time_budget_spent = true;
      reason << "time budget " << params.time_budget << " s spent after " << rep.iterations << " iterations ("
             << crossings.size() << " crossings and " << insideCount << " vertices inside left; ";
      describeBest(reason);
      reason << ")";
      restoreBest();
      break;
    }
    ++rep.iterations;

    t0 = clock.now();
    ResolverIteration it;
    std::vector<int> illegal;
    const std::vector<Stencil> stencils = buildStencils(body, garment, topo, crossings, &illegal);
    it.illegal_vertices = illegal.size();
    it.stencils = stencils.size();
    for (int v : illegal)
      if (!everIllegal[v]) {
        everIllegal[v] = 1;
        ++rep.illegal_vertices;
      }
    infeasibleLastRound = 0;
    movedList.clear();
    auto apply = [&](const ZoneSolution& sol) {
      for (std::size_t i = 0; i < sol.vertices.size(); ++i) {
        if (sol.displacement[i].squaredNorm() == 0) continue;
        move(sol.vertices[i], garment.V.row(sol.vertices[i]) + sol.displacement[i].transpose());
      }
    };
    if (params.solver == ZoneSolver::PerStencilProjection) {
      apply(projectStencilsIndependently(stencils, d));
    } else {
      const auto zones = groupImpactZones(stencils, nv);
      it.impact_zones = zones.size();
      rep.impact_zones += zones.size();
      for (const auto& zone : zones) {
        const ZoneSolution sol = solveImpactZone(stencils, zone, d);
        it.max_condition_estimate = std::max(it.max_condition_estimate, sol.condition_estimate);
        if (!sol.feasible) {
          // Contradicting stencils (the body's normals point every way round this spot): any move
          // would be a guess. Leave the zone as it is and report it.
          ++infeasibleLastRound;
          continue;
        }
        apply(sol);
      }
    }
    rep.max_condition_estimate = std::max(rep.max_condition_estimate, it.max_condition_estimate);
    it.infeasible_zones = infeasibleLastRound;
    rep.infeasible_zones += infeasibleLastRound;
    rep.seconds_solve += clock.now() - t0;
    if (movedList.empty()) {
      reason << "no progress possible: all " << infeasibleLastRound << " impact zones left ("
             << crossings.size() << " crossings) have contradicting constraints, a configuration "
             << "the body's orientation cannot resolve (Sun et al. 2016, Fig. 5)";
      if (error() > best) {
        reason << "; ";
        describeBest(reason);
      }
      restoreBest();
      break;
    }
    it.moved_vertices = movedList.size();

    t0 = clock.now();
    redetect();
    rep.seconds_detection += clock.now() - t0;
    if (error() < best)
      newBest();
    else
      ++sinceBest;
    record(it);
  }

  if (!rep.converged && pushedOut)
    reason << " (after pieces found wholly inside were pushed out to their nearest body points)";
  rep.garment_edge_crossings_after = crossings.garment_edges.size();
  rep.body_edge_crossings_after = crossings.body_edges.size();
  if (crossings.size() > 0 && insideTest) {
    const auto in = classifyInside(body, garment, topo, graph, crossings);
    rep.vertices_inside_after = static_cast<std::size_t>(std::count(in.begin(), in.end(), 1));
  }
  double sum = 0;
  for (std::size_t i = 0; i < touchedList.size(); ++i) {
    const double len = (garment.V.row(touchedList[i]) - startPos[i]).norm();
    if (len == 0) continue;
    ++rep.moved_vertices;
    sum += len;
    rep.max_displacement = std::max(rep.max_displacement, len);
  }
  rep.mean_displacement = rep.moved_vertices ? sum / static_cast<double>(rep.moved_vertices) : 0.0;
  rep.reason = reason.str();
  rep.seconds_total = clock.now();
  return rep;
}

}  // namespace virtual_tryon
