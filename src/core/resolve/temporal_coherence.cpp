#include "virtual_tryon/core/resolve/temporal_coherence.h"

#include "virtual_tryon/core/geometry/point_queries.h"
#include "virtual_tryon/core/resolve/intersections.h"

#include "core/resolve/resolver_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

namespace virtual_tryon {
namespace {

double largestChange(const MatrixX3d& V, const MatrixX3d& input, const MatrixX3d& previous) {
  return V.rows() ? ((V - input) - previous).rowwise().norm().maxCoeff() : 0.0;
}

// A patch of vertices where they are now keeps the frame clean and its shape: no edge of the patch
// is strained (against the input) past max(maxStrain, its strain as resolved), their faces and
// edges cross nothing, none is inside the body, and each is at least its floor from it.
class MoveCheck {
 public:
  MoveCheck(const Body& body, const TriMesh& garment, const MatrixX3d& input, const MatrixX3d& resolved,
            double maxStrain, const std::shared_ptr<const GarmentConnectivity>& given)
      : body_(body), garment_(garment), input_(input), resolved_(resolved), max_strain_(maxStrain),
        connectivity_(resolver_run::connectivityFor(garment, given)), topo_(connectivity_->topo),
        graph_(connectivity_->graph) {
    mark_.assign(static_cast<std::size_t>(garment.F.rows()), 0);
  }
  std::size_t strainRefusals() const { return strain_refusals_; }
  bool clean(const std::vector<int>& patch, const std::vector<double>& floors) {
    if (!keepsShape(patch)) {
      ++strain_refusals_;
      return false;
    }
    around_.clear();
    for (int v : patch)
      for (int i = graph_.vf_start[static_cast<std::size_t>(v)]; i < graph_.vf_start[static_cast<std::size_t>(v) + 1]; ++i) {
        const int f = graph_.vf[static_cast<std::size_t>(i)];
        if (!mark_[static_cast<std::size_t>(f)]) {
          mark_[static_cast<std::size_t>(f)] = 1;
          around_.push_back(f);
        }
      }
    for (int f : around_) mark_[static_cast<std::size_t>(f)] = 0;
    if (patch.size() > 1) std::sort(around_.begin(), around_.end());
    detectCrossings(body_, garment_, topo_, crossings_, &around_);
    if (crossings_.size() > 0) return false;
    for (std::size_t i = 0; i < patch.size(); ++i) {
      const Eigen::Vector3d p = garment_.V.row(patch[i]).transpose();
      if (pointInsideBody(body_, p)) return false;
      if (floors[i] > 0 && closestPointOnBody(body_, p).distance < floors[i]) return false;
    }
    return true;
  }
  double distance(int v) const { return closestPointOnBody(body_, garment_.V.row(v).transpose()).distance; }
  const resolver_run::GarmentGraph& graph() const { return graph_; }

 private:
  // No edge at a vertex of the patch strained past max(max_strain_, its strain as resolved).
  bool keepsShape(const std::vector<int>& patch) const {
    if (!(max_strain_ > 0)) return true;
    for (int v : patch)
      for (int i = graph_.adj_start[static_cast<std::size_t>(v)]; i < graph_.adj_start[static_cast<std::size_t>(v) + 1]; ++i) {
        const int j = graph_.adj_v[static_cast<std::size_t>(i)];
        const double now = resolver_run::edgeStrain(input_, garment_.V, v, j);
        if (now > max_strain_ && now > resolver_run::edgeStrain(input_, resolved_, v, j) * (1 + 1e-9)) return false;
      }
    return true;
  }

  const Body& body_;
  const TriMesh& garment_;
  const MatrixX3d& input_;
  const MatrixX3d& resolved_;
  const double max_strain_;
  std::size_t strain_refusals_ = 0;
  std::shared_ptr<const GarmentConnectivity> connectivity_;
  const GarmentTopology& topo_;
  const resolver_run::GarmentGraph& graph_;  // the faces round each vertex, the neighbours over edges
  std::vector<int> around_;
  std::vector<char> mark_;
  CrossingSet crossings_;
};

// Vertex v and `rings` rings of its neighbours over the garment's edges (v first).
class Patches {
 public:
  explicit Patches(const resolver_run::GarmentGraph& graph)
      : start_(graph.adj_start), next_(graph.adj_v), seen_(graph.vf_start.size(), 0) {}
  std::vector<int> around(int v, int rings) {
    std::vector<int> patch{v};
    seen_[static_cast<std::size_t>(v)] = 1;
    for (std::size_t begin = 0, r = 0; r < static_cast<std::size_t>(std::max(0, rings)); ++r) {
      const std::size_t end = patch.size();
      for (std::size_t i = begin; i < end; ++i)
        for (int k = start_[static_cast<std::size_t>(patch[i])]; k < start_[static_cast<std::size_t>(patch[i]) + 1]; ++k) {
          const int u = next_[static_cast<std::size_t>(k)];
          if (!seen_[static_cast<std::size_t>(u)]) {
            seen_[static_cast<std::size_t>(u)] = 1;
            patch.push_back(u);
          }
        }
      begin = end;
    }
    for (int u : patch) seen_[static_cast<std::size_t>(u)] = 0;
    return patch;
  }

 private:
  const std::vector<int>& start_;
  const std::vector<int>& next_;
  std::vector<char> seen_;
};

// The previous correction on this frame's input, p, lies inside the body deeper than `limit`:
// every clean position is outside, and a segment from p to a point outside leaves through the
// surface, at least p's depth away, so no clean position is within `limit` of p.
bool forcedByInput(const Body& body, const Eigen::RowVector3d& p, double limit) {
  const Eigen::Vector3d q = p.transpose();
  return pointInsideBody(body, q) && closestPointOnBody(body, q).distance > limit;
}

}  // namespace

CoherenceReport limitCorrectionChange(const Body& body, TriMesh& garment, const MatrixX3d& input,
                                      const MatrixX3d& previousCorrection, const CoherenceParams& params) {
  const auto t0 = std::chrono::steady_clock::now();
  CoherenceReport rep;
  const Eigen::Index n = garment.V.rows();
  if (input.rows() != n || previousCorrection.rows() != n) {
    rep.message = "the input and the previous correction need the garment's " + std::to_string(n) + " rows";
    return rep;
  }
  rep.change_before = rep.change_after = rep.change_after_unforced = largestChange(garment.V, input, previousCorrection);
  const double limit = params.max_change;
  if (!(limit > 0) || rep.change_before <= limit) return rep;
  std::vector<int> over;
  for (Eigen::Index v = 0; v < n; ++v)
    if (((garment.V.row(v) - input.row(v)) - previousCorrection.row(v)).norm() > limit) over.push_back(static_cast<int>(v));
  rep.candidates = over.size();
  const MatrixX3d resolved = garment.V;
  MoveCheck check(body, garment, input, resolved, params.max_strain, params.connectivity);
  Patches patches(check.graph());
  // Per vertex: the clearance it keeps when it moves (the limit, or as far as it was if nearer);
  // -1 until it first moves.
  std::vector<double> floor(static_cast<std::size_t>(n), -1.0);
  auto floorOf = [&](int u) {
    double& f = floor[static_cast<std::size_t>(u)];
    if (f < 0) f = params.min_clearance > 0 ? std::min(params.min_clearance, check.distance(u)) * (1 - 1e-9) : 0.0;
    return f;
  };
  std::vector<int> patch;
  std::vector<double> floors;
  MatrixX3d from, step;
  for (int pass = 0; pass < std::max(1, params.passes); ++pass) {
    bool moved = false;
    for (const int v : over) {
      const Eigen::RowVector3d change = (garment.V.row(v) - input.row(v)) - previousCorrection.row(v);
      const double len = change.norm();
      if (len <= limit * (1 + 1e-9)) continue;
      // v to a change of the limit, its rings the same fraction of their own way back.
      const double fraction = 1.0 - limit / len;
      patch = patches.around(v, params.rings);
      floors.resize(patch.size());
      from.resize(static_cast<Eigen::Index>(patch.size()), 3);
      step.resize(from.rows(), 3);
      for (std::size_t i = 0; i < patch.size(); ++i) {
        const int u = patch[i];
        floors[i] = floorOf(u);
        from.row(static_cast<Eigen::Index>(i)) = garment.V.row(u);
        step.row(static_cast<Eigen::Index>(i)) = -fraction * ((garment.V.row(u) - input.row(u)) - previousCorrection.row(u));
      }
      auto place = [&](double t) {
        for (std::size_t i = 0; i < patch.size(); ++i)
          garment.V.row(patch[i]) = from.row(static_cast<Eigen::Index>(i)) + t * step.row(static_cast<Eigen::Index>(i));
      };
      // The whole step, else the largest clean part of it found by bisection (the resolved
      // position, part 0, is clean).
      double lo = 0, hi = 1;
      place(1);
      if (check.clean(patch, floors)) lo = 1;
      for (int b = 0; b < std::max(0, params.bisections) && lo < 1; ++b) {
        const double mid = 0.5 * (lo + hi);
        place(mid);
        (check.clean(patch, floors) ? lo : hi) = mid;
      }
      place(lo);
      moved = moved || lo > 0;
    }
    if (!moved) break;
  }
  std::vector<char> forced(static_cast<std::size_t>(n), 0);
  for (int v : over) {
    const double before = ((resolved.row(v) - input.row(v)) - previousCorrection.row(v)).norm();
    const double after = ((garment.V.row(v) - input.row(v)) - previousCorrection.row(v)).norm();
    if (after <= limit * (1 + 1e-9)) {
      ++rep.limited;
      continue;
    }
    ++(after < before ? rep.partly : rep.held);
    if (forcedByInput(body, input.row(v) + previousCorrection.row(v), limit)) {
      forced[static_cast<std::size_t>(v)] = 1;
      ++rep.forced_by_input;
    }
  }
  const Eigen::VectorXd change = ((garment.V - input) - previousCorrection).rowwise().norm();
  rep.change_after = rep.change_after_unforced = 0;
  for (Eigen::Index v = 0; v < n; ++v) {
    rep.change_after = std::max(rep.change_after, change(v));
    if (!forced[static_cast<std::size_t>(v)]) rep.change_after_unforced = std::max(rep.change_after_unforced, change(v));
  }
  rep.strain_refusals = check.strainRefusals();
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return rep;
}

namespace {

// The largest change of a correction between consecutive frames.
double largestSequenceChange(const std::vector<MatrixX3d>& resolved, const std::vector<MatrixX3d>& inputs) {
  double largest = 0;
  for (std::size_t k = 1; k < resolved.size(); ++k)
    largest = std::max(largest, largestChange(resolved[k], inputs[k], resolved[k - 1] - inputs[k - 1]));
  return largest;
}

std::string sequenceSizeProblem(const std::vector<MatrixX3d>& resolved, const std::vector<MatrixX3d>& inputs,
                                const MatrixX3i& faces, const std::vector<double>& minClearance) {
  if (inputs.size() != resolved.size() || minClearance.size() != resolved.size())
    return "the resolved frames, their inputs and their clearances must be as many (" + std::to_string(resolved.size()) +
           ", " + std::to_string(inputs.size()) + ", " + std::to_string(minClearance.size()) + ")";
  for (std::size_t k = 0; k < resolved.size(); ++k)
    if (resolved[k].rows() != resolved[0].rows() || inputs[k].rows() != resolved[0].rows())
      return "frame " + std::to_string(k) + " does not have the first frame's " + std::to_string(resolved[0].rows()) +
             " vertices";
  if (faces.size() && (faces.minCoeff() < 0 || (!resolved.empty() && faces.maxCoeff() >= resolved[0].rows())))
    return "a face's corner is not a vertex of the frames";
  return "";
}

}  // namespace

BackwardCoherenceReport limitCorrectionChangeBackward(std::vector<MatrixX3d>& resolved,
                                                      const std::vector<MatrixX3d>& inputs, const MatrixX3i& faces,
                                                      const std::function<const Body&(int)>& bodyAt,
                                                      const std::vector<double>& minClearance,
                                                      const CoherenceParams& params) {
  const auto t0 = std::chrono::steady_clock::now();
  BackwardCoherenceReport rep;
  rep.message = sequenceSizeProblem(resolved, inputs, faces, minClearance);
  if (!rep.message.empty()) return rep;
  rep.change_before = rep.change_after = largestSequenceChange(resolved, inputs);
  const double limit = params.max_change;
  if (!(limit > 0) || rep.change_before <= limit * (1 + 1e-9)) return rep;
  for (int k = static_cast<int>(resolved.size()) - 2; k >= 0; --k) {
    const std::size_t i = static_cast<std::size_t>(k);
    const MatrixX3d next = resolved[i + 1] - inputs[i + 1];
    if (largestChange(resolved[i], inputs[i], next) <= limit * (1 + 1e-9)) continue;
    TriMesh garment{resolved[i], faces};
    CoherenceParams cp = params;
    cp.min_clearance = minClearance[i];
    cp.rings = params.backward_rings;
    const CoherenceReport c = limitCorrectionChange(bodyAt(k), garment, inputs[i], next, cp);
    resolved[i] = std::move(garment.V);
    rep.frames.push_back(k);
    rep.reports.push_back(c);
    rep.candidates += c.candidates;
    rep.limited += c.limited;
    rep.partly += c.partly;
    rep.held += c.held;
  }
  rep.change_after = largestSequenceChange(resolved, inputs);
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return rep;
}

}  // namespace virtual_tryon

