// A synthetic scan of a mesh, as a scanner gives it: points on the surface with noise, no normals.
#pragma once

#include "virtual_tryon/core/geometry/mesh.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace virtual_tryon {

struct SyntheticScanParams {
  std::size_t points = 20000;  // number of samples N (>= 1)
  double noise_sigma = 0.001;  // metres (>= 0): every coordinate gets independent N(0, sigma^2)
                               // noise, i.e. an offset in a uniformly random direction whose
                               // component along any axis, the surface normal included, has
                               // standard deviation sigma
  std::uint64_t seed = 1;      // same seed, same mesh, same parameters: the same points, on every
                               // platform (std::mt19937_64, own uniform and Box-Muller transforms)
};

struct SyntheticScan {
  bool success = false;
  std::string message;         // why not, when !success
  MatrixX3d points;            // #N by 3 scanned points (metres)
  std::vector<int> face;       // #N: the face each point was sampled on (before the noise)
  double surface_area = 0;     // m^2, total area of the sampled mesh
};

// Samples `params.points` points uniformly by area on the surface of `mesh` (#V by 3, #F by 3): a
// face with probability proportional to its area, then a uniform point in it (square-root
// barycentric mapping), then the Gaussian noise. Fails (success = false) on an unusable mesh
// (validate()), a mesh of zero area, zero points or a negative / non-finite sigma.
SyntheticScan syntheticScan(const TriMesh& mesh, const SyntheticScanParams& params = SyntheticScanParams());

}  // namespace virtual_tryon
