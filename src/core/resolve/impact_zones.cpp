#include "virtual_tryon/core/resolve/impact_zones.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>
#include <utility>

namespace virtual_tryon {

std::vector<std::vector<int>> groupImpactZones(const std::vector<Stencil>& stencils,
                                               int numVertices) {
  (void)numVertices;
  // Union-find over the stencils' own vertices only (sorted and numbered locally), so the cost
  // follows the stencils, not the garment.
  std::vector<int> verts;
  for (const Stencil& s : stencils)
    for (int k = 0; k < s.count; ++k) verts.push_back(s.vertex[k]);
  std::sort(verts.begin(), verts.end());
  verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
  auto local = [&](int v) {
    return static_cast<int>(std::lower_bound(verts.begin(), verts.end(), v) - verts.begin());
  };
  std::vector<int> parent(verts.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::vector<int> first(stencils.size());
  for (std::size_t i = 0; i < stencils.size(); ++i) {
    const Stencil& s = stencils[i];
    first[i] = local(s.vertex[0]);
    for (int k = 1; k < s.count; ++k) {
      const int a = find(first[i]), b = find(local(s.vertex[k]));
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  std::unordered_map<int, std::size_t> zoneOf;
  std::vector<std::vector<int>> zones;
  for (std::size_t i = 0; i < stencils.size(); ++i) {
    const int r = find(first[i]);
    auto it = zoneOf.emplace(r, zones.size());
    if (it.second) zones.emplace_back();
    zones[it.first->second].push_back(static_cast<int>(i));
  }
  return zones;
}

namespace {

constexpr int kDirectMaxStencils = 64;
constexpr int kMaxSweeps = 500;
constexpr int kMaxActiveSetRounds = 30;

// Gradient dot product of two stencils: sum over shared vertices of w_i w_j (n_i . n_j).
double gradientDot(const Stencil& a, const Stencil& b) {
  double w = 0;
  for (int i = 0; i < a.count; ++i)
    for (int j = 0; j < b.count; ++j)
      if (a.vertex[i] == b.vertex[j]) w += a.weight[i] * b.weight[j];
  return w == 0 ? 0.0 : w * a.normal.dot(b.normal);
}

}  // namespace

namespace {

// One zone's system, A lambda = b with A = Dx^T Dx and b = d - D, and its solve in stages: the
// exact active-set solve (small zones), Hildreth's sweeps (large zones, or when the exact answer
// is infeasible or too large), and the final displacement and feasibility check.
class ZoneSystem {
 public:
  ZoneSystem(const std::vector<Stencil>& stencils, const std::vector<int>& zone, double d)
      : stencils_(stencils),
        zone_(zone),
        d_(d),
        k_(static_cast<int>(zone.size())),
        loc_(static_cast<std::size_t>(k_)),
        A_(k_, k_),
        b_(k_),
        tol_(1e-9 + 1e-6 * std::max(d, 0.0)),
        lambda_(Eigen::VectorXd::Zero(k_)) {
    numberVertices();
    assemble();
  }

  ZoneSolution solve();

 private:
  void numberVertices();
  void assemble();
  double displacementCap() const;
  bool activeSet();
  bool solveActive(const std::vector<char>& active);
  void hildreth();
  void finish();

  const std::vector<Stencil>& stencils_;
  const std::vector<int>& zone_;
  const double d_;
  const int k_;
  ZoneSolution sol_;
  std::vector<std::array<int, 3>> loc_;  // loc_[i][j]: local number of stencil i's j-th vertex
  Eigen::SparseMatrix<double> A_;
  Eigen::VectorXd diag_;
  double eps_ = 0;  // the Tikhonov term
  Eigen::VectorXd b_;
  const double tol_;
  Eigen::VectorXd lambda_;
  double largest_ = 0;  // the largest vertex displacement of the last finish()
};

ZoneSolution ZoneSystem::solve() {
  // The largest displacement a single stencil of the zone asks for on its own; an answer far
  // beyond it comes from contradicting or nearly parallel stencils.
  const double cap = displacementCap();

  const bool direct = k_ <= kDirectMaxStencils;
  bool solved = direct && activeSet();
  if (solved) {
    finish();
    solved = sol_.feasible && largest_ <= cap;  // else: contradicting stencils, use the bounded method
  }
  if (!solved) {
    hildreth();
    finish();
  }
  if (largest_ > cap) {
    const double scale = cap / largest_;
    for (auto& v : sol_.displacement) v *= scale;
    lambda_ *= scale;
    sol_.feasible = false;
  }
  sol_.lambda.assign(lambda_.data(), lambda_.data() + k_);
  return std::move(sol_);
}

// Local vertex numbering; loc_[i][j] is stencil i's j-th vertex.
void ZoneSystem::numberVertices() {
  std::unordered_map<int, int> local;
  for (int i = 0; i < k_; ++i) {
    const Stencil& s = stencils_[zone_[i]];
    for (int j = 0; j < s.count; ++j) {
      auto it = local.emplace(s.vertex[j], static_cast<int>(sol_.vertices.size()));
      if (it.second) sol_.vertices.push_back(s.vertex[j]);
      loc_[i][j] = it.first->second;
    }
  }
}

// A = Dx^T Dx, assembled only where stencils share a vertex; its diagonal, eps and b.
void ZoneSystem::assemble() {
  std::vector<std::vector<int>> byVertex(sol_.vertices.size());
  for (int i = 0; i < k_; ++i)
    for (int j = 0; j < stencils_[zone_[i]].count; ++j) byVertex[loc_[i][j]].push_back(i);
  std::vector<Eigen::Triplet<double>> trip;
  for (const auto& list : byVertex)
    for (int a : list)
      for (int b : list) trip.emplace_back(a, b, 0.0);  // structure; values below
  A_.setFromTriplets(trip.begin(), trip.end(), [](double x, double) { return x; });
  double maxDiag = 0;
  for (int c = 0; c < A_.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A_, c); it; ++it) {
      it.valueRef() = gradientDot(stencils_[zone_[it.row()]], stencils_[zone_[it.col()]]);
      if (it.row() == it.col()) maxDiag = std::max(maxDiag, it.value());
    }
  diag_ = A_.diagonal();
  eps_ = 1e-10 * std::max(maxDiag, 1e-300);
  for (int i = 0; i < k_; ++i) b_[i] = d_ - stencils_[zone_[i]].D;
}

double ZoneSystem::displacementCap() const {
  double cap = 0;
  for (int i = 0; i < k_; ++i)
    if (diag_[i] > 0) cap = std::max(cap, b_[i] / diag_[i]);
  return 4.0 * cap + std::max(d_, 0.0);
}

// Exact active-set solve of the KKT system (small zones).
bool ZoneSystem::activeSet() {
  std::vector<char> active(static_cast<std::size_t>(k_), 1);
  for (int round = 0; round < kMaxActiveSetRounds; ++round) {
    sol_.active_set_rounds = round + 1;
    if (!solveActive(active)) return false;
    // Drop every stencil whose multiplier went negative (it would pull its vertices inward)...
    bool dropped = false;
    for (int i = 0; i < k_; ++i)
      if (active[i] && lambda_[i] < -1e-15 * (1.0 + std::abs(b_[i]))) {
        active[i] = 0;
        dropped = true;
      }
    if (dropped) continue;
    // ...and re-add every inactive one the others leave violated.
    const Eigen::VectorXd g = A_ * lambda_;  // Dx^T dx
    bool added = false;
    for (int i = 0; i < k_; ++i)
      if (!active[i] && b_[i] - g[i] > tol_) {
        active[i] = 1;
        added = true;
      }
    if (!added) return true;
  }
  return false;
}

// lambda with the stencils in `active` met as equalities and the others at 0: A restricted to the
// active set plus eps I, factorized; false when the factorization fails.
bool ZoneSystem::solveActive(const std::vector<char>& active) {
  std::vector<int> idx, pos(static_cast<std::size_t>(k_), -1);
  for (int i = 0; i < k_; ++i)
    if (active[i]) {
      pos[i] = static_cast<int>(idx.size());
      idx.push_back(i);
    }
  lambda_.setZero();
  if (idx.empty()) return true;
  const int m = static_cast<int>(idx.size());
  std::vector<Eigen::Triplet<double>> t;
  for (int c = 0; c < A_.outerSize(); ++c) {
    if (pos[c] < 0) continue;
    for (Eigen::SparseMatrix<double>::InnerIterator it(A_, c); it; ++it)
      if (pos[it.row()] >= 0) t.emplace_back(pos[it.row()], pos[c], it.value());
  }
  for (int i = 0; i < m; ++i) t.emplace_back(i, i, eps_);
  Eigen::SparseMatrix<double> As(m, m);
  As.setFromTriplets(t.begin(), t.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(As);
  if (ldlt.info() != Eigen::Success) return false;
  Eigen::VectorXd bs(m);
  for (int i = 0; i < m; ++i) bs[i] = b_[idx[i]];
  Eigen::VectorXd ls = ldlt.solve(bs);
  // Iterative refinement against the unregularized matrix removes the Tikhonov bias
  // wherever the system is not singular.
  for (int r = 0; r < 2; ++r) ls += ldlt.solve(Eigen::VectorXd(bs - As * ls + eps_ * ls));
  const Eigen::VectorXd piv = ldlt.vectorD().cwiseAbs();
  sol_.condition_estimate = piv.maxCoeff() / std::max(piv.minCoeff(), 1e-300);
  for (int i = 0; i < m; ++i) lambda_[idx[i]] = ls[i];
  return true;
}

// Hildreth's method: projected Gauss-Seidel on the dual, carried out in displacement space. Each
// step projects dx onto one stencil's half-space without letting its lambda go negative, and
// moves by at most the violation it removes, so dx stays bounded even when constraints
// contradict. Cheap per step; an approximate answer is enough, the resolver detects again.
void ZoneSystem::hildreth() {
  lambda_.setZero();
  std::vector<Eigen::Vector3d> dx(sol_.vertices.size(), Eigen::Vector3d::Zero());
  const double stopTol = 1e-4 * std::max(d_, 1e-12);
  for (int sweep = 0; sweep < kMaxSweeps; ++sweep) {
    double worst = 0;
    for (int i = 0; i < k_; ++i) {
      const Stencil& s = stencils_[zone_[i]];
      if (!(diag_[i] > 0)) continue;
      double gdx = 0;
      for (int j = 0; j < s.count; ++j) gdx += s.weight[j] * s.normal.dot(dx[loc_[i][j]]);
      const double r = b_[i] - gdx;  // > 0: violated
      worst = std::max(worst, r);
      const double step = std::max(-lambda_[i], r / diag_[i]);
      if (step == 0) continue;
      lambda_[i] += step;
      for (int j = 0; j < s.count; ++j) dx[loc_[i][j]] += step * s.weight[j] * s.normal;
    }
    sol_.sweeps = sweep + 1;
    if (worst <= stopTol) break;
  }
}

// dx = Dx lambda, the violations left, and feasibility.
void ZoneSystem::finish() {
  for (int i = 0; i < k_; ++i) lambda_[i] = std::max(lambda_[i], 0.0);
  sol_.displacement.assign(sol_.vertices.size(), Eigen::Vector3d::Zero());
  for (int i = 0; i < k_; ++i) {
    const Stencil& s = stencils_[zone_[i]];
    for (int j = 0; j < s.count; ++j) sol_.displacement[loc_[i][j]] += lambda_[i] * s.weight[j] * s.normal;
  }
  const Eigen::VectorXd g = A_ * lambda_;
  sol_.max_violation = 0;
  for (int i = 0; i < k_; ++i) sol_.max_violation = std::max(sol_.max_violation, b_[i] - g[i]);
  bool finite = lambda_.allFinite();
  largest_ = 0;
  for (const auto& v : sol_.displacement) {
    finite = finite && v.allFinite();
    largest_ = std::max(largest_, v.norm());
  }
  if (!finite) {
    lambda_.setZero();
    for (auto& v : sol_.displacement) v.setZero();
    sol_.max_violation = b_.maxCoeff();
    largest_ = 0;
  }
  sol_.feasible = finite && sol_.max_violation <= std::max(tol_, 1e-3 * std::max(d_, 0.0));
}

}  // namespace

ZoneSolution solveImpactZone(const std::vector<Stencil>& stencils, const std::vector<int>& zone,
                             double d) {
  return ZoneSystem(stencils, zone, d).solve();
}

ZoneSolution projectStencilsIndependently(const std::vector<Stencil>& stencils, double d) {
  ZoneSolution sol;
  std::unordered_map<int, int> local;
  std::vector<Eigen::Vector3d> sum;
  std::vector<int> count;
  sol.lambda.assign(stencils.size(), 0.0);
  for (std::size_t i = 0; i < stencils.size(); ++i) {
    const Stencil& s = stencils[i];
    double g2 = 0;
    for (int j = 0; j < s.count; ++j) g2 += s.weight[j] * s.weight[j];
    g2 *= s.normal.squaredNorm();
    const double lambda = g2 > 0 ? std::max(0.0, (d - s.D) / g2) : 0.0;
    sol.lambda[i] = lambda;
    for (int j = 0; j < s.count; ++j) {
      auto it = local.emplace(s.vertex[j], static_cast<int>(sol.vertices.size()));
      if (it.second) {
        sol.vertices.push_back(s.vertex[j]);
        sum.emplace_back(Eigen::Vector3d::Zero());
        count.push_back(0);
      }
      if (lambda * s.weight[j] == 0) continue;
      sum[it.first->second] += lambda * s.weight[j] * s.normal;
      ++count[it.first->second];
    }
  }
  sol.displacement.resize(sol.vertices.size());
  for (std::size_t v = 0; v < sol.vertices.size(); ++v)
    sol.displacement[v] = count[v] ? Eigen::Vector3d(sum[v] / count[v]) : Eigen::Vector3d::Zero();
  // How far the averaged move leaves each constraint from d.
  for (const Stencil& s : stencils) {
    double g = 0;
    for (int j = 0; j < s.count; ++j) g += s.weight[j] * s.normal.dot(sol.displacement[local[s.vertex[j]]]);
    sol.max_violation = std::max(sol.max_violation, d - s.D - g);
  }
  const double tol = 1e-9 + 1e-6 * std::max(d, 0.0);
  sol.feasible = sol.max_violation <= std::max(tol, 1e-3 * std::max(d, 0.0));
  return sol;
}

ZoneConditioning zoneConditioning(const std::vector<Stencil>& stencils, const std::vector<int>& zone,
                                  int maxStencils) {
  ZoneConditioning c;
  const int k = static_cast<int>(zone.size());
  c.stencils = k;
  if (k == 0 || k > maxStencils) return c;
  Eigen::MatrixXd A(k, k);
  for (int i = 0; i < k; ++i)
    for (int j = 0; j <= i; ++j) A(i, j) = A(j, i) = gradientDot(stencils[zone[i]], stencils[zone[j]]);
  const double maxDiag = A.diagonal().maxCoeff();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(A, Eigen::EigenvaluesOnly);
  if (es.info() != Eigen::Success) return c;
  c.computed = true;
  c.lambda_min = std::max(es.eigenvalues().minCoeff(), 0.0);
  c.lambda_max = es.eigenvalues().maxCoeff();
  c.condition = c.lambda_min > 1e-15 * c.lambda_max ? c.lambda_max / c.lambda_min
                                                   : std::numeric_limits<double>::infinity();
  const double eps = 1e-10 * std::max(maxDiag, 1e-300);
  c.regularized_condition = (c.lambda_max + eps) / (c.lambda_min + eps);
  return c;
}

}  // namespace virtual_tryon
