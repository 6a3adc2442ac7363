// Test helper: PointCloud2 messages with a chosen byte layout, for the conversion tests, the
// malformed-input tables and the fuzz seeds.
#pragma once

#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/PointField.h>

#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

namespace virtual_tryon_test {

struct CloudField {
  std::string name;
  std::uint32_t offset;
  std::uint8_t datatype;  // sensor_msgs::PointField::FLOAT32 or FLOAT64
};

// A cloud of width x height points, `pointStep` bytes each and `rowPadding` bytes after each row,
// laid out by `fields`; every byte starts as `fill`. value(i, field) gives point i's value of a
// field (points counted row by row) or nothing to leave its bytes as they are; it is written as a
// double for FLOAT64 and as a float otherwise. A field that does not fit in the point is skipped.
template <class Value>
sensor_msgs::PointCloud2 buildCloud(const std::vector<CloudField>& fields, std::uint32_t pointStep,
                                    std::uint32_t width, std::uint32_t height, std::uint32_t rowPadding,
                                    std::uint8_t fill, Value value) {
  using sensor_msgs::PointField;
  sensor_msgs::PointCloud2 c;
  c.width = width;
  c.height = height;
  c.point_step = pointStep;
  c.row_step = width * pointStep + rowPadding;
  c.is_bigendian = false;
  c.is_dense = true;
  for (const CloudField& f : fields) {
    PointField pf;
    pf.name = f.name;
    pf.offset = f.offset;
    pf.datatype = f.datatype;
    pf.count = 1;
    c.fields.push_back(pf);
  }
  c.data.assign(static_cast<std::size_t>(c.row_step) * height, fill);
  int i = 0;
  for (std::uint32_t r = 0; r < height; ++r)
    for (std::uint32_t col = 0; col < width; ++col, ++i) {
      std::uint8_t* pt = c.data.data() + static_cast<std::size_t>(r) * c.row_step + col * pointStep;
      for (const CloudField& f : fields) {
        const bool isDouble = f.datatype == PointField::FLOAT64;
        if (f.offset + (isDouble ? 8u : 4u) > pointStep) continue;
        const std::optional<double> v = value(i, f);
        if (!v) continue;
        if (isDouble) {
          std::memcpy(pt + f.offset, &*v, 8);
        } else {
          const float fv = static_cast<float>(*v);
          std::memcpy(pt + f.offset, &fv, 4);
        }
      }
    }
  return c;
}

}  // namespace virtual_tryon_test
