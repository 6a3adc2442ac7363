// A garment worn on a moving body (Vassilev et al. 2001's "dynamic simulation of garments on moving
// virtual actors"): draped on the first frame, then stepped through the motion.
//
// Between two body frames A and B, T seconds apart, the cloth takes n = ceil(T / dt) steps of T / n.
// The body between them is interpolated in image space: both frames are rendered (depth and normal
// maps, sec. 5) on one pixel grid, and a pixel's depth and normal at step j are the linear blend at
// s = (j + 1) / n. Each pixel's depth moves at (B - A) / T along z, so the surface's speed along its
// normal n is n_z (B - A) / T, and the collision response works on the velocity relative to it
// (core/drape/collision_response.h): a moving arm pushes the sleeve instead of passing through it.
// After the steps, Sun et al. 2016's resolver corrects what is left inside B (the paper's
// correction-based integration), and the cloth goes on from the corrected positions.
#pragma once

#include "virtual_tryon/core/drape/drape.h"
#include "virtual_tryon/core/drape/worn_maps.h"

#include <array>
#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace virtual_tryon {

struct WornGarmentParams {
  // The first frame's drape. Its cloth, collision (tol, friction, reflection), push_out,
  // quad_midpoints, max_strain and resolver (with resolve_polish_strain and resolve_rest_strain)
  // serve every frame after; mode must be image space.
  DrapeParams drape;
  // s: the cloth's step between frames. 0: dt_safety x the explicit step's stability limit for
  // the cloth as draped, 2 / sqrt(lambda_max(M^-1 H)) (ClothState::spectralTimeStep,
  // core/drape/stiffness_spectrum.h), but no longer than the collision tolerance over the fastest
  // surface (tol / kMaxSurfaceSpeed: a moving skin may not pass through the tolerance shell in one
  // step), and at least the drape's step. The drape's own automatic step (0.9 x the per-node eq. 4
  // bound) is 0.52 of that limit on the hm08 dress: 97 steps a 30 Hz frame, where 72 are stable
  // with 30% to spare. Measured on the walk: the dress goes wrong (nodes at 8-25 m/s) at 1.01x the
  // limit and is as at the drape's step at 0.84x; the trousers, strained to 0.146-0.148 on many
  // frames at any step, end one frame at 0.151 at 0.8x and two at 0.176 at 0.75x, none over 0.148
  // at 0.7x. A dt given above the limit is refused (dress fails once the drape has measured it).
  double dt = 0;
  double dt_safety = 0.7;        // (0, 1]
  bool body_velocity = true;     // respond to the velocity relative to the moving surface
  // With body_velocity, for frames of one body (same vertex count): the skin's own velocity
  // (each body vertex's move over the interval / its length, rendered into velocity maps), so
  // that friction carries the cloth along with the skin under it, tangentially too. Off: only the
  // surface's speed along its normal, from the change of depth (what image space alone gives).
  bool skin_velocity = true;
  bool interpolate = true;       // blend the two frames' maps in time; false: B's maps throughout
  bool resolve = true;           // Sun et al.'s resolver after each frame
  // The cloth's strain_restore (ClothParams, Provot's correction) while worn: a body that pushes
  // the cloth (a knee swinging into the hem) stretches it faster than the velocity fix alone
  // holds; this takes the excess back at this fraction a step. 0 .. 1.
  double strain_restore = 0.3;
  // m: the maps' grid is the first frame's x-y box grown by this on every side, so that the frames
  // of a body moving within it share their pixels. A frame that leaves it gets a new grid, and that
  // one interval is not interpolated (WornFrameReport::grid_rebuilt).
  double grid_margin = 0.25;
  // After the resolver's correction the cloth goes on from the corrected garment, less its spikes:
  // when a spring is strained beyond the drape's max_strain, up to this many passes move the ends
  // of each structural spring longer than (1 + stretch_threshold) rest, or shorter than
  // (1 - relax_compression) rest, back to that length (ClothState::relaxStrainedSprings). A spike
  // of the correction (a foot through a trouser hem: springs 6x long) would otherwise snap back at
  // over 100 m/s in the next frame's steps. 0: off.
  int relax_passes = 10;
  // The correction also squeezes springs (a vertex pushed out towards its neighbour): on the walk's
  // sleeveless shirt a spring 24% short after the steps had left it within 6%. 0: stretched
  // springs alone.
  double relax_compression = 0.1;
  // After that relaxation, the relaxed cloth is resolved again; the result is kept (and published)
  // when the resolver converges and leaves it less strained than the first correction did. Off:
  // the returned garment is the first correction, the relaxed cloth only the next frame's start.
  bool resolve_relaxed = true;
  // A frame whose steps left no structural spring strained past quick_strain is first corrected
  // with a lighter shape relaxation: quick_sweeps sweeps over what the resolver moved and
  // quick_rings rings round it (the drape's resolver's are 18 and 8; the cloth's next steps take
  // the shape on from there). It is kept when it converges and still strains no spring past
  // quick_strain; otherwise, and for a frame strained more by its steps, the frame is corrected
  // from the steps' cloth with the drape's relaxation. 0 sweeps: always the drape's.
  int quick_sweeps = 6;
  int quick_rings = 3;
  double quick_strain = 0.15;
  // When a frame's correction does not converge (the steps let a limb through the cloth: on the
  // walk, a calf swinging back through a wide trouser leg, past what the resolver can undo), or
  // leaves a spring past the drape's max_strain after the second resolve, the cloth as it was on
  // the last frame whose correction converged is carried along with the skin instead: each node
  // moves as its nearest body vertex moved since that frame. First only within carry_rings rings
  // of edges of the trouble (what the correction left crossed, or its strained nodes; blended back
  // to the steps' cloth over as many rings again), then the whole cloth. Each is corrected as above
  // (resolver, relaxation, second resolve); the first that converges (and, for strain, is less
  // strained) is kept and the cloth goes on from it (at the skin's velocity where carried). Off:
  // the frame stays as its correction left it and the cloth goes on from there.
  bool carry_with_skin = true;
  int carry_rings = 5;
  // Nodes bound to body parts that move apart (two legs, a thigh and a calf) stretch the carried
  // cloth between them. Passes that average each node's carried move with its cloth neighbours'
  // (0: each node exactly as its nearest body vertex), then passes of the spring relaxation (as
  // relax_passes) before the correction. On the walk's trousers, largest strain 0.75 with
  // neither, 0.59 with 10 relaxation passes, 0.32 with these defaults.
  int carry_smoothing = 10;
  int carry_relax_passes = 40;
  // A frame whose steps blow up is stepped again from where it began with half the step, at most
  // this many times; then the frame fails (nothing moved).
  int step_halvings = 2;
  int max_steps_per_frame = 5000;  // a longer interval is refused
  // Beyond the paper's front and back maps, pairs along y (top_view: the body's tops and
  // undersides) and along x (side_view), rendered per frame (MapView in depth_maps.h): a point
  // deeper than the tolerance shell collides only when it is inside the body seen from each. The
  // front view alone cannot see a hollow along z: a trouser hem over a raised foot lies between
  // the heel's back and the toes' front, and the armhole between an arm swung back and the torso;
  // it pushes them out to the far surface, and the cloth is caught.
  // Measured on the MakeHuman walk: the side view costs about as much again as the front's maps
  // and left the largest strain where it was on the dress (frames 0-39) and the trousers (0-21),
  // so it is off by default.
  bool top_view = true;
  bool side_view = false;
};

struct WornFrameReport {
  bool success = false;    // false: bad input, or the integration blew up (message); nothing moved
  bool converged = false;  // the resolver converged (or did not run) and strain <= max_strain
  std::string message;
  int steps = 0;
  double dt = 0;           // s
  int step_halvings = 0;   // times the frame's step was halved after a blow-up
  int relax_passes = 0;    // passes that relaxed the cloth's spikes after the resolver
  bool resolved_relaxed = false;  // the relaxed cloth was resolved again and kept (less strained)
  bool quick_correction = false;  // the resolver's correction kept was the quick one (quick_sweeps)
  // The last clean cloth carried with the skin (and corrected) was kept: the steps' correction
  // failed, or (carried_for_strain) left a spring past max_strain and the carried cloth is less
  // strained.
  bool carried = false;
  bool carried_for_strain = false;
  bool carried_whole = false;  // with carried: the whole cloth, not only round the trouble
  double stepped_strain_max = 0;  // with carried: strain_max as the steps' correction left it
  int carried_from = -1;   // frames back to that clean cloth (1: the frame before)
  ResolverReport stepped_resolver;  // with carried: the failed correction of the steps
  bool interpolated = false, grid_rebuilt = false;
  std::size_t colliding_nodes = 0;  // the largest count of colliding nodes over the steps
  double strain_max = 0;   // |l / l0 - 1| over structural springs of the returned garment
  double strain_stepped = 0;  // the same after the steps, before the resolver
  double max_speed = 0;    // m/s, at the end of the steps
  bool resolver_run = false;
  ResolverReport resolver;
  ResolverReport relaxed_resolver;  // the second resolve, of the relaxed cloth (resolved_relaxed)
  double seconds_maps = 0, seconds_cloth = 0, seconds_resolve = 0, seconds_total = 0;
};

class WornGarment {
 public:
  explicit WornGarment(WornGarmentParams params = WornGarmentParams());
  ~WornGarment();
  WornGarment(const WornGarment&) = delete;
  WornGarment& operator=(const WornGarment&) = delete;

  // Drapes `pattern` on `body` (the first frame) and wears the result. Not success: nothing is worn.
  // mapsReady, when given, is called before the drape with the renderer of the maps (as
  // mapRenderer() gives it after): the next frames may be rendered with a copy of it, on another
  // thread, while the garment is draped (FramesAhead).
  DrapeResult dress(const Body& body, const Pattern& pattern, const DrapeProgressCallback& progress = nullptr,
                    int progress_every = 25, const std::function<void(const WornMapRenderer&)>& mapsReady = nullptr);
  // Steps the worn cloth from the frame it is on to `next`, `seconds` later (> 0, at most
  // max_steps_per_frame steps). Any body will do (its maps are rendered); a frame of the same body
  // with the same x-y extent keeps the grid and is interpolated.
  WornFrameReport follow(const Body& next, double seconds);
  // The same with `next`'s maps rendered ahead (by a copy of mapRenderer(), on any thread, in frame
  // order): the frame's interval is maps.seconds. This garment's renderer takes over their state.
  WornFrameReport follow(const Body& next, WornFrameMaps maps);
  // A copy of the renderer of this garment's maps, as of the last frame rendered: render the frames
  // that follow with it (WornMapRenderer::render) and hand each to follow(next, maps).
  WornMapRenderer mapRenderer() const { return renderer_; }

  bool worn() const { return cloth_.has_value(); }
  const TriMesh& garment() const { return garment_; }            // as after the last frame
  const std::vector<double>& vertexStrain() const { return strain_; }  // per vertex, the fit map
  const WornGarmentParams& params() const { return params_; }
  const MapGrid& grid() const { return renderer_.grid(); }
  // s: the explicit step's stability limit for the cloth as draped (0 before dress), and the step
  // the frames take (params dt, or as WornGarmentParams::dt says; a frame's step is then shortened
  // to divide its interval evenly).
  double stepLimit() const { return step_limit_; }
  double clothStep() const { return cloth_step_; }

  // m/s: a pixel's surface speed is clamped to this (a pixel whose depth jumps, say from the torso
  // to an arm swinging in front of it, would otherwise throw what it touches at the jump / T).
  static constexpr double kMaxSurfaceSpeed = 5.0;

  using FrameMaps = virtual_tryon::FrameMaps;
  static constexpr std::array<MapView, 2> kOtherViews = FrameMaps::kOtherViews;

 private:
  WornMapParams mapParams() const;
  bool refused(double seconds, WornFrameReport& rep) const;  // not worn, or a bad interval (message)
  WornFrameReport follow(const Body& next, WornFrameMaps prepared, std::chrono::steady_clock::time_point t0);
  bool stepCloth(const FrameMaps& from, const FrameMaps& to, double seconds, double dt, WornFrameReport& rep);
  bool stepFrame(const FrameMaps& from, const FrameMaps& to, double seconds, WornFrameReport& rep);
  void resolveFrame(const Body& body, WornFrameReport& rep, bool quick = true);
  void correct(const Body& body, const ClothState& cloth, bool quick, WornFrameReport& rep);
  void resolveRelaxed(const Body& body, WornFrameReport& rep);
  void carryWithSkin(const Body& next, double seconds, const MatrixX3d& steppedX, WornFrameReport& rep);
  bool correctCarried(const Body& next, bool failed, bool whole, double& resolveSeconds, WornFrameReport& rep);
  bool frameClean(const WornFrameReport& rep) const {
    return rep.resolver_run && (rep.resolver.converged || rep.resolved_relaxed);
  }

  WornGarmentParams params_;
  std::optional<ClothState> cloth_;
  TriMesh garment_;
  std::vector<double> strain_;
  WornMapRenderer renderer_;  // the grids and the frame last rendered
  FrameMaps maps_;  // of the frame the cloth is on
  MatrixX3d body_V_;  // the body's vertices on that frame
  // The cloth after the last frame whose correction converged, the body's vertices on it, and the
  // frames since (carry_with_skin).
  MatrixX3d clean_V_, clean_body_V_;
  int frames_since_clean_ = 0;
  double step_limit_ = 0, cloth_step_ = 0;
  ResolverParams frame_resolver_;
  ResolverParams quick_resolver_;  // frame_resolver_ with the quick relaxation
};

}  // namespace virtual_tryon
