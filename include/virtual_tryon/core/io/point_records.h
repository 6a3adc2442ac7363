// Packed point records, as in a sensor_msgs/PointCloud2 or a pcl::PCLPointCloud2: width x height
// points of point_step bytes each, rows row_step bytes apart, each point holding named fields
// (name, offset, datatype, count). A description of such a buffer without ROS or PCL types, and
// the one reader of FLOAT32 / FLOAT64 fields by name and offset that the ROS conversions
// (ros/conversions.h: PointCloud2, PolygonMesh) and the mesh files (STL through PCL, mesh_io.h)
// share: the field lookup, the datatype and point_step checks, the row_step and data size checks,
// and the read. The callers word the messages (which differ) and choose the order of the checks.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <vector>

namespace virtual_tryon {

// Datatype codes, the same as sensor_msgs::PointField's and pcl::PCLPointField's.
constexpr std::uint8_t kPointInt8 = 1;
constexpr std::uint8_t kPointUInt8 = 2;
constexpr std::uint8_t kPointInt16 = 3;
constexpr std::uint8_t kPointUInt16 = 4;
constexpr std::uint8_t kPointInt32 = 5;
constexpr std::uint8_t kPointUInt32 = 6;
constexpr std::uint8_t kPointFloat32 = 7;
constexpr std::uint8_t kPointFloat64 = 8;

// "INT8", ..., "FLOAT64"; "unknown" for any other code.
const char* pointDatatypeName(std::uint8_t datatype);

// One field of a point record. `name` views the string of the message it was taken from.
struct PointRecordField {
  std::string_view name;
  std::uint32_t offset = 0;  // bytes from the start of the point
  std::uint8_t datatype = 0;  // kPoint*
  std::uint32_t count = 0;    // elements (not read: one value per field)
};

// A view of packed point records; the buffer (and the field names) belong to the message.
struct PointRecords {
  std::vector<PointRecordField> fields;
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;  // bytes at data
  std::uint32_t width = 0, height = 0;
  std::uint32_t point_step = 0, row_step = 0;
  bool is_bigendian = false;

  // width * height (no overflow: both are 32-bit).
  std::uint64_t points() const { return static_cast<std::uint64_t>(width) * height; }
  // The first field called `name`, or nullptr.
  const PointRecordField* field(std::string_view name) const;
  // width * point_step: the bytes of one row's points.
  std::uint64_t rowBytes() const { return static_cast<std::uint64_t>(width) * point_step; }
  // Rows are row_step apart when height > 1; a single row only needs rowBytes().
  std::uint64_t rowStride() const { return height > 1 ? row_step : rowBytes(); }
  // rowStride() * (height - 1) + rowBytes(): the bytes the points span. For height >= 1 and
  // width * height <= 2^31 (steps < 2^32), so that nothing overflows 64 bits.
  std::uint64_t bytesNeeded() const { return rowStride() * (height - 1) + rowBytes(); }
};

// The records of `cloud`, a sensor_msgs::PointCloud2 or a pcl::PCLPointCloud2 (the same member
// names), which must outlive them. Nothing is checked.
template <typename Cloud>
PointRecords viewPointRecords(const Cloud& cloud) {
  PointRecords r;
  r.fields.reserve(cloud.fields.size());
  for (const auto& f : cloud.fields)
    r.fields.push_back({std::string_view(f.name), static_cast<std::uint32_t>(f.offset),
                        static_cast<std::uint8_t>(f.datatype), static_cast<std::uint32_t>(f.count)});
  r.data = cloud.data.data();
  r.size = cloud.data.size();
  r.width = static_cast<std::uint32_t>(cloud.width);
  r.height = static_cast<std::uint32_t>(cloud.height);
  r.point_step = static_cast<std::uint32_t>(cloud.point_step);
  r.row_step = static_cast<std::uint32_t>(cloud.row_step);
  r.is_bigendian = cloud.is_bigendian != 0;
  return r;
}

// Whether a field can be read as a float: FLOAT32 or FLOAT64, and its bytes inside the point.
enum class FloatFieldProblem { None, NotFloat, OutsidePointStep };
FloatFieldProblem checkFloatField(const PointRecordField& field, std::uint32_t point_step);
// The bytes of a FLOAT64 (8) or FLOAT32 (4, for any other datatype) field.
inline std::uint32_t floatFieldBytes(const PointRecordField& field) {
  return field.datatype == kPointFloat64 ? 8 : 4;
}

// Whether the buffer holds every point (for points() > 0): rowStride() >= rowBytes() (only
// row_step can be smaller, for height > 1), then size >= bytesNeeded().
enum class PointExtentProblem { None, RowStepTooSmall, DataTooShort };
PointExtentProblem checkPointExtent(const PointRecords& records);

// The value of a FLOAT64 field (else FLOAT32) at `p`, which need not be aligned.
inline double readFloatValue(const std::uint8_t* p, std::uint8_t datatype) {
  if (datatype == kPointFloat64) {
    double v;
    std::memcpy(&v, p, sizeof v);
    return v;
  }
  float fv;
  std::memcpy(&fv, p, sizeof fv);
  return static_cast<double>(fv);
}

// Reads `fields[0 .. count)` (each passed by checkFloatField, the extent by checkPointExtent) of
// every point, row by row, as they are (NaN included): calls out(i, k, value) for the point
// i = row * width + column and the field k.
template <typename Out>
void readFloatFields(const PointRecords& records, const PointRecordField* const* fields, int count,
                     Out&& out) {
  const std::uint64_t rowStride = records.rowStride();
  std::uint64_t i = 0;
  for (std::uint64_t r = 0; r < records.height; ++r) {
    const std::uint8_t* row = records.data + r * rowStride;
    for (std::uint64_t c = 0; c < records.width; ++c, ++i) {
      const std::uint8_t* pt = row + c * records.point_step;
      for (int k = 0; k < count; ++k)
        out(i, k, readFloatValue(pt + fields[k]->offset, fields[k]->datatype));
    }
  }
}

}  // namespace virtual_tryon
