// Point Cache 2 read and written, with every declared size checked first.
#include "virtual_tryon/core/io/point_cache.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

namespace virtual_tryon {

namespace {

constexpr char kSignature[12] = {'P', 'O', 'I', 'N', 'T', 'C', 'A', 'C', 'H', 'E', '2', '\0'};
constexpr std::size_t kHeaderBytes = 12 + 4 * 5;

// Little-endian reads and writes, whatever the host's order.
std::uint32_t u32(const unsigned char* p) {
  return std::uint32_t(p[0]) | (std::uint32_t(p[1]) << 8) | (std::uint32_t(p[2]) << 16) | (std::uint32_t(p[3]) << 24);
}
float f32(const unsigned char* p) {
  const std::uint32_t u = u32(p);
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}
void put32(std::string& out, std::uint32_t u) {
  for (int k = 0; k < 4; ++k) out.push_back(static_cast<char>((u >> (8 * k)) & 0xff));
}
void putf(std::string& out, float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  put32(out, u);
}

}  // namespace

bool parsePointCache(const std::string& bytes, PointCache& cache, std::string& error, int expectPoints,
                     const PointCacheLimits& limits) {
  if (bytes.size() < kHeaderBytes) {
    error = "not a point cache: " + std::to_string(bytes.size()) + " bytes, shorter than the 32-byte header";
    return false;
  }
  if (std::memcmp(bytes.data(), kSignature, 12) != 0) {
    error = "not a point cache: the file does not start with the signature POINTCACHE2";
    return false;
  }
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data()) + 12;
  const std::int32_t version = static_cast<std::int32_t>(u32(p));
  const std::int32_t points = static_cast<std::int32_t>(u32(p + 4));
  const float start = f32(p + 8), rate = f32(p + 12);
  const std::int32_t samples = static_cast<std::int32_t>(u32(p + 16));
  if (version != 1) {
    error = "point cache version " + std::to_string(version) + ", only version 1 is read";
    return false;
  }
  if (points < 0 || samples < 0) {
    error = "point cache: negative point count (" + std::to_string(points) + ") or sample count (" +
            std::to_string(samples) + ")";
    return false;
  }
  if (!std::isfinite(start) || !std::isfinite(rate)) {
    error = "point cache: start frame or sample rate is not finite";
    return false;
  }
  if (std::size_t(points) > limits.max_points || std::size_t(samples) > limits.max_samples ||
      std::uint64_t(points) * std::uint64_t(samples) * 3 > limits.max_values) {
    error = "point cache: " + std::to_string(points) + " points x " + std::to_string(samples) +
            " samples is over the limits (" + std::to_string(limits.max_points) + " points, " +
            std::to_string(limits.max_samples) + " samples, " + std::to_string(limits.max_values) + " values)";
    return false;
  }
  if (expectPoints >= 0 && points != expectPoints) {
    error = "point cache has " + std::to_string(points) + " points, the mesh " + std::to_string(expectPoints) +
            " vertices";
    return false;
  }
  const std::uint64_t want = kHeaderBytes + std::uint64_t(points) * std::uint64_t(samples) * 12;
  if (bytes.size() != want) {
    error = "point cache: " + std::to_string(points) + " points x " + std::to_string(samples) + " samples need " +
            std::to_string(want) + " bytes, the file has " + std::to_string(bytes.size()) +
            (bytes.size() < want ? " (truncated)" : " (trailing bytes)");
    return false;
  }
  PointCache out;
  out.points = points;
  out.start_frame = start;
  out.sample_rate = rate;
  out.samples.resize(std::size_t(samples));
  const unsigned char* d = p + 20;
  for (std::int32_t s = 0; s < samples; ++s) {
    MatrixX3d& X = out.samples[std::size_t(s)];
    X.resize(points, 3);
    for (std::int32_t i = 0; i < points; ++i)
      for (int k = 0; k < 3; ++k, d += 4) {
        const float v = f32(d);
        if (!std::isfinite(v)) {
          error = "point cache: sample " + std::to_string(s) + ", point " + std::to_string(i) + " is not finite";
          return false;
        }
        X(i, k) = v;
      }
  }
  cache = std::move(out);
  error.clear();
  return true;
}

bool readPointCache(const std::string& path, PointCache& cache, std::string& error, int expectPoints,
                    const PointCacheLimits& limits) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) {
    error = path + ": cannot open";
    return false;
  }
  const std::streamoff size = in.tellg();
  // The header first, so that a declared size over the limits is refused before the file is read.
  const std::uint64_t cap = kHeaderBytes + std::uint64_t(limits.max_values) * 4;
  if (size < 0 || std::uint64_t(size) > cap) {
    error = path + ": " + std::to_string(size) + " bytes, more than a point cache within the limits can have";
    return false;
  }
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.seekg(0);
  in.read(&bytes[0], size);
  if (!in) {
    error = path + ": read failed";
    return false;
  }
  if (!parsePointCache(bytes, cache, error, expectPoints, limits)) {
    error = path + ": " + error;
    return false;
  }
  return true;
}

std::string pointCacheBytes(const PointCache& cache) {
  std::string out(kSignature, 12);
  put32(out, 1);
  put32(out, static_cast<std::uint32_t>(cache.points));
  putf(out, cache.start_frame);
  putf(out, cache.sample_rate);
  put32(out, static_cast<std::uint32_t>(cache.samples.size()));
  out.reserve(out.size() + cache.samples.size() * std::size_t(std::max(0, cache.points)) * 12);
  for (const MatrixX3d& X : cache.samples)
    for (Eigen::Index i = 0; i < X.rows(); ++i)
      for (int k = 0; k < 3; ++k) putf(out, static_cast<float>(X(i, k)));
  return out;
}

bool writePointCache(const std::string& path, const PointCache& cache, std::string& error) {
  for (std::size_t s = 0; s < cache.samples.size(); ++s)
    if (cache.samples[s].rows() != cache.points) {
      error = "point cache sample " + std::to_string(s) + " has " + std::to_string(cache.samples[s].rows()) +
              " points, not " + std::to_string(cache.points);
      return false;
    }
  std::ofstream out(path, std::ios::binary);
  const std::string bytes = pointCacheBytes(cache);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) {
    error = path + ": cannot write";
    return false;
  }
  return true;
}

}  // namespace virtual_tryon
