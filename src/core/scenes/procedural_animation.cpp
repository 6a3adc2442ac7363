#include "virtual_tryon/core/scenes/procedural_animation.h"

#include "virtual_tryon/core/scenes/demo_scene.h"
#include "virtual_tryon/core/scenes/procedural_body.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace virtual_tryon {

double proceduralSwayAngle(const ProceduralAnimationParams& p, int frame) {
  const double cycle = p.rate * p.period;
  return cycle > 0 ? p.amplitude * std::sin(2 * M_PI * frame / cycle) : 0.0;
}

MatrixX3d poseProcedural(const MatrixX3d& V, const ProceduralAnimationParams& p, int frame) {
  const ProceduralBodyLandmarks L = proceduralBodyLandmarks();
  const Eigen::Vector3d pivot(0, L.waist_y, L.waist_z);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(proceduralSwayAngle(p, frame), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  MatrixX3d out(V.rows(), 3);
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    const Eigen::Vector3d x = V.row(i).transpose();
    const double t = p.blend > 0 ? std::clamp((x.y() - (L.waist_y - p.blend)) / (2 * p.blend), 0.0, 1.0)
                                 : (x.y() >= L.waist_y ? 1.0 : 0.0);
    const double w = t * t * (3 - 2 * t);  // smoothstep: the torso bone's weight
    const Eigen::Vector3d turned = R * (x - pivot) + pivot;
    out.row(i) = ((1 - w) * x + w * turned).transpose();
  }
  return out;
}

ProceduralAnimation makeProceduralAnimation(const ProceduralAnimationParams& params) {
  ProceduralAnimation a;
  a.rate = params.rate;
  a.body = makeProceduralBody();
  const DemoSceneParams d;  // the demo's garment, without its scan
  const ProceduralBodyLandmarks L = proceduralBodyLandmarks();
  a.garment = makeWrinkledWaistTube(L.waist_y - 0.10, L.waist_y + 0.12, d.garment_segments, d.garment_rings,
                                    d.garment_gap, d.garment_dip);
  const int frames = std::max(1, params.frames);
  for (int f = 0; f < frames; ++f) {
    a.body_frames.push_back(poseProcedural(a.body.V, params, f));
    a.garment_frames.push_back(poseProcedural(a.garment.V, params, f));
  }
  return a;
}

}  // namespace virtual_tryon
