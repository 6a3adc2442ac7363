#include "virtual_tryon/core/penetration_resolver.h"

#include "virtual_tryon/core/impact_zones.h"
#include "virtual_tryon/core/intersections.h"
#include "virtual_tryon/core/point_queries.h"
#include "virtual_tryon/core/stencils.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <queue>
#include <sstream>

namespace virtual_tryon {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double meanLength(const MatrixX3d& V, const MatrixX2i& E) {
  double sum = 0;
  for (Eigen::Index e = 0; e < E.rows(); ++e) sum += (V.row(E(e, 0)) - V.row(E(e, 1))).norm();
  return E.rows() ? sum / static_cast<double>(E.rows()) : 0.0;
}

// Inside/outside for every garment vertex of a closed body, with one ray test per connected
// piece: across a garment edge the side flips once per crossing of that edge with a body face.
std::vector<char> classifyInside(const Body& body, const TriMesh& garment,
                                 const GarmentTopology& topo, const CrossingSet& crossings) {
  const int nv = static_cast<int>(garment.V.rows());
  std::vector<int> flips(static_cast<std::size_t>(topo.edges.rows()), 0);
  for (const auto& c : crossings.garment_edges) ++flips[c.edge];
  std::vector<std::vector<std::pair<int, int>>> adj(static_cast<std::size_t>(nv));
  for (Eigen::Index e = 0; e < topo.edges.rows(); ++e) {
    adj[topo.edges(e, 0)].push_back({topo.edges(e, 1), static_cast<int>(e)});
    adj[topo.edges(e, 1)].push_back({topo.edges(e, 0), static_cast<int>(e)});
  }
  std::vector<char> inside(static_cast<std::size_t>(nv), 0), seen(static_cast<std::size_t>(nv), 0);
  for (int s = 0; s < nv; ++s) {
    if (seen[s] || adj[s].empty()) continue;
    seen[s] = 1;
    inside[s] = pointInsideBody(body, garment.V.row(s).transpose()) ? 1 : 0;
    std::queue<int> q;
    q.push(s);
    while (!q.empty()) {
      const int u = q.front();
      q.pop();
      for (const auto& [v, e] : adj[u]) {
        if (seen[v]) continue;
        seen[v] = 1;
        inside[v] = static_cast<char>(inside[u] ^ (flips[e] & 1));
        q.push(v);
      }
    }
  }
  return inside;
}

// Garment faces that touch any vertex flagged in `moved`.
std::vector<int> facesTouching(const TriMesh& garment, const std::vector<char>& moved) {
  std::vector<int> faces;
  for (Eigen::Index f = 0; f < garment.F.rows(); ++f)
    if (moved[garment.F(f, 0)] || moved[garment.F(f, 1)] || moved[garment.F(f, 2)])
      faces.push_back(static_cast<int>(f));
  return faces;
}

// Re-detects only around the faces in `dirty`: crossings of untouched edges and faces stay.
void updateCrossings(const Body& body, const TriMesh& garment, const GarmentTopology& topo,
                     const std::vector<int>& dirty, CrossingSet& crossings) {
  std::vector<char> dirtyFace(static_cast<std::size_t>(garment.F.rows()), 0);
  std::vector<char> dirtyEdge(static_cast<std::size_t>(topo.edges.rows()), 0);
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
  CrossingSet fresh;
  detectCrossings(body, garment, topo, fresh, &dirty);
  ge.insert(ge.end(), fresh.garment_edges.begin(), fresh.garment_edges.end());
  be.insert(be.end(), fresh.body_edges.begin(), fresh.body_edges.end());
}

}  // namespace

ResolverReport resolvePenetrations(const Body& body, TriMesh& garment, const ResolverParams& params) {
  const auto tStart = Clock::now();
  ResolverReport rep;
  rep.body_closed = body.closed();
  const TriMesh original = garment;
  const GarmentTopology topo(garment);
  const double d = params.clearance > 0 ? params.clearance
                                        : params.clearance_fraction * meanLength(garment.V, topo.edges);
  rep.clearance = d;
  const bool insideTest = params.check_inside && body.closed();

  auto t0 = Clock::now();
  CrossingSet crossings;
  detectCrossings(body, garment, topo, crossings);
  rep.seconds_detection += since(t0);
  rep.garment_edge_crossings_before = crossings.garment_edges.size();
  rep.body_edge_crossings_before = crossings.body_edges.size();
  if (insideTest) {
    const auto inside = classifyInside(body, garment, topo, crossings);
    rep.vertices_inside_before = static_cast<std::size_t>(std::count(inside.begin(), inside.end(), 1));
  }

  std::vector<char> everIllegal(static_cast<std::size_t>(garment.V.rows()), 0);
  std::vector<char> moved(static_cast<std::size_t>(garment.V.rows()), 0);
  std::size_t best = crossings.size();
  int sinceBest = 0;
  bool pushedOut = false;
  std::size_t infeasibleLastRound = 0;
  std::ostringstream reason;

  for (;;) {
    if (crossings.size() == 0) {
      if (!insideTest) {
        rep.converged = true;
        reason << "no edge-face crossing left";
        break;
      }
      // No crossing: every connected piece is wholly inside or wholly outside.
      t0 = Clock::now();
      const auto inside = classifyInside(body, garment, topo, crossings);
      rep.seconds_detection += since(t0);
      const auto nInside = static_cast<std::size_t>(std::count(inside.begin(), inside.end(), 1));
      if (nInside == 0) {
        rep.converged = true;
        reason << "no edge-face crossing left, no garment vertex inside the body";
        break;
      }
      if (!params.push_out_inside || pushedOut || rep.iterations >= params.max_iterations) {
        rep.vertices_inside_after = nInside;
        reason << nInside << " garment vertices lie wholly inside the body with no crossing edge"
               << (params.push_out_inside ? " (still inside after pushing them out)" : "");
        break;
      }
      // Push each inside vertex to its nearest body point plus the clearance, then go on.
      t0 = Clock::now();
      std::fill(moved.begin(), moved.end(), 0);
      for (Eigen::Index v = 0; v < garment.V.rows(); ++v) {
        if (!inside[v]) continue;
        const ClosestPoint cp = closestPointOnBody(body, garment.V.row(v).transpose());
        garment.V.row(v) = (cp.point + d * body.faceNormals().row(cp.face).transpose()).transpose();
        moved[v] = 1;
      }
      rep.seconds_solve += since(t0);
      pushedOut = true;
      t0 = Clock::now();
      updateCrossings(body, garment, topo, facesTouching(garment, moved), crossings);
      rep.seconds_detection += since(t0);
      best = crossings.size();
      sinceBest = 0;
      continue;
    }
    if (rep.iterations >= params.max_iterations) {
      reason << "iteration limit " << params.max_iterations << " reached with " << crossings.size()
             << " crossings left";
      break;
    }
    if (sinceBest >= params.stall_iterations) {
      reason << "no progress for " << params.stall_iterations << " iterations (" << crossings.size()
             << " crossings left, best " << best << ")";
      if (infeasibleLastRound > 0)
        reason << "; " << infeasibleLastRound
               << " impact zones have contradicting constraints, a configuration the body's "
                  "orientation cannot resolve (Sun et al. 2016, Fig. 5)";
      break;
    }
    ++rep.iterations;

    t0 = Clock::now();
    std::vector<int> illegal;
    const std::vector<Stencil> stencils = buildStencils(body, garment, topo, crossings, &illegal);
    for (int v : illegal) everIllegal[v] = 1;
    const auto zones = groupImpactZones(stencils, static_cast<int>(garment.V.rows()));
    rep.impact_zones += zones.size();
    infeasibleLastRound = 0;
    std::fill(moved.begin(), moved.end(), 0);
    for (const auto& zone : zones) {
      const ZoneSolution sol = solveImpactZone(stencils, zone, d);
      if (!sol.feasible) {
        // Contradicting stencils (the body's normals point every way round this spot): any move
        // would be a guess. Leave the zone as it is and report it.
        ++infeasibleLastRound;
        continue;
      }
      for (std::size_t i = 0; i < sol.vertices.size(); ++i) {
        if (sol.displacement[i].squaredNorm() == 0) continue;
        garment.V.row(sol.vertices[i]) += sol.displacement[i].transpose();
        moved[sol.vertices[i]] = 1;
      }
    }
    rep.infeasible_zones += infeasibleLastRound;
    rep.seconds_solve += since(t0);
    if (std::find(moved.begin(), moved.end(), 1) == moved.end()) {
      reason << "no progress possible: all " << infeasibleLastRound << " impact zones left ("
             << crossings.size() << " crossings) have contradicting constraints, a configuration "
             << "the body's orientation cannot resolve (Sun et al. 2016, Fig. 5)";
      break;
    }

    t0 = Clock::now();
    updateCrossings(body, garment, topo, facesTouching(garment, moved), crossings);
    rep.seconds_detection += since(t0);
    if (crossings.size() < best) {
      best = crossings.size();
      sinceBest = 0;
    } else {
      ++sinceBest;
    }
  }

  rep.garment_edge_crossings_after = crossings.garment_edges.size();
  rep.body_edge_crossings_after = crossings.body_edges.size();
  if (crossings.size() > 0 && insideTest) {
    const auto inside = classifyInside(body, garment, topo, crossings);
    rep.vertices_inside_after = static_cast<std::size_t>(std::count(inside.begin(), inside.end(), 1));
  }
  rep.illegal_vertices = static_cast<std::size_t>(std::count(everIllegal.begin(), everIllegal.end(), 1));
  double sum = 0;
  for (Eigen::Index v = 0; v < garment.V.rows(); ++v) {
    const double len = (garment.V.row(v) - original.V.row(v)).norm();
    if (len == 0) continue;
    ++rep.moved_vertices;
    sum += len;
    rep.max_displacement = std::max(rep.max_displacement, len);
  }
  rep.mean_displacement = rep.moved_vertices ? sum / static_cast<double>(rep.moved_vertices) : 0.0;
  rep.reason = reason.str();
  rep.seconds_total = since(tStart);
  return rep;
}

}  // namespace virtual_tryon
