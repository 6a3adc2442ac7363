// libFuzzer target: the Point Cache 2 reader (parsePointCache, limits tightened so that any
// accepted input stays small). A cache that reads must write back to the same bytes.
#include "virtual_tryon/core/io/point_cache.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace vt = virtual_tryon;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  vt::PointCache cache;
  std::string error;
  vt::PointCacheLimits limits;
  limits.max_points = 4096;
  limits.max_samples = 4096;
  limits.max_values = 1 << 20;
  if (!vt::parsePointCache(bytes, cache, error, -1, limits)) {
    if (error.empty()) std::abort();
    return 0;
  }
  // float32 values read back exactly; -0 and the bits of the header's floats too.
  if (vt::pointCacheBytes(cache) != bytes) {
    std::fprintf(stderr, "round trip changed the bytes\n");
    std::abort();
  }
  return 0;
}
