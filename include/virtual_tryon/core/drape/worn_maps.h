// A moving body's maps for a worn garment (WornGarment, worn_garment.h): per body frame the front
// pair of depth and normal maps (with the skin's velocity for frames of one body) and the other
// views' pairs, each on a grid kept while the body stays within it.
//
// This is the part of a worn frame that needs the body alone. WornGarment::follow(next, seconds)
// renders it first; a caller that has the frames in hand (a recorded motion) can instead render
// frame k + 1 on another thread while the cloth steps through frame k, with a copy of the garment's
// renderer (WornGarment::mapRenderer()), and pass it to WornGarment::follow(next, maps).
#pragma once

#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/drape/depth_maps.h"

#include <array>
#include <memory>

namespace virtual_tryon {

// A frame's maps: the front pair (along z) and, where switched on, the pairs of kOtherViews.
struct FrameMaps {
  static constexpr std::array<MapView, 2> kOtherViews{MapView::Top, MapView::Side};
  std::shared_ptr<const DepthMaps> front;
  std::array<std::shared_ptr<const DepthMaps>, 2> other;
};

// One body frame's maps, rendered ahead of WornGarment::follow.
struct WornFrameMaps {
  FrameMaps maps;
  MatrixX3d body_V;           // the frame's body vertices (#V by 3)
  double seconds = 0;         // the interval the skin's velocity was taken over (s)
  bool skin_velocity = false; // velocity maps from the previous frame's vertices
  bool grid_rebuilt = false;  // a view's grid was made anew (the body left it)
  double seconds_render = 0;  // wall time of the rendering
};

struct WornMapParams {
  CollisionParams collision;  // the drape's: its tol is the grids' pixel and the shell
  double grid_margin = 0.25;  // m: see WornGarmentParams::grid_margin
  bool skin_velocity = true;  // velocity maps for frames of one body
  std::array<bool, 2> views{true, false};  // kOtherViews switched on (top, side)
  // Render the views side by side on the hardware threads (false: one after the other, for a
  // renderer that already runs beside other work).
  bool parallel = true;
};

// The grids and the last frame's vertices. Copyable: a copy renders ahead on its own.
class WornMapRenderer {
 public:
  WornMapRenderer() = default;
  // Grids round `first` at `pixel` metres (the drape's map pixel), grown by the margin; its maps
  // without velocity.
  WornMapRenderer(const WornMapParams& params, const Body& first, double pixel, FrameMaps& firstMaps);

  // `next`'s maps, `seconds` after the frame rendered last: a view whose grid no longer holds the
  // body gets a new one (grid_rebuilt). Velocity maps when skin_velocity is on and next has as many
  // vertices as that frame.
  WornFrameMaps render(const Body& next, double seconds);
  // Takes over the state `maps` left (its grids and vertices), as if this renderer had made it.
  void adopt(const WornFrameMaps& maps);

  const MapGrid& grid() const { return grid_; }
  WornMapParams& params() { return params_; }

 private:
  MapGrid gridAround(const Eigen::Vector3d& boxMin, const Eigen::Vector3d& boxMax) const;
  FrameMaps renderViews(const Body& body, const MatrixX3d* velocity) const;

  WornMapParams params_;
  MapGrid grid_;
  std::array<MapGrid, 2> other_grid_;
  double pixel_ = 0;
  MatrixX3d last_V_;
};

// The box of `body` seen from view v (viewPoint of its corners).
void viewBox(MapView v, const Body& body, Eigen::Vector3d& lo, Eigen::Vector3d& hi);

}  // namespace virtual_tryon
