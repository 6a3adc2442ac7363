#include "virtual_tryon/core/drape/drape.h"

#include "virtual_tryon/core/geometry/point_queries.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <sstream>

namespace virtual_tryon {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

constexpr double kSettleWindow = 0.1;  // seconds of simulated time
constexpr int kSettleWindowMin = 25;   // iterations
// Settled also needs the largest strain to have changed by less than this over the window: one
// over-stretched spring relaxing moves a few nodes, which the rms over all nodes does not see.
constexpr double kSettleStrainChange = 0.01;

std::string num(double v) {
  std::ostringstream o;
  o.precision(4);
  o << v;
  return o.str();
}

// Velocity response of every colliding node and quad midpoint; a node that gets several
// responses gets their mean (sec. 6). Templated on the (final) collider so the per-point test
// inlines.
template <class Collider>
class CollisionResponse {
 public:
  CollisionResponse(const Collider& collider, const CollisionParams& p, bool quads,
                    const ClothState& cloth, double dt, double pushOut)
      : collider_(collider), p_(p), quads_(quads), cloth_(cloth), dt_(dt), push_out_(pushOut) {}

  void operator()(const MatrixX3d& x, MatrixX3d& v) {
    const Eigen::Index n = x.rows();
    sum_.setZero(n, 3);
    count_.assign(static_cast<std::size_t>(n), 0);
    Eigen::Vector3d normal;
    double depth = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (!collider_.collide(x.row(i).transpose(), normal, depth)) continue;
      Eigen::Vector3d r = collisionResponse(v.row(i).transpose(), normal, p_.friction, p_.reflection);
      // Beyond the paper: a node deeper than the shell also gets back a fraction of its depth per
      // step, so points the velocity response alone leaves inside come out (bounded: at most
      // push_out * depth / dt).
      if (depth > p_.tol && dt_ > 0) r += (push_out_ * (depth - p_.tol) / dt_) * normal;
      sum_.row(i) += r.transpose();
      ++count_[i];
    }
    if (quads_)
      for (const auto& q : cloth_.quads()) {
        const Eigen::Vector3d mid = 0.25 * (x.row(q[0]) + x.row(q[1]) + x.row(q[2]) + x.row(q[3])).transpose();
        if (!collider_.collide(mid, normal, depth)) continue;
        const Eigen::Vector3d vm = 0.25 * (v.row(q[0]) + v.row(q[1]) + v.row(q[2]) + v.row(q[3])).transpose();
        const Eigen::RowVector3d r = collisionResponse(vm, normal, p_.friction, p_.reflection).transpose();
        for (int c : q) {
          sum_.row(c) += r;
          ++count_[c];
        }
      }
    for (Eigen::Index i = 0; i < n; ++i)
      if (count_[i]) v.row(i) = sum_.row(i) / count_[i];
  }

 private:
  const Collider& collider_;
  CollisionParams p_;
  bool quads_;
  const ClothState& cloth_;
  double dt_, push_out_;
  MatrixX3d sum_;
  std::vector<int> count_;
};

}  // namespace

std::string validateDrapeParams(const DrapeParams& p) {
  auto bad = [](const std::string& what, double v, const std::string& range) {
    return what + " = " + num(v) + " is out of range (" + range + ")";
  };
  if (!(p.spacing > 0.001 && p.spacing <= 0.5)) return bad("spacing", p.spacing, "0.001 < spacing <= 0.5 m");
  const ClothParams& c = p.cloth;
  if (!(c.density > 0) || !std::isfinite(c.density)) return bad("density", c.density, "> 0 kg/m^2");
  if (!(c.k_structural > 0) || !std::isfinite(c.k_structural)) return bad("k_structural", c.k_structural, "> 0 N/m");
  if (!(c.k_shear >= 0) || !std::isfinite(c.k_shear)) return bad("k_shear", c.k_shear, ">= 0 N/m");
  if (!(c.k_flexion >= 0) || !std::isfinite(c.k_flexion)) return bad("k_flexion", c.k_flexion, ">= 0 N/m");
  if (!(c.k_seam > 0) || !std::isfinite(c.k_seam)) return bad("k_seam", c.k_seam, "> 0 N/m");
  if (!(c.damping_rate >= 0) || !std::isfinite(c.damping_rate)) return bad("damping_rate", c.damping_rate, ">= 0 1/s");
  if (!(c.sewing_damping_rate >= 0) || !std::isfinite(c.sewing_damping_rate))
    return bad("sewing_damping_rate", c.sewing_damping_rate, ">= 0 1/s");
  if (!(c.seam_max_stretch > 0) || !std::isfinite(c.seam_max_stretch))
    return bad("seam_max_stretch", c.seam_max_stretch, "> 0 m");
  if (!(c.stretch_threshold >= 0.01 && c.stretch_threshold <= 0.15))
    return bad("stretch_threshold", c.stretch_threshold, "0.01 .. 0.15");
  if (!c.gravity.allFinite()) return "gravity is not finite";
  const CollisionParams& k = p.collision;
  if (!(k.tol > 0) || !std::isfinite(k.tol)) return bad("tol", k.tol, "> 0 m");
  if (k.map_size != 0 && (k.map_size < 16 || k.map_size > 4096))
    return bad("map_size", k.map_size, "0 (from tol) or 16 .. 4096 pixels");
  if (!(k.friction >= 0 && k.friction <= 1)) return bad("friction", k.friction, "0 .. 1");
  if (!(k.reflection >= 0 && k.reflection <= 1)) return bad("reflection", k.reflection, "0 .. 1");
  if (!(p.dt >= 0) || !std::isfinite(p.dt)) return bad("dt", p.dt, ">= 0 s (0: automatic)");
  if (!(p.dt_safety > 0 && p.dt_safety <= 1)) return bad("dt_safety", p.dt_safety, "0 < dt_safety <= 1");
  if (p.max_iterations < 1) return bad("max_iterations", p.max_iterations, ">= 1");
  if (p.max_sew_iterations < 1) return bad("max_sew_iterations", p.max_sew_iterations, ">= 1");
  if (!(p.settle_speed > 0)) return bad("settle_speed", p.settle_speed, "> 0 m/s");
  if (!(p.weld_tolerance >= 0)) return bad("weld_tolerance", p.weld_tolerance, ">= 0 m");
  if (!(p.time_budget >= 0)) return bad("time_budget", p.time_budget, ">= 0 s");
  if (!(p.push_out >= 0 && p.push_out <= 1)) return bad("push_out", p.push_out, "0 .. 1");
  if (p.min_drape_iterations < 0) return bad("min_drape_iterations", p.min_drape_iterations, ">= 0");
  if (p.limits.max_vertices < 1 || p.limits.max_faces < 1) return "limits: max_vertices and max_faces must be >= 1";
  return "";
}

DrapeResult drape(const Body& body, const Pattern& input, const DrapeParams& params,
                  TriMesh& garment, const DrapeProgressCallback& progress, int progress_every) {
  const auto tStart = Clock::now();
  DrapeResult rep;
  const std::string paramError = validateDrapeParams(params);
  if (!paramError.empty()) {
    rep.message = paramError;
    return rep;
  }
  Pattern pattern = input;
  normalizePattern(pattern);
  ClothMesh mesh;
  std::string error;
  if (!meshPattern(pattern, params.spacing, mesh, error, params.limits)) {
    rep.message = error;
    return rep;
  }
  if (mesh.X.rows() > 0) {  // panels placed where they cannot reach the body
    const Eigen::Vector3d lo = mesh.X.colwise().minCoeff().transpose(), hi = mesh.X.colwise().maxCoeff().transpose();
    for (const std::string& w : placementWarnings(body.boxMin(), body.boxMax(), lo, hi))
      rep.warnings.push_back(w);
  }
  ClothState cloth(mesh, params.cloth);
  rep.seams_total = cloth.openSeams();

  // Time step (eq. 4).
  rep.dt_bound = cloth.stableTimeStep();
  rep.dt_bound_paper = cloth.paperTimeStep();
  rep.dt = params.dt > 0 ? params.dt : params.dt_safety * rep.dt_bound;
  if (params.dt > rep.dt_bound) {
    const std::string what = "requested dt " + num(params.dt) + " s is above the stability bound " +
                             num(rep.dt_bound) + " s (0.4 pi sqrt(m / K) with m a node's mass and K the "
                             "sum of the stiffnesses meeting at it; node mass " + num(cloth.nodeMass()) + " kg)";
    if (!params.clamp_dt) {
      rep.message = what;
      return rep;
    }
    rep.warnings.push_back(what + "; clamped to the bound");
    rep.dt = rep.dt_bound;
  }

  // Collisions: maps or BVH, cached with the body.
  std::unique_ptr<ImageSpaceCollider> imageSpace;
  std::unique_ptr<ObjectSpaceCollider> objectSpace;
  std::unique_ptr<CollisionResponse<ImageSpaceCollider>> imageResponse;
  std::unique_ptr<CollisionResponse<ObjectSpaceCollider>> objectResponse;
  if (params.mode == CollisionMode::ImageSpace) {
    auto maps = body.depthMaps(params.collision);
    rep.map_size = std::max(maps->width(), maps->height());
    imageSpace = std::make_unique<ImageSpaceCollider>(maps);
    imageResponse = std::make_unique<CollisionResponse<ImageSpaceCollider>>(
        *imageSpace, params.collision, params.quad_midpoints, cloth, rep.dt, params.push_out);
    cloth.setVelocityHook([&](const MatrixX3d& x, MatrixX3d& v) { (*imageResponse)(x, v); });
  } else {
    body.bvh();
    objectSpace = std::make_unique<ObjectSpaceCollider>(body, params.collision.tol);
    objectResponse = std::make_unique<CollisionResponse<ObjectSpaceCollider>>(
        *objectSpace, params.collision, params.quad_midpoints, cloth, rep.dt, params.push_out);
    cloth.setVelocityHook([&](const MatrixX3d& x, MatrixX3d& v) { (*objectResponse)(x, v); });
  }
  const double weldTol = params.weld_tolerance > 0 ? params.weld_tolerance : std::max(0.5 * params.spacing, 0.015);
  rep.seconds_setup = since(tStart);

  // Sew, weld, drape.
  const auto tSim = Clock::now();
  int drapeIterations = 0;
  bool settled = false, blewUp = false;
  // Settle test on the net motion over a window of kSettleWindow seconds (at least
  // kSettleWindowMin iterations): the rms over nodes of (displacement over the window) / (its
  // duration). The instantaneous node velocities of a cloth resting on the body are dominated by
  // contact chatter: a node pressed onto the body by the cloth's tension leaves the tolerance shell
  // by the reflected velocity, falls back in with one step of the full spring acceleration (a * dt,
  // up to 0.5 m/s) and is stopped again, so its speed jumps while it moves less than a millimetre.
  // That chatter does not move the garment and averages out over the window; a slide or a swing
  // does not (a slide at speed s shows s, and the window is far shorter than a swing of the
  // hanging cloth, about a second).
  const int settleWindow = std::max(kSettleWindowMin, static_cast<int>(std::ceil(kSettleWindow / rep.dt)));
  MatrixX3d settleRef;
  int settleRefIteration = 0;
  double settleRefStrain = 0;  // largest strain at settleRef
  std::string stop;
  while (true) {
    const bool sewing = cloth.openSeams() > 0;
    if (!cloth.step(rep.dt, sewing)) {
      blewUp = true;
      break;
    }
    ++rep.iterations;
    if (sewing) {
      ++rep.sew_iterations;
      cloth.weldClosedSeams(weldTol);
    } else {
      ++drapeIterations;
      if (settleRef.rows() != cloth.positions().rows()) {
        settleRef = cloth.positions();
        settleRefIteration = drapeIterations;
        double strainMean = 0;
        cloth.strain(settleRefStrain, strainMean);
      } else if (drapeIterations - settleRefIteration >= settleWindow) {
        const double span = (drapeIterations - settleRefIteration) * rep.dt;
        rep.net_speed = std::sqrt((cloth.positions() - settleRef).rowwise().squaredNorm().mean()) / span;
        double strainMax = 0, strainMean = 0;
        cloth.strain(strainMax, strainMean);
        const bool strainSteady = std::abs(strainMax - settleRefStrain) < kSettleStrainChange;
        settleRef = cloth.positions();
        settleRefIteration = drapeIterations;
        settleRefStrain = strainMax;
        if (drapeIterations >= params.min_drape_iterations && rep.net_speed < params.settle_speed && strainSteady) {
          settled = true;
          break;
        }
      }
    }
    if (progress && progress_every > 0 && rep.iterations % progress_every == 0) {
      DrapeProgress pr;
      pr.iteration = rep.iterations;
      pr.sewing = cloth.openSeams() > 0;
      pr.seam_gap = cloth.maxSeamGap();
      pr.kinetic_energy = cloth.kineticEnergy();
      pr.max_speed = cloth.maxSpeed();
      pr.seconds = since(tStart);
      if (!progress(pr)) {
        rep.cancelled = true;
        stop = "cancelled at iteration " + std::to_string(rep.iterations);
        break;
      }
    }
    if (sewing && cloth.openSeams() > 0 && rep.sew_iterations >= params.max_sew_iterations) {
      stop = std::to_string(cloth.openSeams()) + " seams still open after " +
             std::to_string(rep.sew_iterations) + " sewing iterations (largest gap " +
             num(cloth.maxSeamGap()) + " m, weld tolerance " + num(weldTol) + " m)";
      break;
    }
    if (rep.iterations >= params.max_iterations) {
      stop = "iteration limit " + std::to_string(params.max_iterations) + " reached before the cloth settled";
      break;
    }
    if (params.time_budget > 0 && since(tStart) > params.time_budget) {
      stop = "time budget " + num(params.time_budget) + " s spent";
      break;
    }
  }
  rep.seconds_simulation = since(tSim);
  rep.seconds_per_iteration = rep.iterations ? rep.seconds_simulation / rep.iterations : 0.0;
  rep.seams_open = cloth.openSeams();
  rep.seam_gap_max = cloth.maxSeamGap();
  rep.seam_gap_mean = cloth.meanSeamGap();
  cloth.strain(rep.strain_max, rep.strain_mean);
  rep.max_speed = cloth.maxSpeed();
  rep.kinetic_energy = cloth.kineticEnergy();
  garment = cloth.mesh();
  rep.vertices = static_cast<std::size_t>(garment.V.rows());
  rep.triangles = static_cast<std::size_t>(garment.F.rows());

  if (blewUp) {
    rep.message = "the integration blew up at iteration " + std::to_string(rep.iterations + 1) +
                  " (a non-finite value or a node faster than " + num(params.cloth.runaway_speed) +
                  " m/s) with dt " + num(rep.dt) + " s, bound " + num(rep.dt_bound) +
                  " s; no garment is returned";
    garment = TriMesh();
    rep.seconds_total = since(tStart);
    return rep;
  }
  rep.success = true;

  // Clean what the collisions let through.
  if (params.resolve) {
    const auto t0 = Clock::now();
    rep.draped_vertices = garment.V;
    // The resolver gets what is left of the drape's budget (at least a millisecond, so that it
    // always makes its first detection pass and reports), unless its own budget is tighter.
    ResolverParams resolverParams = params.resolver;
    if (params.time_budget > 0) {
      const double left = std::max(1e-3, params.time_budget - since(tStart));
      if (resolverParams.time_budget <= 0 || resolverParams.time_budget > left)
        resolverParams.time_budget = left;
    }
    rep.resolver = resolvePenetrations(body, garment, resolverParams);
    rep.resolver_run = true;
    rep.seconds_resolve = since(t0);
    rep.penetrating_before_resolve = rep.resolver.vertices_inside_before;
    rep.penetrating_after = rep.resolver.vertices_inside_after;
  } else if (body.closed()) {
    for (Eigen::Index i = 0; i < garment.V.rows(); ++i)
      rep.penetrating_before_resolve += pointInsideBody(body, garment.V.row(i).transpose());
    rep.penetrating_after = rep.penetrating_before_resolve;
  }
  rep.converged = settled && rep.seams_open == 0 && (!rep.resolver_run || rep.resolver.converged);
  std::ostringstream msg;
  if (rep.converged)
    msg << "draped: " << rep.iterations << " iterations (" << rep.sew_iterations << " sewing), settled";
  else if (!stop.empty())
    msg << "not converged: " << stop;
  else if (rep.resolver_run && !rep.resolver.converged)
    msg << "not converged: resolver: " << rep.resolver.reason;
  else
    msg << "not converged";
  rep.message = msg.str();
  rep.seconds_total = since(tStart);
  return rep;
}

}  // namespace virtual_tryon
