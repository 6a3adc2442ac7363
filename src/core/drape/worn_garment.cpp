#include "virtual_tryon/core/drape/worn_garment.h"

#include "core/drape/collision_response.h"
#include "virtual_tryon/core/geometry/point_queries.h"
#include "virtual_tryon/core/resolve/intersections.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

namespace virtual_tryon {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// The largest of per-node strains (0 for none).
double largest(const std::vector<double>& strain) {
  double m = 0;
  for (double s : strain) m = std::max(m, s);
  return m;
}

std::string num(double v) {
  std::ostringstream o;
  o.precision(4);
  o << v;
  return o.str();
}

constexpr double kMaxSurfaceSpeed = WornGarment::kMaxSurfaceSpeed;

// The body between two frames' maps on one grid, at time s in [0, 1] of the interval (the blend of
// each pixel's depth and normal; see worn_garment.h), and the surface's velocity there: from B's
// velocity maps when it has them (the skin's own motion over the interval, tangential part
// included), else its speed along the normal from the change of depth. With the other views, a
// point deeper than the tolerance shell collides only when each of them sees it inside too (the
// body is inside every view's depth interval, so nothing truly inside is missed); the front view
// gives the normal, depth and velocity (a wall moving sideways, a leg swinging, seen from above is
// a depth that jumps).
class MovingMaps {
 public:
  MovingMaps(const FrameMaps& a, const FrameMaps& b, double seconds, bool interpolate,
             bool velocity)
      : a_(*a.front), b_(*b.front), inv_t_(1.0 / seconds), interpolate_(interpolate), velocity_(velocity) {
    for (std::size_t k = 0; k < FrameMaps::kOtherViews.size(); ++k)
      if (a.other[k] && b.other[k]) others_.push_back({FrameMaps::kOtherViews[k], a.other[k].get(), b.other[k].get()});
    spanFrontView();
  }
  void setTime(double s) { s_ = s; }

  bool collide(const Eigen::Vector3d& p, Eigen::Vector3d& normal, double& depth, Eigen::Vector3d& surface) const {
    std::size_t i;
    if (!b_.pixelIndex(p.x(), p.y(), i)) return false;
    const std::array<float, 2>& span = span_[i];
    if (!(p.z() >= span[0] && p.z() <= span[1])) return false;  // most of the cloth: one load
    if (!view(a_, b_, p, normal, depth, &surface)) return false;
    // Within the tolerance shell the front view is right (the shell is along z: at a steep wall a
    // point in it may lie far from the wall along y, and another view would let it through).
    if (depth <= b_.tol()) return true;
    Eigen::Vector3d nq;
    double dq;
    for (const Other& o : others_)
      if (!view(*o.a, *o.b, viewPoint(o.view, p), nq, dq, nullptr)) return false;  // outside, seen from there
    return true;
  }

 private:
  // One view: the maps a and b of the interval's ends on one grid, the point in the view's frame;
  // `surface` (may be null) the surface's velocity.
  bool view(const DepthMaps& a, const DepthMaps& b, const Eigen::Vector3d& p, Eigen::Vector3d& normal,
            double& depth, Eigen::Vector3d* surface) const {
    std::size_t i;
    if (!b.pixelIndex(p.x(), p.y(), i)) return false;
    const float fb = b.frontDepth()[i], bb = b.backDepth()[i];
    const float fa = a.frontDepth()[i], ba = a.backDepth()[i];
    if (!interpolate_ || std::isnan(fa)) {  // arriving
      bool front = true;
      if (!still(b, i, p.z(), normal, depth, front)) return false;
      if (surface) *surface = mapVelocity(b, i, front);
      return true;
    }
    if (std::isnan(fb)) return false;  // the body has left this pixel by the end of the interval
    const double s = s_;
    const double f = fa + s * (fb - fa), bk = ba + s * (bb - ba), z = p.z();
    if (!(z <= f && z >= bk)) return false;
    const bool front = f - z <= z - bk;
    const Eigen::Vector3f& na = front ? a.frontNormal()[i] : a.backNormal()[i];
    const Eigen::Vector3f& nb = front ? b.frontNormal()[i] : b.backNormal()[i];
    const Eigen::Vector3d n = ((1 - s) * na.cast<double>() + s * nb.cast<double>());
    const double len = n.norm();
    normal = len > 1e-9 ? Eigen::Vector3d(n / len) : nb.cast<double>();
    depth = front ? f - z : z - bk;
    if (!surface) return true;
    if (b.hasVelocity()) {
      *surface = mapVelocity(b, i, front);
    } else {
      // The surface z = depth(x, y, t) moves along its normal at n_z dz/dt.
      const double dz = front ? fb - fa : bb - ba;
      const double speed = velocity_ ? std::clamp(normal.z() * dz * inv_t_, -kMaxSurfaceSpeed, kMaxSurfaceSpeed) : 0.0;
      *surface = speed * normal;
    }
    return true;
  }

  // Pixel i's surface velocity in b's velocity maps (front or back), at most kMaxSurfaceSpeed; zero
  // without them or with body_velocity off.
  Eigen::Vector3d mapVelocity(const DepthMaps& b, std::size_t i, bool front) const {
    if (!velocity_ || !b.hasVelocity()) return Eigen::Vector3d::Zero();
    Eigen::Vector3d u = (front ? b.frontVelocity()[i] : b.backVelocity()[i]).cast<double>();
    const double speed = u.norm();
    if (speed > kMaxSurfaceSpeed) u *= kMaxSurfaceSpeed / speed;
    return u;
  }

  // Per pixel of the front view, the depths between which the body can be at any time of the
  // interval: from the lower of the two backs to the higher of the two fronts (B's alone where it
  // arrives or is not interpolated; empty where it has left), a little wider than the float
  // values so that the blend's rounding never falls outside. A point outside it collides at no time.
  void spanFrontView() {
    const std::vector<float>&fa = a_.frontDepth(), &ba = a_.backDepth(), &fb = b_.frontDepth(), &bb = b_.backDepth();
    const bool same = fa.size() == fb.size() && interpolate_;
    span_.resize(fb.size());
    constexpr float kPad = 1e-5f;
    for (std::size_t i = 0; i < fb.size(); ++i) {
      if (std::isnan(fb[i])) {
        span_[i] = {1.0f, -1.0f};
      } else if (!same || std::isnan(fa[i])) {
        span_[i] = {bb[i] - kPad, fb[i] + kPad};
      } else {
        span_[i] = {std::min(ba[i], bb[i]) - kPad, std::max(fa[i], fb[i]) + kPad};
      }
    }
  }

  static bool still(const DepthMaps& m, std::size_t i, double z, Eigen::Vector3d& normal, double& depth,
                    bool& front) {
    const double f = m.frontDepth()[i], b = m.backDepth()[i];
    if (!(z <= f && z >= b)) return false;
    front = f - z <= z - b;
    normal = (front ? m.frontNormal()[i] : m.backNormal()[i]).cast<double>();
    depth = front ? f - z : z - b;
    return true;
  }

  struct Other {
    MapView view;
    const DepthMaps* a;
    const DepthMaps* b;
  };
  const DepthMaps& a_;
  const DepthMaps& b_;
  std::vector<Other> others_;
  std::vector<std::array<float, 2>> span_;  // spanFrontView()
  double inv_t_, s_ = 1;
  bool interpolate_, velocity_;
};

bool sameGrid(const MapGrid& a, const MapGrid& b) {
  return a.width == b.width && a.height == b.height && a.pixel == b.pixel && a.x0 == b.x0 && a.y0 == b.y0;
}

}  // namespace

WornGarment::WornGarment(WornGarmentParams params) : params_(std::move(params)) {}
WornGarment::~WornGarment() = default;

DrapeResult WornGarment::dress(const Body& body, const Pattern& pattern, const DrapeProgressCallback& progress,
                               int progress_every, const std::function<void(const WornMapRenderer&)>& mapsReady) {
  cloth_.reset();
  garment_ = TriMesh();
  strain_.clear();
  maps_ = FrameMaps();
  renderer_ = WornMapRenderer();
  body_V_.resize(0, 3);
  clean_V_.resize(0, 3);
  clean_body_V_.resize(0, 3);
  frames_since_clean_ = 0;
  step_limit_ = cloth_step_ = 0;
  if (params_.drape.mode != CollisionMode::ImageSpace) {
    DrapeResult r;
    r.message = "a worn garment steps in image space: drape mode must be image space";
    return r;
  }
  if (!(params_.grid_margin >= 0 && params_.grid_margin <= 10) || !(params_.dt >= 0) || !std::isfinite(params_.dt) ||
      params_.max_steps_per_frame < 1 || !(params_.strain_restore >= 0 && params_.strain_restore <= 1) ||
      params_.relax_passes < 0 || params_.relax_passes > 1000 ||
      !(params_.relax_compression >= 0 && params_.relax_compression < 1) || params_.step_halvings < 0 ||
      params_.step_halvings > 8 || params_.carry_rings < 0 || params_.carry_rings > 1000 ||
      params_.carry_relax_passes < 0 || params_.carry_relax_passes > 10000 || params_.carry_smoothing < 0 ||
      params_.carry_smoothing > 1000 || params_.quick_sweeps < 0 || params_.quick_sweeps > 1000 ||
      params_.quick_rings < 0 || params_.quick_rings > 1000 || !(params_.quick_strain > 0 && params_.quick_strain <= 10) ||
      !(params_.dt_safety > 0 && params_.dt_safety <= 1)) {
    DrapeResult r;
    r.message = "worn garment parameters out of range (grid_margin 0 .. 10 m, dt >= 0 s, max_steps_per_frame >= 1, "
                "strain_restore 0 .. 1, relax_passes 0 .. 1000, relax_compression 0 .. <1, step_halvings 0 .. 8, carry_rings 0 .. 1000, "
                "carry_relax_passes 0 .. 10000, carry_smoothing 0 .. 1000, quick_sweeps and quick_rings 0 .. 1000, "
                "quick_strain > 0 .. 10, dt_safety > 0 .. 1)";
    return r;
  }
  // The first frame's maps on the grid every later frame shares, at the drape's pixel size (the
  // body's own maps, which the drape then uses too); the caller may start rendering the next
  // frames with it while the garment is draped.
  renderer_ = WornMapRenderer(mapParams(), body, body.depthMaps(params_.drape.collision)->pixelSize(), maps_);
  if (mapsReady) mapsReady(renderer_);
  DrapeResult rep = drape(body, pattern, params_.drape, garment_, cloth_, progress, progress_every);
  if (!rep.success) {
    maps_ = FrameMaps();
    renderer_ = WornMapRenderer();
    return rep;
  }
  strain_ = rep.vertex_strain;
  cloth_->setStrainRestore(params_.strain_restore);
  step_limit_ = cloth_->spectralTimeStep();
  const double drapeStep = params_.drape.dt > 0 ? params_.drape.dt : params_.drape.dt_safety * cloth_->stableTimeStep();
  const double collisionStep = params_.drape.collision.tol / kMaxSurfaceSpeed;
  cloth_step_ = params_.dt > 0 ? params_.dt : std::max(drapeStep, std::min(params_.dt_safety * step_limit_, collisionStep));
  if (params_.dt > 0 && step_limit_ > 0 && params_.dt > step_limit_) {
    // Above it every step amplifies the cloth's stiffest mode (on the walk's dress at 1.01x: nodes
    // at 8-25 m/s, and a frame whose correction took minutes).
    rep.success = rep.converged = false;
    rep.message = "the cloth's step " + num(params_.dt) + " s is above its stability limit " + num(step_limit_) +
                  " s (2 / sqrt of the largest eigenvalue of M^-1 K, the cloth as draped)";
    cloth_.reset();
    maps_ = FrameMaps();
    renderer_ = WornMapRenderer();
    step_limit_ = cloth_step_ = 0;
    return rep;
  }
  body_V_ = body.mesh().V;
  clean_V_ = garment_.V;
  clean_body_V_ = body_V_;
  // Each frame's resolve keeps the drape's final-resolve settings: edges past the polish strain
  // against the cloth as stepped, and every structural spring within its rest bound.
  frame_resolver_ = params_.drape.resolver;
  if (params_.drape.resolve_polish_strain > 0)
    frame_resolver_.relaxation.polish_strain = params_.drape.resolve_polish_strain;
  if (params_.drape.resolve_rest_strain > 0) {
    frame_resolver_.relaxation.rest_strain = params_.drape.resolve_rest_strain;
    for (const Spring& sp : cloth_->springs())
      if (sp.type == SpringType::Structural) frame_resolver_.relaxation.rest_lengths.push_back({sp.a, sp.b, sp.rest});
  }
  frame_resolver_.connectivity = garmentConnectivity(garment_);  // the cloth's faces stay: built once
  quick_resolver_ = frame_resolver_;
  quick_resolver_.relaxation.max_sweeps = params_.quick_sweeps;
  quick_resolver_.relaxation.rings = params_.quick_rings;
  return rep;
}

WornMapParams WornGarment::mapParams() const {
  WornMapParams m;
  m.collision = params_.drape.collision;
  m.grid_margin = params_.grid_margin;
  m.skin_velocity = params_.body_velocity && params_.skin_velocity;
  m.views = {params_.top_view, params_.side_view};
  return m;
}

bool WornGarment::stepFrame(const FrameMaps& from, const FrameMaps& to, double seconds, WornFrameReport& rep) {
  for (double dt = cloth_step_;; dt /= 2, ++rep.step_halvings) {
    if (stepCloth(from, to, seconds, dt, rep)) return true;
    if (rep.steps == 0 || rep.step_halvings >= params_.step_halvings) return false;  // refused, or no halving left
  }
}

bool WornGarment::stepCloth(const FrameMaps& from, const FrameMaps& to, double seconds, double dt,
                            WornFrameReport& rep) {
  ClothState& cloth = *cloth_;
  rep.steps = 0;
  const int n = std::max(1, static_cast<int>(std::ceil(seconds / dt - 1e-9)));
  if (n > params_.max_steps_per_frame) {
    rep.message = "the frame is " + num(seconds) + " s long: " + std::to_string(n) + " steps of at most " + num(dt) +
                  " s, above max_steps_per_frame " + std::to_string(params_.max_steps_per_frame);
    return false;
  }
  rep.steps = n;
  rep.dt = seconds / n;
  CollisionResponse<MovingMaps> response(MovingMaps(from, to, seconds, rep.interpolated, params_.body_velocity),
                                         params_.drape.collision, params_.drape.quad_midpoints, cloth, rep.dt,
                                         params_.drape.push_out);
  cloth.setVelocityHook([&response](const MatrixX3d& x, MatrixX3d& v) { response(x, v); });
  const MatrixX3d x0 = cloth.positions(), v0 = cloth.velocities();
  bool ok = true;
  for (int j = 0; j < n && ok; ++j) {
    response.collider().setTime(static_cast<double>(j + 1) / n);
    ok = cloth.step(rep.dt, false);
    rep.colliding_nodes = std::max(rep.colliding_nodes, response.collidingNodes());
  }
  cloth.setVelocityHook(nullptr);
  if (!ok) {
    cloth.positions() = x0;  // nothing moved
    cloth.velocities() = v0;
    rep.message = "the integration blew up (a non-finite value or a node faster than " +
                  num(cloth.params().runaway_speed) + " m/s) with dt " + num(rep.dt) + " s" +
                  (rep.step_halvings > 0 ? " (halved " + std::to_string(rep.step_halvings) + " times)" : "");
    return false;
  }
  rep.max_speed = cloth.maxSpeed();
  return true;
}

void WornGarment::resolveFrame(const Body& body, WornFrameReport& rep, bool quick) {
  ClothState& cloth = *cloth_;
  garment_ = cloth.mesh();
  rep.strain_stepped = largest(cloth.nodeStrain(garment_.V));
  if (params_.resolve) {
    const auto t0 = Clock::now();
    correct(body, cloth, quick, rep);
    rep.resolver_run = true;
    rep.seconds_resolve = since(t0);
    // The cloth goes on from the corrected positions; a corrected node keeps its velocity less
    // what points into the body (the correction took it out; its old velocity would take it back).
    const MatrixX3d moved = garment_.V - cloth.positions();
    for (Eigen::Index i = 0; i < moved.rows(); ++i) {
      const double d = moved.row(i).norm();
      if (!(d > 0)) continue;
      const Eigen::RowVector3d u = moved.row(i) / d;
      const double inward = cloth.velocities().row(i).dot(u);
      if (inward < 0) cloth.velocities().row(i) -= inward * u;
    }
    cloth.positions() = garment_.V;
  }
  strain_ = cloth.nodeStrain(garment_.V);
  rep.strain_max = largest(strain_);
  const double spike = params_.drape.max_strain > 0 ? params_.drape.max_strain : cloth.params().stretch_threshold;
  if (params_.relax_passes > 0 && rep.strain_max > spike) {
    rep.relax_passes = cloth.relaxStrainedSprings(params_.relax_passes, params_.relax_compression);
    if (params_.resolve && params_.resolve_relaxed) resolveRelaxed(body, rep);
  }
}

// The steps' cloth (garment_) corrected. With `quick`, where the steps left no spring strained
// past quick_strain, first with the quick relaxation, kept when it converges and still strains
// none past it; else (again from the steps' cloth) with the drape's.
void WornGarment::correct(const Body& body, const ClothState& cloth, bool quick, WornFrameReport& rep) {
  rep.quick_correction = false;
  if (quick && params_.quick_sweeps > 0 && rep.strain_stepped <= params_.quick_strain) {
    const MatrixX3d stepped = garment_.V;
    rep.resolver = resolvePenetrations(body, garment_, quick_resolver_);
    if (rep.resolver.converged && largest(cloth.nodeStrain(garment_.V)) <= params_.quick_strain) {
      rep.quick_correction = true;
      return;
    }
    garment_.V = stepped;
  }
  rep.resolver = resolvePenetrations(body, garment_, frame_resolver_);
}

// The relaxed cloth (its spikes pulled back) resolved again: kept, and published, when that
// resolve converges and leaves it less strained than the first one did.
void WornGarment::resolveRelaxed(const Body& body, WornFrameReport& rep) {
  ClothState& cloth = *cloth_;
  TriMesh relaxed = cloth.mesh();
  const auto t0 = Clock::now();
  const ResolverReport second = resolvePenetrations(body, relaxed, frame_resolver_);
  rep.seconds_resolve += since(t0);
  if (!second.converged) return;
  std::vector<double> strain = cloth.nodeStrain(relaxed.V);
  const double strainMax = largest(strain);
  if (!(strainMax < rep.strain_max)) return;
  rep.resolved_relaxed = true;
  rep.strain_max = strainMax;
  rep.relaxed_resolver = second;
  strain_ = std::move(strain);
  garment_ = std::move(relaxed);
  cloth.positions() = garment_.V;
}

namespace {

// The vertices of the crossings left in `garment`.
std::vector<int> crossingVertices(const Body& body, const TriMesh& garment) {
  const GarmentTopology topo(garment);
  CrossingSet left;
  detectCrossings(body, garment, topo, left);
  std::vector<int> seeds;
  for (const EdgeFaceCrossing& c : left.garment_edges) seeds.push_back(topo.edges(c.edge, 0)), seeds.push_back(topo.edges(c.edge, 1));
  for (const EdgeFaceCrossing& c : left.body_edges)
    for (int k = 0; k < 3; ++k) seeds.push_back(garment.F(c.face, k));
  return seeds;
}

// The nodes whose strain is over `limit`.
std::vector<int> nodesOver(const std::vector<double>& strain, double limit) {
  std::vector<int> out;
  for (std::size_t i = 0; i < strain.size(); ++i)
    if (strain[i] > limit) out.push_back(static_cast<int>(i));
  return out;
}

// Per node of a mesh with faces F, a weight 1 within `inner` rings of edges of the seeds, falling
// linearly to 0 at `outer` rings; all 1 without seeds.
std::vector<double> weightsAround(const MatrixX3i& F, std::size_t n, const std::vector<int>& seeds, int inner, int outer) {
  if (seeds.empty()) return std::vector<double>(n, 1.0);
  std::vector<std::vector<int>> adj(n);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), c = F(f, (k + 1) % 3);
      adj[static_cast<std::size_t>(a)].push_back(c);
      adj[static_cast<std::size_t>(c)].push_back(a);
    }
  std::vector<int> ring(n, -1), queue;
  for (int v : seeds)
    if (ring[static_cast<std::size_t>(v)] < 0) ring[static_cast<std::size_t>(v)] = 0, queue.push_back(v);
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const int u = queue[head];
    if (ring[static_cast<std::size_t>(u)] >= outer) continue;
    for (int v : adj[static_cast<std::size_t>(u)])
      if (ring[static_cast<std::size_t>(v)] < 0) ring[static_cast<std::size_t>(v)] = ring[static_cast<std::size_t>(u)] + 1, queue.push_back(v);
  }
  std::vector<double> w(n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    if (ring[i] >= 0) w[i] = ring[i] <= inner ? 1.0 : std::max(0.0, double(outer - ring[i]) / double(outer - inner));
  return w;
}

// Each cloth node (rows of X, faces F) moved as its nearest body vertex moved from `from` to `to`,
// the moves then averaged with the cloth neighbours' `passes` times (Jacobi, half the node's own):
// neighbours bound to body parts that move apart (two legs, a thigh and a calf) would otherwise
// tear the cloth between them.
MatrixX3d skinDisplacement(const MatrixX3d& from, const MatrixX3d& to, const MatrixX3d& X, const MatrixX3i& F,
                           int passes) {
  const std::vector<int> bound = nearestVertices(from, X);
  MatrixX3d d = MatrixX3d::Zero(X.rows(), 3);
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    const int b = bound[static_cast<std::size_t>(i)];
    if (b >= 0) d.row(i) = to.row(b) - from.row(b);
  }
  MatrixX3d sum(X.rows(), 3);
  std::vector<int> count(static_cast<std::size_t>(X.rows()));
  for (int pass = 0; pass < passes; ++pass) {
    sum.setZero();
    std::fill(count.begin(), count.end(), 0);
    for (Eigen::Index f = 0; f < F.rows(); ++f)
      for (int k = 0; k < 3; ++k) {
        const int a = F(f, k), c = F(f, (k + 1) % 3);
        sum.row(a) += d.row(c);
        sum.row(c) += d.row(a);
        ++count[static_cast<std::size_t>(a)];
        ++count[static_cast<std::size_t>(c)];
      }
    for (Eigen::Index i = 0; i < X.rows(); ++i)
      if (count[static_cast<std::size_t>(i)] > 0) d.row(i) = 0.5 * d.row(i) + 0.5 * sum.row(i) / count[static_cast<std::size_t>(i)];
  }
  return d;
}

}  // namespace

// The frame's correction failed, or left the cloth strained past max_strain. The cloth of the last
// clean frame, each node moved as its nearest body vertex moved since then, is the fallback: first
// only round the trouble (what the correction left crossed, or its strained nodes; the steps' cloth
// elsewhere), then the whole cloth. Each is corrected as a frame's steps are; the first that
// converges (and, for strain, is less strained) is kept. Otherwise everything is put back as the
// steps' correction left it.
void WornGarment::carryWithSkin(const Body& next, double seconds, const MatrixX3d& steppedX, WornFrameReport& rep) {
  ClothState& cloth = *cloth_;
  const MatrixX3d& V = next.mesh().V;
  if (clean_V_.rows() != cloth.positions().rows() || steppedX.rows() != clean_V_.rows() ||
      clean_body_V_.rows() != V.rows() || frames_since_clean_ < 1)
    return;
  const bool failed = !frameClean(rep);
  const std::vector<int> seeds = failed ? crossingVertices(next, garment_) : nodesOver(strain_, params_.drape.max_strain);
  const MatrixX3d carried = clean_V_ + skinDisplacement(clean_body_V_, V, clean_V_, garment_.F, params_.carry_smoothing);
  const MatrixX3d skinVelocity = (carried - clean_V_) / (seconds * frames_since_clean_);
  const std::vector<double> w = weightsAround(garment_.F, static_cast<std::size_t>(carried.rows()), seeds,
                                              params_.carry_rings, 2 * params_.carry_rings);
  const MatrixX3d x = cloth.positions(), v = cloth.velocities();
  const TriMesh before = garment_;
  const std::vector<double> beforeStrain = strain_;
  double resolveSeconds = rep.seconds_resolve;
  for (int attempt = 0; attempt < 2; ++attempt) {
    for (Eigen::Index i = 0; i < carried.rows(); ++i) {
      const double wi = attempt == 0 ? w[static_cast<std::size_t>(i)] : 1.0;
      cloth.positions().row(i) = steppedX.row(i) + wi * (carried.row(i) - steppedX.row(i));
      cloth.velocities().row(i) = (1 - wi) * v.row(i) + wi * skinVelocity.row(i);
    }
    if (correctCarried(next, failed, attempt == 1, resolveSeconds, rep)) return;
  }
  cloth.positions() = x;
  cloth.velocities() = v;
  garment_ = before;
  strain_ = beforeStrain;
  rep.seconds_resolve = resolveSeconds;
}

// The carried cloth (in cloth_) relaxed and corrected as a frame's steps are; taken into rep when
// that converges and (for strain) is less strained than rep.
bool WornGarment::correctCarried(const Body& next, bool failed, bool whole, double& resolveSeconds,
                                 WornFrameReport& rep) {
  // Nodes bound to body parts that move apart (two legs, a thigh and a calf) stretch the cloth
  // between them: that is taken back before the correction.
  if (params_.carry_relax_passes > 0) cloth_->relaxStrainedSprings(params_.carry_relax_passes, params_.relax_compression);
  WornFrameReport again = rep;
  again.relax_passes = 0;
  again.resolved_relaxed = false;
  again.resolver = ResolverReport();
  again.relaxed_resolver = ResolverReport();
  resolveFrame(next, again, /*quick=*/false);  // the fallback's own correction is the drape's, in full
  resolveSeconds += again.seconds_resolve;
  if (!frameClean(again) || !(failed || again.strain_max < rep.strain_max)) return false;
  again.carried = true;
  again.carried_whole = whole;
  again.carried_for_strain = !failed;
  again.carried_from = frames_since_clean_;
  again.stepped_resolver = rep.resolver;
  again.stepped_strain_max = rep.strain_max;
  again.strain_stepped = rep.strain_stepped;
  again.seconds_resolve = resolveSeconds;
  rep = std::move(again);
  return true;
}

bool WornGarment::refused(double seconds, WornFrameReport& rep) const {
  if (!worn())
    rep.message = "no garment is worn: dress() it first";
  else if (!(seconds > 0) || !std::isfinite(seconds))
    rep.message = "the frame interval must be a positive number of seconds (got " + num(seconds) + ")";
  else
    return false;
  return true;
}

WornFrameReport WornGarment::follow(const Body& next, double seconds) {
  const auto t0 = Clock::now();
  WornFrameReport rep;
  if (refused(seconds, rep)) return rep;
  return follow(next, renderer_.render(next, seconds), t0);
}

WornFrameReport WornGarment::follow(const Body& next, WornFrameMaps maps) {
  return follow(next, std::move(maps), Clock::now());
}

WornFrameReport WornGarment::follow(const Body& next, WornFrameMaps prepared, std::chrono::steady_clock::time_point t0) {
  WornFrameReport rep;
  const double seconds = prepared.seconds;
  if (refused(seconds, rep)) return rep;
  if (!prepared.maps.front || prepared.body_V.rows() != next.mesh().V.rows()) {
    rep.message = "the frame's maps were not rendered for this body";
    return rep;
  }
  const auto tMaps = Clock::now();
  renderer_.adopt(prepared);
  rep.grid_rebuilt = prepared.grid_rebuilt;
  FrameMaps to = std::move(prepared.maps);
  // Each view is interpolated on its own grid; one whose grid was rebuilt (the top view's x-z box
  // once a walk has carried the body past its margin) uses the new frame's maps throughout.
  rep.interpolated = params_.interpolate && sameGrid(maps_.front->grid(), to.front->grid());
  FrameMaps from = to;
  if (rep.interpolated) from.front = maps_.front;
  for (std::size_t k = 0; k < kOtherViews.size(); ++k)
    if (params_.interpolate && to.other[k] && maps_.other[k] && sameGrid(maps_.other[k]->grid(), to.other[k]->grid()))
      from.other[k] = maps_.other[k];
  rep.seconds_maps = prepared.seconds_render + since(tMaps);
  const auto tCloth = Clock::now();
  if (!stepFrame(from, to, seconds, rep)) {
    rep.seconds_total = since(t0);
    return rep;
  }
  rep.seconds_cloth = since(tCloth);
  maps_ = std::move(to);
  body_V_ = next.mesh().V;
  rep.success = true;
  const MatrixX3d steppedX = cloth_->positions();
  resolveFrame(next, rep);
  ++frames_since_clean_;
  if (params_.resolve && params_.carry_with_skin &&
      (!frameClean(rep) || (params_.drape.max_strain > 0 && rep.strain_max > params_.drape.max_strain)))
    carryWithSkin(next, seconds, steppedX, rep);
  if (frameClean(rep)) {
    clean_V_ = garment_.V;
    clean_body_V_ = body_V_;
    frames_since_clean_ = 0;
  }
  const double maxStrain = params_.drape.max_strain;
  const bool withinStrain = !(maxStrain > 0) || rep.strain_max <= maxStrain;
  rep.converged = (!rep.resolver_run || rep.resolver.converged || rep.resolved_relaxed) && withinStrain;
  std::ostringstream msg;
  msg << rep.steps << " steps of " << num(rep.dt) << " s";
  if (rep.step_halvings > 0) msg << " (the step halved " << rep.step_halvings << " times after a blow-up)";
  if (rep.relax_passes > 0) msg << "; the cloth's spikes relaxed in " << rep.relax_passes << " passes";
  if (!rep.interpolated) msg << " (maps not interpolated" << (rep.grid_rebuilt ? ": new grid)" : ")");
  if (rep.resolved_relaxed)
    msg << "; the relaxed cloth resolved again (" << rep.relaxed_resolver.garment_edge_crossings_before +
                                                         rep.relaxed_resolver.body_edge_crossings_before
        << " crossings) and kept";
  if (rep.carried) {
    if (rep.carried_for_strain)
      msg << "; the correction left a spring stretched by " << num(rep.stepped_strain_max);
    else
      msg << "; the steps' correction failed ("
          << rep.stepped_resolver.garment_edge_crossings_after + rep.stepped_resolver.body_edge_crossings_after
          << " crossings left)";
    msg << ": the cloth " << rep.carried_from << (rep.carried_from == 1 ? " frame" : " frames")
        << " back carried with the skin " << (rep.carried_whole ? "everywhere" : "around that")
        << " and resolved instead";
  }
  if (rep.resolver_run && !rep.resolver.converged && !rep.resolved_relaxed) msg << "; not converged: resolver: " << rep.resolver.reason;
  if (!withinStrain)
    msg << "; not converged: a spring is stretched by " << num(rep.strain_max) << ", above max_strain " << num(maxStrain);
  rep.message = msg.str();
  rep.seconds_total = since(t0);
  return rep;
}

}  // namespace virtual_tryon
