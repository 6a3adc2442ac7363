#include "virtual_tryon/core/resolve/temporal_coherence.h"

#include "virtual_tryon/core/geometry/point_queries.h"
#include "virtual_tryon/core/resolve/intersections.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

namespace virtual_tryon {
namespace {

// Faces round each vertex, as offsets into one list.
void vertexFaceLists(const MatrixX3i& F, Eigen::Index nv, std::vector<int>& start, std::vector<int>& faces) {
  start.assign(static_cast<std::size_t>(nv) + 1, 0);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) ++start[static_cast<std::size_t>(F(f, k)) + 1];
  for (std::size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
  faces.assign(static_cast<std::size_t>(start.back()), 0);
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) faces[static_cast<std::size_t>(fill[static_cast<std::size_t>(F(f, k))]++)] = static_cast<int>(f);
}

double largestChange(const TriMesh& garment, const MatrixX3d& input, const MatrixX3d& previous) {
  return garment.V.rows() ? ((garment.V - input) - previous).rowwise().norm().maxCoeff() : 0.0;
}

// Vertex v where it is now keeps the frame clean: its faces and edges cross nothing, it is not
// inside the body, and it is at least `clearance` from it.
class MoveCheck {
 public:
  MoveCheck(const Body& body, const TriMesh& garment) : body_(body), garment_(garment), topo_(garment) {
    vertexFaceLists(garment.F, garment.V.rows(), start_, faces_);
  }
  bool clean(int v, double clearance) {
    around_.assign(faces_.begin() + start_[static_cast<std::size_t>(v)], faces_.begin() + start_[static_cast<std::size_t>(v) + 1]);
    detectCrossings(body_, garment_, topo_, crossings_, &around_);
    if (crossings_.size() > 0) return false;
    const Eigen::Vector3d p = garment_.V.row(v).transpose();
    if (pointInsideBody(body_, p)) return false;
    return !(clearance > 0) || closestPointOnBody(body_, p).distance >= clearance;
  }
  double distance(int v) const { return closestPointOnBody(body_, garment_.V.row(v).transpose()).distance; }

 private:
  const Body& body_;
  const TriMesh& garment_;
  GarmentTopology topo_;
  std::vector<int> start_, faces_, around_;
  CrossingSet crossings_;
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
  rep.change_before = rep.change_after = rep.change_after_unforced = largestChange(garment, input, previousCorrection);
  const double limit = params.max_change;
  if (!(limit > 0) || rep.change_before <= limit) return rep;
  std::vector<int> over;
  for (Eigen::Index v = 0; v < n; ++v)
    if (((garment.V.row(v) - input.row(v)) - previousCorrection.row(v)).norm() > limit) over.push_back(static_cast<int>(v));
  rep.candidates = over.size();
  const MatrixX3d resolved = garment.V;
  MoveCheck check(body, garment);
  std::vector<double> floor(over.size());
  for (std::size_t i = 0; i < over.size(); ++i)
    floor[i] = params.min_clearance > 0 ? std::min(params.min_clearance, check.distance(over[i])) : 0.0;
  for (int pass = 0; pass < std::max(1, params.passes); ++pass) {
    bool moved = false;
    for (std::size_t i = 0; i < over.size(); ++i) {
      const int v = over[i];
      const Eigen::RowVector3d change = (garment.V.row(v) - input.row(v)) - previousCorrection.row(v);
      const double len = change.norm();
      if (len <= limit * (1 + 1e-9)) continue;
      const Eigen::RowVector3d from = garment.V.row(v);
      const Eigen::RowVector3d step = -change * (1.0 - limit / len);
      // The whole step, else the largest clean part of it found by bisection (the resolved
      // position, part 0, is clean).
      double lo = 0, hi = 1;
      garment.V.row(v) = from + step;
      if (check.clean(v, floor[i] * (1 - 1e-9))) lo = 1;
      for (int b = 0; b < std::max(0, params.bisections) && lo < 1; ++b) {
        const double mid = 0.5 * (lo + hi);
        garment.V.row(v) = from + mid * step;
        (check.clean(v, floor[i] * (1 - 1e-9)) ? lo : hi) = mid;
      }
      garment.V.row(v) = from + lo * step;
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
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return rep;
}

}  // namespace virtual_tryon
