#include "virtual_tryon/core/drape/drape.h"

#include "core/drape/collision_response.h"

#include "virtual_tryon/core/geometry/point_queries.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
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

// One drape run: the stages of drape() on the state they share.
// Each seam's two stretch lengths and what the longer takes in (DrapeResult::seam_lengths).
void noteSeamLengths(const Pattern& pattern, DrapeResult& rep) {
  for (const PatternSeam& seam : pattern.seams) {
    DrapeResult::SeamLength l;
    l.a = stretchLength(pattern, seam.a);
    l.b = stretchLength(pattern, seam.b);
    l.take_in = std::abs(l.a - l.b);
    rep.seam_take_in_max = std::max(rep.seam_take_in_max, l.take_in);
    rep.seam_lengths.push_back(l);
  }
}

class DrapeRun {
 public:
  DrapeRun(const Body& body, const DrapeParams& params, const DrapeProgressCallback& progress,
           int progress_every)
      : tStart_(Clock::now()), body_(body), params_(params), progress_(progress),
        progress_every_(progress_every) {}

  DrapeResult run(const Pattern& input, TriMesh& garment) {
    if (!setUp(input)) return rep_;
    simulate();
    takeGarment(garment);
    if (blewUp_) {
      rep_.message = "the integration blew up at iteration " + std::to_string(rep_.iterations + 1) +
                     " (a non-finite value or a node faster than " + num(params_.cloth.runaway_speed) +
                     " m/s) with dt " + num(rep_.dt) + " s, bound " + num(rep_.dt_bound) +
                     " s; no garment is returned";
      garment = TriMesh();
      rep_.seconds_total = since(tStart_);
      return rep_;
    }
    rep_.success = true;
    resolve(garment);
    rep_.vertex_strain = cloth_->nodeStrain(garment.V);
    for (double s : rep_.vertex_strain) rep_.strain_max_final = std::max(rep_.strain_max_final, s);
    summarize();
    return rep_;
  }

  // The cloth after run() (success): at the returned garment's positions, with its velocities, and
  // no collision hook (the run's colliders go with the run).
  std::optional<ClothState> takeCloth(const TriMesh& garment) {
    if (cloth_) {
      cloth_->setVelocityHook(nullptr);
      if (garment.V.rows() == cloth_->positions().rows()) cloth_->positions() = garment.V;
    }
    return std::move(cloth_);
  }

 private:
  // Meshes and places the pattern, builds the cloth, picks the time step and the collider; false
  // (with rep_.message) when the run cannot start.
  bool setUp(const Pattern& input) {
    const std::string paramError = validateDrapeParams(params_);
    if (!paramError.empty()) {
      rep_.message = paramError;
      return false;
    }
    Pattern pattern = input;
    normalizePattern(pattern);
    ClothMesh mesh;
    std::string error;
    if (!meshPattern(pattern, params_.spacing, mesh, error, params_.limits)) {
      rep_.message = error;
      return false;
    }
    if (mesh.X.rows() > 0) {  // panels placed where they cannot reach the body
      const Eigen::Vector3d lo = mesh.X.colwise().minCoeff().transpose(),
                            hi = mesh.X.colwise().maxCoeff().transpose();
      for (const std::string& w : placementWarnings(body_.boxMin(), body_.boxMax(), lo, hi))
        rep_.warnings.push_back(w);
    }
    cloth_.emplace(mesh, params_.cloth);
    rep_.seams_total = cloth_->openSeams();
    rep_.openings = static_cast<std::size_t>(patternOpenings(pattern));
    noteSeamLengths(pattern, rep_);
    if (!chooseTimeStep()) return false;
    makeCollider();
    weldTol_ = params_.weld_tolerance > 0 ? params_.weld_tolerance : std::max(0.5 * params_.spacing, 0.015);
    rep_.seconds_setup = since(tStart_);
    return true;
  }

  // Time step (eq. 4); false when a requested dt above the bound is refused.
  bool chooseTimeStep() {
    rep_.dt_bound = cloth_->stableTimeStep();
    rep_.dt_bound_paper = cloth_->paperTimeStep();
    rep_.dt = params_.dt > 0 ? params_.dt : params_.dt_safety * rep_.dt_bound;
    if (params_.dt > rep_.dt_bound) {
      const std::string what = "requested dt " + num(params_.dt) + " s is above the stability bound " +
                               num(rep_.dt_bound) + " s (0.4 pi sqrt(m / K) with m a node's mass and K the "
                               "sum of the stiffnesses meeting at it; node mass " + num(cloth_->nodeMass()) +
                               " kg)";
      if (!params_.clamp_dt) {
        rep_.message = what;
        return false;
      }
      rep_.warnings.push_back(what + "; clamped to the bound");
      rep_.dt = rep_.dt_bound;
    }
    return true;
  }

  // Collisions: maps or BVH, cached with the body.
  void makeCollider() {
    ClothState& cloth = *cloth_;
    if (params_.mode == CollisionMode::ImageSpace) {
      auto maps = body_.depthMaps(params_.collision);
      rep_.map_size = std::max(maps->width(), maps->height());
      imageSpace_ = std::make_unique<ImageSpaceCollider>(maps);
      imageResponse_ = std::make_unique<CollisionResponse<StillBody<ImageSpaceCollider>>>(
          StillBody<ImageSpaceCollider>{*imageSpace_}, params_.collision, params_.quad_midpoints, cloth, rep_.dt, params_.push_out);
      cloth.setVelocityHook([this](const MatrixX3d& x, MatrixX3d& v) { (*imageResponse_)(x, v); });
    } else {
      body_.bvh();
      objectSpace_ = std::make_unique<ObjectSpaceCollider>(body_, params_.collision.tol);
      objectResponse_ = std::make_unique<CollisionResponse<StillBody<ObjectSpaceCollider>>>(
          StillBody<ObjectSpaceCollider>{*objectSpace_}, params_.collision, params_.quad_midpoints, cloth, rep_.dt, params_.push_out);
      cloth.setVelocityHook([this](const MatrixX3d& x, MatrixX3d& v) { (*objectResponse_)(x, v); });
    }
  }

  // Sew, weld, drape: until settled, blown up, cancelled or out of iterations or time.
  void simulate() {
    const auto tSim = Clock::now();
    // Settle test on the net motion over a window of kSettleWindow seconds (at least
    // kSettleWindowMin iterations): the rms over nodes of (displacement over the window) / (its
    // duration). The instantaneous node velocities of a cloth resting on the body are dominated by
    // contact chatter: a node pressed onto the body by the cloth's tension leaves the tolerance shell
    // by the reflected velocity, falls back in with one step of the full spring acceleration (a * dt,
    // up to 0.5 m/s) and is stopped again, so its speed jumps while it moves less than a millimetre.
    // That chatter does not move the garment and averages out over the window; a slide or a swing
    // does not (a slide at speed s shows s, and the window is far shorter than a swing of the
    // hanging cloth, about a second).
    settleWindow_ = std::max(kSettleWindowMin, static_cast<int>(std::ceil(kSettleWindow / rep_.dt)));
    ClothState& cloth = *cloth_;
    while (true) {
      const bool sewing = cloth.openSeams() > 0;
      if (!cloth.step(rep_.dt, sewing)) {
        blewUp_ = true;
        break;
      }
      ++rep_.iterations;
      if (sewing) {
        ++rep_.sew_iterations;
        cloth.weldClosedSeams(weldTol_);
      } else if (drapeStepSettles()) {
        settled_ = true;
        break;
      }
      if (cancelledByProgress() || limitReached(sewing)) break;
    }
    rep_.seconds_simulation = since(tSim);
  }

  // Counts a drape iteration and runs the settle test when its window is full: true when settled.
  bool drapeStepSettles() {
    const ClothState& cloth = *cloth_;
    ++drapeIterations_;
    if (settleRef_.rows() != cloth.positions().rows()) {
      settleRef_ = cloth.positions();
      settleRefIteration_ = drapeIterations_;
      double strainMean = 0;
      cloth.strain(settleRefStrain_, strainMean);
    } else if (drapeIterations_ - settleRefIteration_ >= settleWindow_) {
      const double span = (drapeIterations_ - settleRefIteration_) * rep_.dt;
      rep_.net_speed = std::sqrt((cloth.positions() - settleRef_).rowwise().squaredNorm().mean()) / span;
      double strainMax = 0, strainMean = 0;
      cloth.strain(strainMax, strainMean);
      const bool strainSteady = std::abs(strainMax - settleRefStrain_) < kSettleStrainChange;
      settleRef_ = cloth.positions();
      settleRefIteration_ = drapeIterations_;
      settleRefStrain_ = strainMax;
      if (drapeIterations_ >= params_.min_drape_iterations && rep_.net_speed < params_.settle_speed &&
          strainSteady)
        return true;
    }
    return false;
  }

  // Reports progress when due; true when the callback cancelled the run.
  bool cancelledByProgress() {
    if (!(progress_ && progress_every_ > 0 && rep_.iterations % progress_every_ == 0)) return false;
    const ClothState& cloth = *cloth_;
    DrapeProgress pr;
    pr.iteration = rep_.iterations;
    pr.sewing = cloth.openSeams() > 0;
    pr.seam_gap = cloth.maxSeamGap();
    pr.kinetic_energy = cloth.kineticEnergy();
    pr.max_speed = cloth.maxSpeed();
    pr.seconds = since(tStart_);
    if (progress_(pr)) return false;
    rep_.cancelled = true;
    stop_ = "cancelled at iteration " + std::to_string(rep_.iterations);
    return true;
  }

  // True (with stop_) when the sewing iterations, the iterations or the time budget are spent.
  bool limitReached(bool sewing) {
    const ClothState& cloth = *cloth_;
    if (sewing && cloth.openSeams() > 0 && rep_.sew_iterations >= params_.max_sew_iterations) {
      std::string which;
      for (int k : cloth.openSeamIndices()) which += (which.empty() ? "" : ", ") + std::to_string(k);
      stop_ = std::to_string(cloth.openSeams()) + " seams still open (" + which + ") after " +
              std::to_string(rep_.sew_iterations) + " sewing iterations (largest gap " +
              num(cloth.maxSeamGap()) + " m, weld tolerance " + num(weldTol_) + " m)";
      return true;
    }
    if (rep_.iterations >= params_.max_iterations) {
      stop_ = "iteration limit " + std::to_string(params_.max_iterations) +
              " reached before the cloth settled";
      return true;
    }
    if (params_.time_budget > 0 && since(tStart_) > params_.time_budget) {
      stop_ = "time budget " + num(params_.time_budget) + " s spent";
      return true;
    }
    return false;
  }

  // The cloth's final state into the report, and its mesh into `garment`.
  void takeGarment(TriMesh& garment) {
    const ClothState& cloth = *cloth_;
    rep_.seconds_per_iteration = rep_.iterations ? rep_.seconds_simulation / rep_.iterations : 0.0;
    rep_.seams_open = cloth.openSeams();
    rep_.seam_gap_max = cloth.maxSeamGap();
    rep_.seam_gap_mean = cloth.meanSeamGap();
    cloth.strain(rep_.strain_max, rep_.strain_mean);
    rep_.max_speed = cloth.maxSpeed();
    rep_.kinetic_energy = cloth.kineticEnergy();
    garment = cloth.mesh();
    rep_.vertices = static_cast<std::size_t>(garment.V.rows());
    rep_.triangles = static_cast<std::size_t>(garment.F.rows());
    rep_.boundary_loops = boundaryLoops(garment);
  }

  // Clean what the collisions let through.
  void resolve(TriMesh& garment) {
    if (params_.resolve) {
      const auto t0 = Clock::now();
      rep_.draped_vertices = garment.V;
      // The resolver gets what is left of the drape's budget (at least a millisecond, so that it
      // always makes its first detection pass and reports), unless its own budget is tighter.
      ResolverParams resolverParams = params_.resolver;
      if (params_.resolve_polish_strain > 0) resolverParams.relaxation.polish_strain = params_.resolve_polish_strain;
      if (params_.resolve_rest_strain > 0) {
        resolverParams.relaxation.rest_strain = params_.resolve_rest_strain;
        for (const Spring& sp : cloth_->springs())
          if (sp.type == SpringType::Structural) resolverParams.relaxation.rest_lengths.push_back({sp.a, sp.b, sp.rest});
      }
      if (params_.time_budget > 0) {
        const double left = std::max(1e-3, params_.time_budget - since(tStart_));
        if (resolverParams.time_budget <= 0 || resolverParams.time_budget > left)
          resolverParams.time_budget = left;
      }
      rep_.resolver = resolvePenetrations(body_, garment, resolverParams);
      rep_.resolver_run = true;
      rep_.seconds_resolve = since(t0);
      rep_.penetrating_before_resolve = rep_.resolver.vertices_inside_before;
      rep_.penetrating_after = rep_.resolver.vertices_inside_after;
    } else if (body_.closed()) {
      for (Eigen::Index i = 0; i < garment.V.rows(); ++i)
        rep_.penetrating_before_resolve += pointInsideBody(body_, garment.V.row(i).transpose());
      rep_.penetrating_after = rep_.penetrating_before_resolve;
    }
  }

  // Converged or not, and the one-line summary.
  void summarize() {
    const bool watertight = rep_.boundary_loops == rep_.openings;
    const bool withinStrain = !(params_.max_strain > 0) || rep_.strain_max_final <= params_.max_strain;
    rep_.converged = settled_ && rep_.seams_open == 0 && watertight && withinStrain &&
                     (!rep_.resolver_run || rep_.resolver.converged);
    std::ostringstream msg;
    if (rep_.converged)
      msg << "draped: " << rep_.iterations << " iterations (" << rep_.sew_iterations << " sewing), settled";
    else if (!stop_.empty())
      msg << "not converged: " << stop_;
    else if (rep_.seams_open == 0 && !watertight)
      msg << "not converged: the garment has " << rep_.boundary_loops << " boundary loops for the pattern's "
          << rep_.openings << " openings (holes along its seams)";
    else if (rep_.resolver_run && !rep_.resolver.converged)
      msg << "not converged: resolver: " << rep_.resolver.reason;
    else if (!withinStrain)
      msg << "not converged: a spring is stretched by " << num(rep_.strain_max_final)
          << " of its rest length, above max_strain " << num(params_.max_strain)
          << " (a seam or an opening too tight for the body, or cloth too soft for its weight)";
    else
      msg << "not converged";
    rep_.message = msg.str();
    rep_.seconds_total = since(tStart_);
  }

  const Clock::time_point tStart_;
  const Body& body_;
  const DrapeParams& params_;
  const DrapeProgressCallback& progress_;
  const int progress_every_;
  DrapeResult rep_;

  std::optional<ClothState> cloth_;
  std::unique_ptr<ImageSpaceCollider> imageSpace_;
  std::unique_ptr<ObjectSpaceCollider> objectSpace_;
  std::unique_ptr<CollisionResponse<StillBody<ImageSpaceCollider>>> imageResponse_;
  std::unique_ptr<CollisionResponse<StillBody<ObjectSpaceCollider>>> objectResponse_;
  double weldTol_ = 0;

  int drapeIterations_ = 0;
  bool settled_ = false, blewUp_ = false;
  int settleWindow_ = 0;
  MatrixX3d settleRef_;
  int settleRefIteration_ = 0;
  double settleRefStrain_ = 0;  // largest strain at settleRef_
  std::string stop_;
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
  if (!(c.strain_restore >= 0 && c.strain_restore <= 1)) return bad("strain_restore", c.strain_restore, "0 .. 1");
  if (c.weld_relax_passes < 0 || c.weld_relax_passes > 10000)
    return bad("weld_relax_passes", c.weld_relax_passes, "0 .. 10000");
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
  if (!(p.resolve_polish_strain >= 0)) return bad("resolve_polish_strain", p.resolve_polish_strain, ">= 0");
  if (!(p.resolve_rest_strain >= 0)) return bad("resolve_rest_strain", p.resolve_rest_strain, ">= 0");
  if (!(p.max_strain >= 0) || !std::isfinite(p.max_strain)) return bad("max_strain", p.max_strain, ">= 0 (0: no limit)");
  if (!(p.weld_tolerance >= 0)) return bad("weld_tolerance", p.weld_tolerance, ">= 0 m");
  if (!(p.time_budget >= 0)) return bad("time_budget", p.time_budget, ">= 0 s");
  if (!(p.push_out >= 0 && p.push_out <= 1)) return bad("push_out", p.push_out, "0 .. 1");
  if (p.min_drape_iterations < 0) return bad("min_drape_iterations", p.min_drape_iterations, ">= 0");
  if (p.limits.max_vertices < 1 || p.limits.max_faces < 1) return "limits: max_vertices and max_faces must be >= 1";
  return "";
}

DrapeResult drape(const Body& body, const Pattern& input, const DrapeParams& params,
                  TriMesh& garment, const DrapeProgressCallback& progress, int progress_every) {
  return DrapeRun(body, params, progress, progress_every).run(input, garment);
}

DrapeResult drape(const Body& body, const Pattern& input, const DrapeParams& params, TriMesh& garment,
                  std::optional<ClothState>& cloth, const DrapeProgressCallback& progress, int progress_every) {
  DrapeRun run(body, params, progress, progress_every);
  DrapeResult rep = run.run(input, garment);
  cloth.reset();
  if (rep.success) cloth = run.takeCloth(garment);
  return rep;
}

}  // namespace virtual_tryon
