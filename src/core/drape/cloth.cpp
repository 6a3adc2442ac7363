#include "virtual_tryon/core/drape/cloth.h"

#include "virtual_tryon/core/drape/stiffness_spectrum.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <set>

namespace virtual_tryon {

namespace {
constexpr long kCheckpointEvery = 32;
}  // namespace

double stableTimeStep(double mass, double kMax) {
  if (!(mass > 0) || !(kMax > 0)) return 0.0;
  return 0.4 * M_PI * std::sqrt(mass / kMax);
}

namespace {
double stiffnessOf(const ClothParams& p, SpringType t) {
  switch (t) {
    case SpringType::Structural: return p.k_structural;
    case SpringType::Shear: return p.k_shear;
    case SpringType::Flexion: return p.k_flexion;
  }
  return p.k_structural;
}
}  // namespace

ClothState::ClothState(const ClothMesh& mesh, const ClothParams& params)
    : params_(params), x_(mesh.X), springs_(mesh.springs), seams_(mesh.seam_pairs), quads_(mesh.quads),
      F_(mesh.F) {
  mass_ = params.density * mesh.spacing * mesh.spacing;
  const Eigen::Index n = x_.rows();
  v_ = MatrixX3d::Zero(n, 3);
  f_ = MatrixX3d::Zero(n, 3);
  m_.assign(static_cast<std::size_t>(n), mass_);
  packSprings();
  int nSeams = static_cast<int>(mesh.seam_stage.size());
  for (const auto& s : seams_) nSeams = std::max(nSeams, s.seam + 1);
  seam_welded_.assign(static_cast<std::size_t>(nSeams), 0);
  seam_stage_ = mesh.seam_stage;
  seam_stage_.resize(static_cast<std::size_t>(nSeams), 0);
  countOpenSeams();
}

double ClothState::maxStiffness(bool withSeams) const {
  double k = std::max({params_.k_structural, params_.k_shear, params_.k_flexion});
  if (withSeams && !seams_.empty()) k = std::max(k, params_.k_seam);
  return k;
}

double ClothState::paperTimeStep() const {
  return virtual_tryon::stableTimeStep(mass_, maxStiffness(true));
}

double ClothState::stableTimeStep() const {
  // K per node: the sum of the stiffnesses of the springs (and open seams) that meet there.
  std::vector<double> ksum(m_.size(), 0.0);
  for (std::size_t s = 0; s < springs_.size(); ++s) {
    ksum[springs_[s].a] += packed_.k[s];
    ksum[springs_[s].b] += packed_.k[s];
  }
  for (const SeamPair& sp : seams_) {
    ksum[sp.a] += params_.k_seam;
    ksum[sp.b] += params_.k_seam;
  }
  double dt = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < m_.size(); ++i)
    if (ksum[i] > 0) dt = std::min(dt, virtual_tryon::stableTimeStep(m_[i], ksum[i]));
  return std::isfinite(dt) ? dt : 0.0;
}

double ClothState::spectralTimeStep() const {
  return virtual_tryon::spectralTimeStep(largestStiffnessEigenvalue(x_, springs_, packed_.k, m_).lambda_max);
}

void ClothState::packSprings() {
  const std::size_t n = springs_.size();
  packed_.a.resize(n);
  packed_.b.resize(n);
  packed_.rest.resize(n);
  packed_.k.resize(n);
  for (std::size_t s = 0; s < n; ++s) {
    packed_.a[s] = springs_[s].a;
    packed_.b[s] = springs_[s].b;
    packed_.rest[s] = springs_[s].rest;
    packed_.k[s] = stiffnessOf(params_, springs_[s].type);
  }
}

void ClothState::computeForces(bool sewing) {
  // Raw loops over the row-major n x 3 buffers: this is the hot path of every iteration.
  // While sewing, gravity is off (unless gravity_while_sewing) and the damping is the larger of
  // the two rates.
  const Eigen::Index n = x_.rows();
  if (x4_.rows() != static_cast<std::size_t>(n)) {
    x4_.resize(static_cast<std::size_t>(n));
    f4_.resize(static_cast<std::size_t>(n));
  }
  const double* x = x_.data();
  const double* v = v_.data();
  double* x4 = x4_.data();
  double* f4 = f4_.data();
  const bool gravityOn = !sewing || params_.gravity_while_sewing;
  const double gx = gravityOn ? params_.gravity.x() : 0.0;
  const double gy = gravityOn ? params_.gravity.y() : 0.0;
  const double gz = gravityOn ? params_.gravity.z() : 0.0;
  const double c = sewing ? std::max(params_.damping_rate, params_.sewing_damping_rate) : params_.damping_rate;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double m = m_[i];
    x4[4 * i + 0] = x[3 * i + 0];
    x4[4 * i + 1] = x[3 * i + 1];
    x4[4 * i + 2] = x[3 * i + 2];
    f4[4 * i + 0] = m * (gx - c * v[3 * i + 0]);
    f4[4 * i + 1] = m * (gy - c * v[3 * i + 1]);
    f4[4 * i + 2] = m * (gz - c * v[3 * i + 2]);
  }
  // The velocity fix needs the over-stretched springs of these positions: the kernel notes them.
  over_index_.clear();
  addSpringForces(packed_, x4_, f4_, 1.0 + params_.stretch_threshold, params_.vectorized, over_index_);
  over_.clear();
  for (int s : over_index_) addStretched(s);
  over_valid_ = true;
}

void ClothState::addStretched(int spring) {
  const Spring& sp = springs_[static_cast<std::size_t>(spring)];
  const Eigen::RowVector3d d = x_.row(sp.b) - x_.row(sp.a);
  const double len = d.norm();
  over_.push_back({sp.a, sp.b, {d.x() / len, d.y() / len, d.z() / len},
                   std::max(0.0, len - (1.0 + params_.stretch_threshold) * sp.rest)});
}

void ClothState::fixVelocities(double restore) {
  fixed_springs_ = 0;
  if (params_.velocity_fix_passes <= 0) return;
  // Over-stretched springs of the current positions (computeForces notes them).
  if (!over_valid_) computeForces(false);
  double* v = v_.data();
  if (restore > 0)
    for (const Stretched& o : over_) {  // the contraction, half at each end
      const double c = 0.5 * restore * o.excess;
      for (int k = 0; k < 3; ++k) {
        v[3 * o.a + k] += c * o.u[k];
        v[3 * o.b + k] -= c * o.u[k];
      }
    }
  auto along = [v](int node, const double* u) { return v[3 * node] * u[0] + v[3 * node + 1] * u[1] + v[3 * node + 2] * u[2]; };
  for (int pass = 0; pass < params_.velocity_fix_passes; ++pass) {
    std::size_t acted = 0;
    for (const Stretched& o : over_) {
      const double va = along(o.a, o.u), vb = along(o.b, o.u);
      bool changed = false;
      if (va < 0) {  // a moves away from b
        double* w = v + 3 * o.a;
        w[0] -= va * o.u[0];
        w[1] -= va * o.u[1];
        w[2] -= va * o.u[2];
        changed = true;
      }
      if (vb > 0) {  // b moves away from a
        double* w = v + 3 * o.b;
        w[0] -= vb * o.u[0];
        w[1] -= vb * o.u[1];
        w[2] -= vb * o.u[2];
        changed = true;
      }
      acted += changed;
    }
    if (pass == 0) fixed_springs_ = acted;
    if (acted == 0) return;
  }
  // The passes above are Gauss-Seidel: fixing one spring can leave a neighbour with a tiny
  // stretching rate again. A node still stretching one of its over-long springs stops (a zero
  // velocity stretches nothing and touches no other node), so afterwards no over-stretched spring
  // gets longer, exactly.
  for (const Stretched& o : over_) {
    if (along(o.a, o.u) < 0) std::fill(v + 3 * o.a, v + 3 * o.a + 3, 0.0);
    if (along(o.b, o.u) > 0) std::fill(v + 3 * o.b, v + 3 * o.b + 3, 0.0);
  }
}

namespace {

// The seam pull while sewing, added to f4: only the lowest stage with an open seam pulls
// (PatternSeam::stage).
void addSeamPull(const std::vector<SeamPair>& seams, const std::vector<int>& seamStage,
                 const MatrixX3d& x, const ClothParams& params, PaddedRows& f4) {
  int stage = std::numeric_limits<int>::max();
  for (const SeamPair& s : seams) stage = std::min(stage, seamStage[s.seam]);
  for (const SeamPair& s : seams) {
    if (seamStage[s.seam] != stage) continue;
    const Eigen::RowVector3d d = x.row(s.b) - x.row(s.a);
    const double len = d.norm();
    // A constant pull of k_seam * seam_max_stretch: strong enough to finish closing a seam
    // against the cloth's resistance, never strong enough to fling a panel across the body.
    const double scale = len > 0 ? params.seam_max_stretch / len : 0.0;
    const Eigen::RowVector3d f = (params.k_seam * scale) * d;
    double* fa = f4.row(static_cast<std::size_t>(s.a));
    double* fb = f4.row(static_cast<std::size_t>(s.b));
    for (int k = 0; k < 3; ++k) {
      fa[k] += f[k];
      fb[k] -= f[k];
    }
  }
}

// Euler's velocity update of the first n nodes, v += dt f / m.
void accelerate(Eigen::Index n, MatrixX3d& vel, const PaddedRows& f4, const std::vector<double>& m,
                double dt) {
  double* v = vel.data();
  const double* f = f4.data();
  for (Eigen::Index i = 0; i < n; ++i) {
    const double s = dt / m[i];
    v[3 * i + 0] += s * f[4 * i + 0];
    v[3 * i + 1] += s * f[4 * i + 1];
    v[3 * i + 2] += s * f[4 * i + 2];
  }
}

// Position update and the blow-up check in one pass: false when a node is faster than
// runawaySpeed or a value is not finite.
bool moveNodes(MatrixX3d& pos, const MatrixX3d& vel, double dt, double runawaySpeed) {
  const Eigen::Index n = pos.rows();
  const double limit2 = runawaySpeed * runawaySpeed;
  bool ok = true;
  const double* v = vel.data();
  double* x = pos.data();
  for (Eigen::Index i = 0; i < 3 * n; i += 3) {
    x[i] += dt * v[i];
    x[i + 1] += dt * v[i + 1];
    x[i + 2] += dt * v[i + 2];
    const double s2 = v[i] * v[i] + v[i + 1] * v[i + 1] + v[i + 2] * v[i + 2];
    // NaN compares false: a non-finite velocity fails here, a non-finite position below.
    if (!(s2 <= limit2) || !std::isfinite(x[i] + x[i + 1] + x[i + 2])) ok = false;
  }
  return ok;
}

}  // namespace

bool ClothState::step(double dt, bool sewing) {
  // A finite state to fall back on, refreshed every kCheckpointEvery steps (copying the state
  // every step would cost a tenth of the step).
  if (steps_ % kCheckpointEvery == 0 || x_prev_.rows() != x_.rows()) {
    x_prev_ = x_;
    v_prev_ = v_;
  }
  ++steps_;
  computeForces(sewing);
  if (sewing) addSeamPull(seams_, seam_stage_, x_, params_, f4_);
  accelerate(x_.rows(), v_, f4_, m_, dt);
  fixVelocities(sewing || !(dt > 0) ? 0.0 : params_.strain_restore / dt);
  if (hook_) {
    hook_(x_, v_);
    // The collision response changes velocities after the fix and can stretch the cloth again:
    // a garment hanging on a cone (trousers on the hips) slid down it, the response pushing its
    // nodes out along the body's normals, until its springs were 30-90% over their rest length.
    // So once the seams are closed (gravity on) the fix has the last word and no over-long
    // spring grows. While sewing (no gravity) the response may stretch the cloth: the seam pull
    // works against the body there, and the springs relax once the seams are welded.
    if (!sewing) fixVelocities();
  }
  over_valid_ = false;  // the positions move
  const bool ok = moveNodes(x_, v_, dt, params_.runaway_speed);
  if (!ok) {
    x_ = x_prev_;
    v_ = v_prev_;
    steps_ = 0;
  }
  return ok;
}

double ClothState::maxSeamGap() const {
  double g = 0;
  for (const SeamPair& s : seams_) g = std::max(g, (x_.row(s.a) - x_.row(s.b)).norm());
  return g;
}

double ClothState::meanSeamGap() const {
  if (seams_.empty()) return 0;
  double g = 0;
  for (const SeamPair& s : seams_) g += (x_.row(s.a) - x_.row(s.b)).norm();
  return g / static_cast<double>(seams_.size());
}

std::vector<int> ClothState::openSeamIndices() const {
  std::set<int> open;
  for (const SeamPair& s : seams_) open.insert(s.seam);
  return std::vector<int>(open.begin(), open.end());
}

void ClothState::countOpenSeams() {
  std::set<int> open;
  for (const SeamPair& s : seams_) open.insert(s.seam);
  open_seams_ = static_cast<int>(open.size());
}

int ClothState::weldClosedSeams(double tolerance) {
  std::vector<double> worst(seam_welded_.size(), 0.0);
  for (const SeamPair& s : seams_)
    worst[s.seam] = std::max(worst[s.seam], (x_.row(s.a) - x_.row(s.b)).norm());
  std::vector<char> weld(seam_welded_.size(), 0);
  int count = 0;
  for (const SeamPair& s : seams_)
    if (!weld[s.seam] && worst[s.seam] < tolerance) {
      weld[s.seam] = 1;
      ++count;
    }
  if (count == 0) return 0;
  const int n = static_cast<int>(x_.rows());
  std::vector<int> parent(static_cast<std::size_t>(n));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  std::vector<SeamPair> stillOpen;
  for (const SeamPair& s : seams_) {
    if (!weld[s.seam]) {
      stillOpen.push_back(s);
      continue;
    }
    const int a = find(s.a), b = find(s.b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
  for (std::size_t i = 0; i < weld.size(); ++i)
    if (weld[i]) seam_welded_[i] = 1;
  seams_ = stillOpen;
  std::vector<int> rep(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) rep[i] = find(i);
  rebuildAfterWeld(rep);
  relaxStrainedSprings(params_.weld_relax_passes);
  countOpenSeams();
  return count;
}

int ClothState::relaxStrainedSprings(int passes, double compressed) {
  const double longest = 1.0 + params_.stretch_threshold;
  const double shortest = compressed > 0 ? 1.0 - compressed : 0.0;
  int done = 0;
  for (int pass = 0; pass < passes; ++pass) {
    bool moved = false;
    for (const Spring& sp : springs_) {
      if (sp.type != SpringType::Structural) continue;
      const Eigen::RowVector3d d = x_.row(sp.b) - x_.row(sp.a);
      const double len = d.norm();
      if (!(len > 0)) continue;
      double bound = len;  // the length the spring is brought to
      if (len > longest * sp.rest) bound = longest * sp.rest;
      else if (len < shortest * sp.rest) bound = shortest * sp.rest;
      else continue;
      const double ia = 1.0 / m_[sp.a], ib = 1.0 / m_[sp.b];
      const Eigen::RowVector3d corr = ((len - bound) / (len * (ia + ib))) * d;
      x_.row(sp.a) += ia * corr;
      x_.row(sp.b) -= ib * corr;
      moved = true;
    }
    if (!moved) break;
    ++done;
  }
  over_valid_ = false;
  return done;
}

void ClothState::rebuildAfterWeld(const std::vector<int>& rep) {
  const int n = static_cast<int>(rep.size());
  std::vector<int> id(static_cast<std::size_t>(n), -1);
  int m = 0;
  for (int i = 0; i < n; ++i)
    if (rep[i] == i) id[i] = m++;
  MatrixX3d x = MatrixX3d::Zero(m, 3), v = MatrixX3d::Zero(m, 3);
  std::vector<double> mass(static_cast<std::size_t>(m), 0.0);
  std::vector<int> count(static_cast<std::size_t>(m), 0);
  for (int i = 0; i < n; ++i) {
    const int j = id[rep[i]];
    x.row(j) += x_.row(i);
    v.row(j) += m_[i] * v_.row(i);  // momentum is kept
    mass[j] += m_[i];
    ++count[j];
  }
  for (int j = 0; j < m; ++j) {
    x.row(j) /= count[j];
    v.row(j) /= mass[j];
  }
  auto remap = [&](int i) { return id[rep[i]]; };
  std::vector<Spring> springs;
  std::set<std::pair<int, int>> seen;
  for (std::size_t s = 0; s < springs_.size(); ++s) {
    Spring sp = springs_[s];
    sp.a = remap(sp.a);
    sp.b = remap(sp.b);
    if (sp.a == sp.b || !seen.insert({std::min(sp.a, sp.b), std::max(sp.a, sp.b)}).second) continue;
    springs.push_back(sp);
  }
  for (SeamPair& s : seams_) {
    s.a = remap(s.a);
    s.b = remap(s.b);
  }
  seams_.erase(std::remove_if(seams_.begin(), seams_.end(), [](const SeamPair& s) { return s.a == s.b; }),
               seams_.end());
  for (auto& q : quads_)
    for (int& c : q) c = remap(c);
  MatrixX3i F(F_.rows(), 3);
  Eigen::Index nf = 0;
  for (Eigen::Index f = 0; f < F_.rows(); ++f) {
    const int a = remap(F_(f, 0)), b = remap(F_(f, 1)), c = remap(F_(f, 2));
    if (a == b || b == c || a == c) continue;
    F.row(nf++) << a, b, c;
  }
  F.conservativeResize(nf, 3);
  x_ = x;
  v_ = v;
  f_ = MatrixX3d::Zero(m, 3);
  m_ = mass;
  springs_ = springs;
  packSprings();
  over_valid_ = false;
  F_ = F;
}

const MatrixX3d& ClothState::evaluateForces() {
  computeForces(false);
  const double* f4 = f4_.data();
  double* f = f_.data();
  for (Eigen::Index i = 0; i < f_.rows(); ++i) {
    f[3 * i + 0] = f4[4 * i + 0];
    f[3 * i + 1] = f4[4 * i + 1];
    f[3 * i + 2] = f4[4 * i + 2];
  }
  return f_;
}

double ClothState::potentialEnergy() const {
  double e = 0;
  for (std::size_t s = 0; s < springs_.size(); ++s) {
    const double l = (x_.row(springs_[s].b) - x_.row(springs_[s].a)).norm();
    e += 0.5 * packed_.k[s] * (l - springs_[s].rest) * (l - springs_[s].rest);
  }
  for (Eigen::Index i = 0; i < x_.rows(); ++i) e -= m_[i] * params_.gravity.dot(x_.row(i).transpose());
  return e;
}

double ClothState::kineticEnergy() const {
  double e = 0;
  for (Eigen::Index i = 0; i < v_.rows(); ++i) e += 0.5 * m_[i] * v_.row(i).squaredNorm();
  return e;
}

double ClothState::rmsSpeed() const {
  double m = 0;
  for (double mi : m_) m += mi;
  return m > 0 ? std::sqrt(2.0 * kineticEnergy() / m) : 0.0;
}

double ClothState::maxSpeed() const {
  return v_.rows() ? std::sqrt(v_.rowwise().squaredNorm().maxCoeff()) : 0.0;
}

namespace {

// |l / l0 - 1| of a structural spring of non-zero rest length with its nodes at x; false for others.
bool structuralStrain(const Spring& sp, const MatrixX3d& x, double& e) {
  if (sp.type != SpringType::Structural || !(sp.rest > 0)) return false;
  e = std::abs((x.row(sp.b) - x.row(sp.a)).norm() / sp.rest - 1.0);
  return true;
}

}  // namespace

void ClothState::strain(double& maxStrain, double& meanStrain) const {
  maxStrain = meanStrain = 0;
  std::size_t n = 0;
  for (const Spring& sp : springs_) {
    double e = 0;
    if (!structuralStrain(sp, x_, e)) continue;
    maxStrain = std::max(maxStrain, e);
    meanStrain += e;
    ++n;
  }
  if (n) meanStrain /= static_cast<double>(n);
}

std::vector<double> ClothState::nodeStrain(const MatrixX3d& x) const {
  std::vector<double> strain(static_cast<std::size_t>(x.rows()), 0.0);
  for (const Spring& sp : springs_) {
    double e = 0;
    if (sp.a >= x.rows() || sp.b >= x.rows() || !structuralStrain(sp, x, e)) continue;
    strain[static_cast<std::size_t>(sp.a)] = std::max(strain[static_cast<std::size_t>(sp.a)], e);
    strain[static_cast<std::size_t>(sp.b)] = std::max(strain[static_cast<std::size_t>(sp.b)], e);
  }
  return strain;
}

TriMesh ClothState::mesh() const {
  TriMesh m;
  m.V = x_;
  m.F = F_;
  return m;
}

}  // namespace virtual_tryon
