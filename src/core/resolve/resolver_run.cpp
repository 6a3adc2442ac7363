#include "core/resolve/resolver_run.h"

#include "virtual_tryon/core/geometry/point_queries.h"

#include "core/geometry/parallel_ranges.h"

#include <algorithm>
#include <cmath>
#include <queue>
#include <utility>

namespace virtual_tryon {
namespace resolver_run {
namespace {

// Passes of the face-middle lift before the rounds (each face clearance projected in turn).
constexpr int kFaceLiftPasses = 2;
// Fewer impact zones than this in a round: one thread solves them (threads cost more than they save).
constexpr int kParallelZones = 4;
// Fewer nearest-point queries than this: one thread answers them.
constexpr int kNearestPerThread = 64;

// |l / l0 - 1| of edge e into `strain`; false for an edge of zero input length.
bool edgeStrain(const TriMesh& input, const TriMesh& garment, const MatrixX2i& E, Eigen::Index e, double& strain) {
  const double l0 = (input.V.row(E(e, 0)) - input.V.row(E(e, 1))).norm();
  if (!(l0 > 0)) return false;
  strain = std::abs((garment.V.row(E(e, 0)) - garment.V.row(E(e, 1))).norm() / l0 - 1);
  return true;
}

// |l / l0 - 1| of each edge of non-zero input length, in edge order; a single 0 when there is none.
std::vector<double> edgeStrains(const TriMesh& input, const TriMesh& garment, const MatrixX2i& E) {
  std::vector<double> s;
  s.reserve(static_cast<std::size_t>(E.rows()));
  double strain = 0;
  for (Eigen::Index e = 0; e < E.rows(); ++e)
    if (edgeStrain(input, garment, E, e, strain)) s.push_back(strain);
  if (s.empty()) s.push_back(0);
  return s;
}

// The largest of edgeStrains.
double maxEdgeStrain(const TriMesh& input, const TriMesh& garment, const MatrixX2i& E) {
  double worst = 0, strain = 0;
  for (Eigen::Index e = 0; e < E.rows(); ++e)
    if (edgeStrain(input, garment, E, e, strain)) worst = std::max(worst, strain);
  return worst;
}

}  // namespace

namespace {

double meanLength(const MatrixX3d& V, const MatrixX2i& E) {
  double sum = 0;
  for (Eigen::Index e = 0; e < E.rows(); ++e) sum += (V.row(E(e, 0)) - V.row(E(e, 1))).norm();
  return E.rows() ? sum / static_cast<double>(E.rows()) : 0.0;
}

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
                     std::vector<char>& dirtyEdge, CrossingSet& crossings, CandidateCache& candidates) {
  for (int f : dirty) {
    dirtyFace[f] = 1;
    for (int k = 0; k < 3; ++k) dirtyEdge[topo.face_edges(f, k)] = 1;
  }
  auto& ge = crossings.garment_edges;
  ge.erase(std::remove_if(ge.begin(), ge.end(),
                          [&](const EdgeFaceCrossing& c) { return dirtyEdge[c.edge] != 0; }),
           ge.end());
  auto& be = crossings.body_edges;
  be.erase(std::remove_if(be.begin(), be.end(),
                          [&](const EdgeFaceCrossing& c) { return dirtyFace[c.face] != 0; }),
           be.end());
  for (int f : dirty) {
    dirtyFace[f] = 0;
    for (int k = 0; k < 3; ++k) dirtyEdge[topo.face_edges(f, k)] = 0;
  }
  CrossingSet fresh;
  detectCrossings(body, garment, topo, fresh, &dirty, candidates);
  ge.insert(ge.end(), fresh.garment_edges.begin(), fresh.garment_edges.end());
  be.insert(be.end(), fresh.body_edges.begin(), fresh.body_edges.end());
}

// How often garment edge e crosses the body, mod 2, from the counts per crossed edge.
int parity(const std::unordered_map<int, int>& flips, int e) {
  const auto it = flips.find(e);
  return it == flips.end() ? 0 : (it->second & 1);
}

}  // namespace

std::shared_ptr<const GarmentConnectivity> connectivityFor(const TriMesh& garment,
                                                           const std::shared_ptr<const GarmentConnectivity>& given) {
  if (given && given->vertices == garment.V.rows() && given->faces == garment.F.rows()) return given;
  return std::make_shared<const GarmentConnectivity>(garment);
}

GarmentGraph::GarmentGraph(const TriMesh& garment, const GarmentTopology& topo) {
  const int nv = static_cast<int>(garment.V.rows());
  facesRoundVertices(garment.F, nv, vf_start, vf);

  adj_start.assign(static_cast<std::size_t>(nv) + 1, 0);
  for (Eigen::Index e = 0; e < topo.edges.rows(); ++e) {
    ++adj_start[topo.edges(e, 0) + 1];
    ++adj_start[topo.edges(e, 1) + 1];
  }
  for (int v = 0; v < nv; ++v) adj_start[v + 1] += adj_start[v];
  adj_v.resize(static_cast<std::size_t>(adj_start[nv]));
  adj_e.resize(adj_v.size());
  std::vector<int> fill(adj_start.begin(), adj_start.end() - 1);
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

ResolverRun::ResolverRun(const Body& body, TriMesh& garment, const ResolverParams& params,
                         const Stopwatch& clock)
    : ResolverRun(body, garment, garment, params, clock) {}

ResolverRun::ResolverRun(const Body& body, const TriMesh& input, TriMesh& garment, const ResolverParams& params,
                         const Stopwatch& clock)
    : body_(body),
      garment_(garment),
      input_(input),
      params_(params),
      clock_(clock),
      nv_(static_cast<int>(garment.V.rows())),
      connectivity_(connectivityFor(garment, params.connectivity)),
      topo_(connectivity_->topo),
      graph_(connectivity_->graph),
      d_((params.clearance > 0 ? params.clearance
                               : params.clearance_fraction * meanLength(input.V, topo_.edges)) +
         std::max(0.0, params.body_uncertainty)),
      insideTest_(params.check_inside && body.closed()),
      warm_(&input != &garment) {
  rep_.body_closed = body.closed();
  rep_.clearance = d_;
  rep_.body_uncertainty = std::max(0.0, params.body_uncertainty);
}

// The first full detection, the inside flags before any move, and the trace's iteration 0. The
// full detection asks the body's tree for each face's own box and keeps nothing: the candidate
// cache (grown boxes, kept lists) serves the faces detected again later, a small part of the
// garment, and is filled for those as they come (on the walk, alternated with filling it here:
// 4-8% less a frame on the jeans and the female T-shirt, the same on the worn dress).
void ResolverRun::detect() {
  double t0 = clock_.now();
  detectCrossings(body_, garment_, topo_, crossings_);
  rep_.seconds_detection += clock_.now() - t0;
  rep_.garment_edge_crossings_before = crossings_.garment_edges.size();
  rep_.body_edge_crossings_before = crossings_.body_edges.size();

  if (insideTest_) {
    t0 = clock_.now();
    insideBefore_ = classifyInside(body_, garment_, topo_, graph_, crossings_);
    pieceInsideBefore_.assign(static_cast<std::size_t>(graph_.pieces), 0);
    for (int v = 0; v < nv_; ++v)
      if (insideBefore_[v]) {
        ++rep_.vertices_inside_before;
        ++pieceInsideBefore_[graph_.piece[v]];
      }
    inside_ = insideBefore_;
    insideCount_ = rep_.vertices_inside_before;
    rep_.seconds_detection += clock_.now() - t0;
  }

  const std::size_t nv = static_cast<std::size_t>(nv_);
  touched_.assign(nv, 0);
  logged_.assign(nv, 0);
  faceMark_.assign(static_cast<std::size_t>(garment_.F.rows()), 0);
  dirtyFace_.assign(faceMark_.size(), 0);
  dirtyEdge_.assign(static_cast<std::size_t>(topo_.edges.rows()), 0);
  unknown_.assign(nv, 0);
  everIllegal_.assign(nv, 0);
  pieceMark_.assign(static_cast<std::size_t>(graph_.pieces), 0);

  record(ResolverIteration());
  bestCrossings_ = crossings_;
  best_ = error();
  bestInside_ = insideCount_;
}

// A trace entry for the state now, shown to the observer (whose time the clock leaves out).
void ResolverRun::record(ResolverIteration it) {
  it.iteration = rep_.iterations;
  it.seconds = clock_.now();
  it.garment_edge_crossings = crossings_.garment_edges.size();
  it.body_edge_crossings = crossings_.body_edges.size();
  it.vertices_inside = insideCount_;
  rep_.trace.push_back(it);
  if (params_.on_iteration) clock_.exclude([&] { params_.on_iteration(rep_.trace.back(), garment_); });
}

// The state now is the best: the undo log starts afresh from it.
void ResolverRun::newBest() {
  for (const auto& u : undo_) logged_[u.v] = 0;
  undo_.clear();
  bestCrossings_ = crossings_;
  best_ = error();
  bestInside_ = insideCount_;
  sinceBest_ = 0;
}

// Back to the best state (when the state now is worse), through the undo log.
void ResolverRun::restoreBest() {
  if (error() <= best_) return;
  for (auto it = undo_.rbegin(); it != undo_.rend(); ++it) {
    garment_.V.row(it->v) = it->x;
    if (insideTest_) inside_[it->v] = it->inside;
  }
  for (const auto& u : undo_) logged_[u.v] = 0;
  undo_.clear();
  crossings_ = bestCrossings_;
  insideCount_ = bestInside_;
}

void ResolverRun::describeBest() {
  reason_ << "best " << best_ << " (crossings + vertices inside), which is returned";
}

// Every move of a garment vertex: keeps its start position, logs it for restoreBest(), and
// lists it for redetect().
void ResolverRun::moveVertex(int v, const Eigen::RowVector3d& to) {
  if (!touched_[v]) {
    touched_[v] = 1;
    touchedList_.push_back(v);
    startPos_.push_back(garment_.V.row(v));
  }
  if (!logged_[v]) {
    logged_[v] = 1;
    undo_.push_back({v, garment_.V.row(v), insideTest_ ? inside_[v] : char(0)});
  }
  garment_.V.row(v) = to;
  movedList_.push_back(v);
}

// Garment faces round the vertices moved in this step (each once), detected again; then the
// moved vertices classified again.
void ResolverRun::redetect() {
  const double t0 = clock_.now();
  redetectFaces();
  if (insideTest_) reclassifyMoved();
  rep_.seconds_detection += clock_.now() - t0;
}

void ResolverRun::redetectFaces() {
  dirty_.clear();
  std::sort(movedList_.begin(), movedList_.end());
  movedList_.erase(std::unique(movedList_.begin(), movedList_.end()), movedList_.end());
  for (int v : movedList_)
    for (int i = graph_.vf_start[v]; i < graph_.vf_start[v + 1]; ++i)
      if (!faceMark_[graph_.vf[i]]) {
        faceMark_[graph_.vf[i]] = 1;
        dirty_.push_back(graph_.vf[i]);
      }
  for (int f : dirty_) faceMark_[f] = 0;
  std::sort(dirty_.begin(), dirty_.end());
  updateCrossings(body_, garment_, topo_, dirty_, dirtyFace_, dirtyEdge_, crossings_, candidates_);
}

// The moved vertices' inside flags: from a neighbour that did not move, across the crossings of
// the edge between them, spread over the moved region; one ray test for a region with no such
// neighbour.
void ResolverRun::reclassifyMoved() {
  std::unordered_map<int, int> flips;
  for (const auto& c : crossings_.garment_edges) ++flips[c.edge];
  for (int v : movedList_) {
    insideCount_ -= static_cast<std::size_t>(inside_[v]);
    unknown_[v] = 1;
  }
  for (int v : movedList_) {
    if (!unknown_[v]) continue;
    for (int i = graph_.adj_start[v]; i < graph_.adj_start[v + 1]; ++i) {
      const int u = graph_.adj_v[i];
      if (unknown_[u]) continue;
      unknown_[v] = 0;
      inside_[v] = static_cast<char>(inside_[u] ^ parity(flips, graph_.adj_e[i]));
      queue_.push_back(v);
      spread(flips);
      break;
    }
  }
  for (int v : movedList_) {
    if (!unknown_[v]) continue;
    unknown_[v] = 0;
    inside_[v] = pointInsideBody(body_, garment_.V.row(v).transpose()) ? 1 : 0;
    queue_.push_back(v);
    spread(flips);
  }
  for (int v : movedList_) insideCount_ += static_cast<std::size_t>(inside_[v]);
}

// Classifies the unknown vertices reachable from the queue, each from the one it was reached from.
void ResolverRun::spread(const std::unordered_map<int, int>& flips) {
  while (!queue_.empty()) {
    const int u = queue_.back();
    queue_.pop_back();
    for (int i = graph_.adj_start[u]; i < graph_.adj_start[u + 1]; ++i) {
      const int w = graph_.adj_v[i];
      if (!unknown_[w]) continue;
      unknown_[w] = 0;
      inside_[w] = static_cast<char>(inside_[u] ^ parity(flips, graph_.adj_e[i]));
      queue_.push_back(w);
    }
  }
}

// With no crossing every piece lies wholly inside or wholly outside. Pieces no vertex of which
// moved keep their status; a moved piece takes it from a vertex that did not move, or from one
// ray test when all of them moved. Returns the vertices inside; `insidePieces` lists the moved
// pieces now inside and the unmoved pieces that were inside from the start.
std::size_t ResolverRun::insideNow(std::vector<int>& insidePieces) {
  insidePieces.clear();
  std::size_t n = rep_.vertices_inside_before;
  std::vector<int> movedPieces;
  for (int v : touchedList_) {
    const int p = graph_.piece[v];
    if (p < 0 || pieceMark_[p]) continue;
    pieceMark_[p] = 1;
    movedPieces.push_back(p);
  }
  for (int p : movedPieces) {
    n -= static_cast<std::size_t>(pieceInsideBefore_[p]);
    int known = -1;
    for (int i = graph_.piece_start[p]; i < graph_.piece_start[p + 1]; ++i)
      if (!touched_[graph_.piece_members[i]]) {
        known = graph_.piece_members[i];
        break;
      }
    const int first = graph_.piece_members[graph_.piece_start[p]];
    const bool in =
        known >= 0 ? insideBefore_[known] != 0 : pointInsideBody(body_, garment_.V.row(first).transpose());
    if (in) {
      n += static_cast<std::size_t>(graph_.pieceSize(p));
      insidePieces.push_back(p);
    }
  }
  for (int p = 0; p < graph_.pieces && n > 0; ++p)
    if (!pieceMark_[p] && pieceInsideBefore_[p] > 0) insidePieces.push_back(p);
  for (int p : movedPieces) pieceMark_[p] = 0;
  return n;
}

bool ResolverRun::decideStopCrossingFree() {
  if (!insideTest_) {
    rep_.converged = true;
    reason_ << "no edge-face crossing left";
    return true;
  }
  const double t0 = clock_.now();
  const std::size_t nInside = insideNow(insidePieces_);
  rep_.seconds_detection += clock_.now() - t0;
  if (nInside == 0) {
    insideCount_ = 0;
    rep_.converged = true;
    reason_ << "no edge-face crossing left, no garment vertex inside the body";
    return true;
  }
  rep_.vertices_inside_after = nInside;
  if (!params_.push_out_inside || pushedOut_ || rep_.iterations >= params_.max_iterations) {
    reason_ << nInside << " garment vertices lie wholly inside the body with no crossing edge"
            << (params_.push_out_inside ? " (still inside after pushing them out)" : "");
    return true;
  }
  if (budgetSpent()) {
    rep_.time_budget_spent = true;
    reason_ << "time budget " << params_.time_budget << " s spent with " << nInside
            << " garment vertices wholly inside the body";
    return true;
  }
  return false;
}

// Push each vertex of a piece wholly inside (as decideStopCrossingFree() found them) to its
// nearest body point plus the clearance.
void ResolverRun::pushOutInsidePieces() {
  const double t0 = clock_.now();
  movedList_.clear();
  std::vector<int> members;
  for (int p : insidePieces_)
    for (int i = graph_.piece_start[p]; i < graph_.piece_start[p + 1]; ++i) members.push_back(graph_.piece_members[i]);
  const std::vector<ClosestPoint> nearest = nearestBodyPoints(members);
  for (std::size_t i = 0; i < members.size(); ++i) pushTo(members[i], nearest[i]);
  pushedOut_ = true;
  rep_.vertices_inside_after = 0;
  finishPushOut(t0, true);
}

void ResolverRun::pushTo(int v, const ClosestPoint& cp) {
  moveVertex(v, (cp.point + d_ * body_.faceNormal(cp.face)).transpose());
}

// The solve time since t0, the crossings round the moved vertices, the best state, the trace.
void ResolverRun::finishPushOut(double t0, bool alwaysNewBest) {
  ResolverIteration it;
  it.push_out = true;
  it.moved_vertices = movedList_.size();
  rep_.seconds_solve += clock_.now() - t0;
  redetect();
  if (alwaysNewBest || error() < best_) newBest();
  record(it);
}

// The nearest body point of each listed garment vertex (as it is now), the queries shared among
// the hardware threads (each independent of the others).
std::vector<ClosestPoint> ResolverRun::nearestBodyPoints(const std::vector<int>& vertices) const {
  std::vector<ClosestPoint> nearest(vertices.size());
  parallelRanges(static_cast<int>(vertices.size()), kNearestPerThread, [&](int first, int last) {
    for (int i = first; i < last; ++i)
      nearest[static_cast<std::size_t>(i)] =
          closestPointOnBody(body_, garment_.V.row(vertices[static_cast<std::size_t>(i)]).transpose());
  });
  return nearest;
}

void ResolverRun::pushOutInsideVertices() {
  if (!insideTest_ || insideCount_ == 0 || budgetSpent()) return;
  const double t0 = clock_.now();
  movedList_.clear();
  std::vector<int> inside;
  for (int v = 0; v < nv_; ++v)
    if (inside_[v]) inside.push_back(v);
  const std::vector<ClosestPoint> nearest = nearestBodyPoints(inside);
  for (std::size_t i = 0; i < inside.size(); ++i) pushTo(inside[i], nearest[i]);
  finishPushOut(t0, false);
}

void ResolverRun::pushOutNearVertices() {
  if (budgetSpent()) return;
  const double t0 = clock_.now();
  movedList_.clear();
  std::vector<double> distance(static_cast<std::size_t>(nv_));
  std::vector<int> all(static_cast<std::size_t>(nv_));
  for (int v = 0; v < nv_; ++v) all[static_cast<std::size_t>(v)] = v;
  const std::vector<ClosestPoint> nearest = nearestBodyPoints(all);
  for (int v = 0; v < nv_; ++v) {
    const ClosestPoint& cp = nearest[static_cast<std::size_t>(v)];
    distance[v] = cp.distance;
    if ((insideTest_ && inside_[v]) || cp.distance < d_) {
      pushTo(v, cp);
      distance[v] = d_;
      ++rep_.near_vertices_pushed;
    }
  }
  if (params_.relaxation.face_clearance >= 0) liftFaceMiddles(distance);
  finishPushOut(t0, false);
}

// The faces whose middle passes nearer to the body than the clearance (face_clearance.h), their
// corners lifted together along the body vertex's normal until it clears; a face with a corner
// farther from the body than the clearance plus the face's reach from it is skipped.
void ResolverRun::liftFaceMiddles(const std::vector<double>& distance) {
  std::vector<FaceClearance> found;
  for (Eigen::Index f = 0; f < garment_.F.rows(); ++f) {
    bool clear = false;
    for (int k = 0; k < 3 && !clear; ++k)
      clear = distance[garment_.F(f, k)] > cornerReach(garment_, static_cast<int>(f), k) + d_;
    if (!clear) faceClearances(body_, garment_, static_cast<int>(f), d_, found);
  }
  std::vector<char> lifted(static_cast<std::size_t>(nv_), 0);
  for (int pass = 0; pass < kFaceLiftPasses; ++pass)
    for (const FaceClearance& k : found) {
      const double shortBy = shortfall(k, garment_);
      if (!(shortBy > 0)) continue;
      for (int i = 0; i < 3; ++i) {
        const int v = garment_.F(k.face, i);
        moveVertex(v, garment_.V.row(v) + shortBy * k.normal.transpose());
        if (!lifted[v] && distance[v] > d_) ++rep_.near_vertices_pushed;  // not pushed before
        lifted[v] = 1;
      }
    }
}

bool ResolverRun::decideStop() {
  if (rep_.iterations >= params_.max_iterations) {
    reason_ << "iteration limit " << params_.max_iterations << " reached with " << crossings_.size()
            << " crossings and " << insideCount_ << " vertices inside left; ";
    describeBest();
    restoreBest();
    return true;
  }
  if (sinceBest_ >= params_.stall_iterations) {
    reason_ << "no progress for " << params_.stall_iterations << " iterations (" << crossings_.size()
            << " crossings and " << insideCount_ << " vertices inside left; ";
    describeBest();
    reason_ << ")";
    if (infeasibleLastRound_ > 0)
      reason_ << "; " << infeasibleLastRound_
              << " impact zones have contradicting constraints, a configuration the body's "
                 "orientation cannot resolve (Sun et al. 2016, Fig. 5)";
    restoreBest();
    return true;
  }
  if (budgetSpent()) {
    rep_.time_budget_spent = true;
    reason_ << "time budget " << params_.time_budget << " s spent after " << rep_.iterations
            << " iterations (" << crossings_.size() << " crossings and " << insideCount_
            << " vertices inside left; ";
    describeBest();
    reason_ << ")";
    restoreBest();
    return true;
  }
  return false;
}

// Stencils from the crossings, impact zones, their solves, the moves; then detection again.
bool ResolverRun::solveRound() {
  ++rep_.iterations;

  const double t0 = clock_.now();
  ResolverIteration it;
  const std::vector<Stencil> stencils = roundStencils(it);
  infeasibleLastRound_ = 0;
  movedList_.clear();
  if (params_.solver == ZoneSolver::PerStencilProjection)
    apply(projectStencilsIndependently(stencils, d_));
  else
    solveZones(stencils, it);
  rep_.max_condition_estimate = std::max(rep_.max_condition_estimate, it.max_condition_estimate);
  it.infeasible_zones = infeasibleLastRound_;
  rep_.infeasible_zones += infeasibleLastRound_;
  rep_.seconds_solve += clock_.now() - t0;
  if (movedList_.empty()) {
    stopNothingMoved();
    return false;
  }
  it.moved_vertices = movedList_.size();

  redetect();
  if (error() < best_)
    newBest();
  else
    ++sinceBest_;
  record(it);
  return true;
}

// This round's stencils, counting the vertices found illegal (in the round, and once each in the run).
std::vector<Stencil> ResolverRun::roundStencils(ResolverIteration& it) {
  std::vector<int> illegal;
  std::vector<Stencil> stencils = buildStencils(body_, garment_, topo_, crossings_, &illegal);
  it.illegal_vertices = illegal.size();
  it.stencils = stencils.size();
  for (int v : illegal)
    if (!everIllegal_[v]) {
      everIllegal_[v] = 1;
      ++rep_.illegal_vertices;
    }
  return stencils;
}

void ResolverRun::solveZones(const std::vector<Stencil>& stencils, ResolverIteration& it) {
  const auto zones = groupImpactZones(stencils, nv_);
  it.impact_zones = zones.size();
  rep_.impact_zones += zones.size();
  // The zones share no garment vertex: they are solved on the hardware threads, then applied in
  // their order (the same moves whatever the number of threads).
  std::vector<ZoneSolution> solutions(zones.size());
  parallelItems(static_cast<int>(zones.size()), kParallelZones, [&](int z) {
    solutions[static_cast<std::size_t>(z)] = solveImpactZone(stencils, zones[static_cast<std::size_t>(z)], d_);
  });
  for (const ZoneSolution& sol : solutions) {
    it.max_condition_estimate = std::max(it.max_condition_estimate, sol.condition_estimate);
    if (!sol.feasible) {
      // Contradicting stencils (the body's normals point every way round this spot): any move
      // would be a guess. Leave the zone as it is and report it.
      ++infeasibleLastRound_;
      continue;
    }
    apply(sol);
  }
}

void ResolverRun::apply(const ZoneSolution& sol) {
  for (std::size_t i = 0; i < sol.vertices.size(); ++i) {
    if (sol.displacement[i].squaredNorm() == 0) continue;
    moveVertex(sol.vertices[i], garment_.V.row(sol.vertices[i]) + sol.displacement[i].transpose());
  }
}

// A round that moved nothing: every zone left is infeasible.
void ResolverRun::stopNothingMoved() {
  reason_ << "no progress possible: all " << infeasibleLastRound_ << " impact zones left ("
          << crossings_.size() << " crossings) have contradicting constraints, a configuration "
          << "the body's orientation cannot resolve (Sun et al. 2016, Fig. 5)";
  if (error() > best_) {
    reason_ << "; ";
    describeBest();
  }
  restoreBest();
}

bool ResolverRun::relaxShape() {
  if (params_.objective != ResolverObjective::Smooth || !rep_.converged) return false;
  ShapeRelaxationParams relaxation = params_.relaxation;
  if (params_.time_budget > 0) {  // what is left of the run's budget, if anything
    const double left = params_.time_budget - clock_.now();
    if (left <= 0) return false;
    relaxation.time_budget = relaxation.time_budget > 0 ? std::min(relaxation.time_budget, left) : left;
  }
  if (params_.body_uncertainty > 0 && relaxation.face_clearance == 0) relaxation.face_clearance = d_;
  const double t0 = clock_.now();
  rep_.max_edge_strain_before_relaxation = maxEdgeStrain(input_, garment_, topo_.edges);
  if (warm_ && params_.warm_local_relaxation) {
    relaxation.local = true;
    relaxation.seeds = movedByRounds();
    rep_.relaxation = resolver_run::relaxShape(body_, input_, garment_, topo_, graph_, d_, relaxation, &candidates_);
    rep_.max_edge_strain_after_local_relaxation = maxEdgeStrain(input_, garment_, topo_.edges);
    rep_.relaxation_widened = rep_.max_edge_strain_after_local_relaxation > params_.warm_full_relaxation_strain;
    relaxation.local = false;
  }
  if (rep_.relaxation_widened && params_.time_budget > 0) {
    const double left = params_.time_budget - clock_.now();
    if (left <= 0) rep_.relaxation_widened = false;  // keep the local result, clean as it is
    relaxation.time_budget = relaxation.time_budget > 0 ? std::min(relaxation.time_budget, left) : left;
  }
  if (!rep_.relaxation.local || rep_.relaxation_widened)
    rep_.relaxation = resolver_run::relaxShape(body_, input_, garment_, topo_, graph_, d_, relaxation, &candidates_);
  rep_.relaxed = true;
  rep_.seconds_relaxation = clock_.now() - t0;
  return true;
}

// The vertices the rounds (and push-outs) moved away from where the run started them.
std::vector<int> ResolverRun::movedByRounds() const {
  std::vector<int> moved;
  for (std::size_t i = 0; i < touchedList_.size(); ++i)
    if ((garment_.V.row(touchedList_[i]) - startPos_[i]).squaredNorm() > 0) moved.push_back(touchedList_[i]);
  return moved;
}

ResolverReport ResolverRun::finish() {
  if (!rep_.converged && pushedOut_)
    reason_ << " (after pieces found wholly inside were pushed out to their nearest body points)";
  rep_.garment_edge_crossings_after = crossings_.garment_edges.size();
  rep_.body_edge_crossings_after = crossings_.body_edges.size();
  if (crossings_.size() > 0 && insideTest_) {
    const auto in = classifyInside(body_, garment_, topo_, graph_, crossings_);
    rep_.vertices_inside_after = static_cast<std::size_t>(std::count(in.begin(), in.end(), 1));
  }
  displacementStats();
  shapeStats();
  rep_.objective = params_.objective == ResolverObjective::Smooth ? "smooth" : "paper";
  rep_.reason = reason_.str();
  rep_.seconds_total = clock_.now();
  return std::move(rep_);
}

// Moved vertices (those that end away from their start), mean and largest displacement.
void ResolverRun::displacementStats() {
  double sum = 0;
  if (rep_.relaxed) {  // the relaxation moves vertices the rounds never touched
    for (int v = 0; v < nv_; ++v) {
      const double len = (garment_.V.row(v) - input_.V.row(v)).norm();
      if (len == 0) continue;
      ++rep_.moved_vertices;
      sum += len;
      rep_.max_displacement = std::max(rep_.max_displacement, len);
    }
    rep_.mean_displacement = rep_.moved_vertices ? sum / static_cast<double>(rep_.moved_vertices) : 0.0;
    return;
  }
  for (std::size_t i = 0; i < touchedList_.size(); ++i) {
    const double len = (garment_.V.row(touchedList_[i]) - startPos_[i]).norm();
    if (len == 0) continue;
    ++rep_.moved_vertices;
    sum += len;
    rep_.max_displacement = std::max(rep_.max_displacement, len);
  }
  rep_.mean_displacement = rep_.moved_vertices ? sum / static_cast<double>(rep_.moved_vertices) : 0.0;
}

// The largest strain and the 99th percentile's (the value at that rank of the sorted strains,
// found without sorting them all).
void ResolverRun::shapeStats() {
  std::vector<double> strain = edgeStrains(input_, garment_, topo_.edges);
  rep_.max_edge_strain = *std::max_element(strain.begin(), strain.end());
  const std::size_t rank = static_cast<std::size_t>(std::ceil(0.99 * static_cast<double>(strain.size())));
  const auto at = strain.begin() + static_cast<std::ptrdiff_t>(std::max<std::size_t>(rank, 1) - 1);
  std::nth_element(strain.begin(), at, strain.end());
  rep_.p99_edge_strain = *at;
}

}  // namespace resolver_run

std::shared_ptr<const GarmentConnectivity> garmentConnectivity(const TriMesh& garment) {
  return std::make_shared<const GarmentConnectivity>(garment);
}

}  // namespace virtual_tryon
