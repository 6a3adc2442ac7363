// A bounds check of ROS 1 wire-format messages before roscpp's deserializer sees them.
//
// roscpp_serialization trusts every array length prefix: it resizes the vector to the declared
// length and only then finds out whether the bytes are there, so 4 bytes can ask for 2^32
// elements. That is a property of roscpp (a node receives whole messages whose lengths the
// sender chose), not of the conversions under test, so the fuzz targets first walk the message
// and skip inputs whose arrays are longer than the bytes left could hold.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

namespace vt_fuzz {

class Wire {
 public:
  Wire(const std::uint8_t* data, std::size_t size) : p_(data), end_(data + size) {}

  bool skip(std::size_t n) {
    if (static_cast<std::size_t>(end_ - p_) < n) return false;
    p_ += n;
    return true;
  }
  bool u32(std::uint32_t& v) {
    if (end_ - p_ < 4) return false;
    std::memcpy(&v, p_, 4);
    p_ += 4;
    return true;
  }
  // A length-prefixed array of elements of at least `minElement` bytes each.
  bool arrayLength(std::size_t minElement, std::uint32_t& n) {
    if (!u32(n)) return false;
    return static_cast<std::uint64_t>(n) * minElement <= static_cast<std::uint64_t>(end_ - p_);
  }
  bool string() {
    std::uint32_t n;
    return arrayLength(1, n) && skip(n);
  }
  bool header() { return skip(12) && string(); }  // seq, stamp, frame_id

  bool pointCloud2() {
    if (!header() || !skip(8)) return false;  // height, width
    std::uint32_t fields;
    if (!arrayLength(13, fields)) return false;  // name (4 + n), offset 4, datatype 1, count 4
    for (std::uint32_t i = 0; i < fields; ++i)
      if (!string() || !skip(9)) return false;
    if (!skip(1 + 8)) return false;  // is_bigendian, point_step, row_step
    std::uint32_t bytes;
    if (!arrayLength(1, bytes) || !skip(bytes)) return false;
    return skip(1);  // is_dense
  }

  bool polygonMesh() {
    if (!header() || !pointCloud2()) return false;
    std::uint32_t polygons;
    if (!arrayLength(4, polygons)) return false;
    for (std::uint32_t i = 0; i < polygons; ++i) {
      std::uint32_t n;
      if (!arrayLength(4, n) || !skip(4 * static_cast<std::size_t>(n))) return false;
    }
    return true;
  }

 private:
  const std::uint8_t* p_;
  const std::uint8_t* end_;
};

}  // namespace vt_fuzz
