// Point Cache 2 (.pc2): a mesh's vertex positions over time, the format that Blender's Mesh Cache
// modifier and 3ds Max read. A 12-byte signature "POINTCACHE2\0", then int32 version (1), int32
// point count, float32 start frame, float32 sample rate, int32 sample count, then float32 x y z
// per point per sample, little-endian, in the vertex order of the rest mesh.
#pragma once

#include "virtual_tryon/core/geometry/mesh.h"

#include <cstddef>
#include <string>
#include <vector>

namespace virtual_tryon {

struct PointCache {
  int points = 0;
  float start_frame = 0, sample_rate = 1;
  std::vector<MatrixX3d> samples;  // each #points by 3, metres
};

struct PointCacheLimits {
  std::size_t max_points = MeshLimits().max_vertices;
  std::size_t max_samples = 100000;
  std::size_t max_values = std::size_t(1) << 28;  // points x samples x 3 floats (1 GiB as float32)
};

// Parses a whole .pc2 file's bytes. Checked before anything of a declared size is allocated: the
// signature, version 1, point and sample counts >= 0 and within `limits`, the data size against the
// byte count (a truncated or padded file is refused); then every value finite. `expectPoints` >= 0
// also requires that point count (the rest mesh's vertices). On failure `cache` is unchanged and
// false is returned with `error`; nothing is thrown.
bool parsePointCache(const std::string& bytes, PointCache& cache, std::string& error, int expectPoints = -1,
                     const PointCacheLimits& limits = PointCacheLimits());
// Same from a file; messages start with the path.
bool readPointCache(const std::string& path, PointCache& cache, std::string& error, int expectPoints = -1,
                    const PointCacheLimits& limits = PointCacheLimits());
// Writes the cache (float32, little-endian); every sample must have `points` rows. False with
// `error` when it cannot.
bool writePointCache(const std::string& path, const PointCache& cache, std::string& error);
std::string pointCacheBytes(const PointCache& cache);

}  // namespace virtual_tryon
