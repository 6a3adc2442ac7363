// Packed point records: see point_records.h.
#include "virtual_tryon/core/io/point_records.h"

namespace virtual_tryon {

const char* pointDatatypeName(std::uint8_t datatype) {
  switch (datatype) {
    case kPointInt8: return "INT8";
    case kPointUInt8: return "UINT8";
    case kPointInt16: return "INT16";
    case kPointUInt16: return "UINT16";
    case kPointInt32: return "INT32";
    case kPointUInt32: return "UINT32";
    case kPointFloat32: return "FLOAT32";
    case kPointFloat64: return "FLOAT64";
    default: return "unknown";
  }
}

const PointRecordField* PointRecords::field(std::string_view name) const {
  for (const PointRecordField& f : fields)
    if (f.name == name) return &f;
  return nullptr;
}

FloatFieldProblem checkFloatField(const PointRecordField& field, std::uint32_t point_step) {
  if (field.datatype != kPointFloat32 && field.datatype != kPointFloat64) return FloatFieldProblem::NotFloat;
  if (static_cast<std::uint64_t>(field.offset) + floatFieldBytes(field) > point_step)
    return FloatFieldProblem::OutsidePointStep;
  return FloatFieldProblem::None;
}

PointExtentProblem checkPointExtent(const PointRecords& records) {
  if (records.rowStride() < records.rowBytes()) return PointExtentProblem::RowStepTooSmall;
  if (records.size < records.bytesNeeded()) return PointExtentProblem::DataTooShort;
  return PointExtentProblem::None;
}

}  // namespace virtual_tryon
