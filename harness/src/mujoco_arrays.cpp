#include <mujoco/mjxmacro.h>
#include <lever/harness/mujoco_arrays.hpp>

#include <cstdint>
#include <limits>
#include <type_traits>

namespace lever::test {

namespace {

template <class T>
constexpr MjKind kind_of() {
  if constexpr (std::is_same_v<T, mjtNum>) return MjKind::kDouble;
  if constexpr (std::is_same_v<T, int>) return MjKind::kInt;
  if constexpr (std::is_same_v<T, mjtByte>) return MjKind::kByte;
  return MjKind::kOther;
}

}  // namespace

// the PREAMBLE macros declare every size some list might use; not every one is used
#pragma GCC diagnostic ignored "-Wunused-variable"

// mjxmacro.h's lists name each array's rows by a member of mjModel and its columns by a number
// or by a local the PREAMBLE macro declares; X reads them as that.
std::map<std::string, MjArray> mujoco_model_arrays(const mjModel* m) {
  std::map<std::string, MjArray> arrays;
  MJMODEL_POINTERS_PREAMBLE(m)
#define X(type, name, rows, cols) \
  arrays[#name] = {m->name, kind_of<type>(), static_cast<int>(m->rows), static_cast<int>(cols)};
  MJMODEL_POINTERS
#undef X
  return arrays;
}

std::map<std::string, MjArray> mujoco_data_arrays(const mjModel* m, const mjData* d) {
  std::map<std::string, MjArray> arrays;
  MJDATA_POINTERS_PREAMBLE(m)
#define X(type, name, rows, cols) \
  arrays[#name] = {d->name, kind_of<type>(), static_cast<int>(m->rows), static_cast<int>(cols)};
  MJDATA_POINTERS
#undef X
  // mjData's fixed vectors (energy[2], ...): one row of all their numbers
#define X(type, name, rows, cols) arrays[#name] = {d->name, kind_of<type>(), 1, (rows) * (cols)};
  MJDATA_VECTOR
#undef X
  return arrays;
}

double element(const MjArray& array, long i) {
  switch (array.kind) {
    case MjKind::kDouble: return static_cast<const mjtNum*>(array.data)[i];
    case MjKind::kInt: return static_cast<const int*>(array.data)[i];
    case MjKind::kByte: return static_cast<const mjtByte*>(array.data)[i];
    case MjKind::kOther: break;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

double element(const FieldView& view, long i) {
  switch (view.info->scalar) {
    case Scalar::kDouble: return static_cast<const double*>(view.data)[i];
    case Scalar::kInt: return static_cast<const int*>(view.data)[i];
    case Scalar::kByte: return static_cast<const uint8_t*>(view.data)[i];
  }
  return std::numeric_limits<double>::quiet_NaN();
}

bool same_layout(const FieldView& ours, const MjArray& theirs) {
  const MjKind kind = ours.info->scalar == Scalar::kDouble ? MjKind::kDouble
                      : ours.info->scalar == Scalar::kInt  ? MjKind::kInt
                                                           : MjKind::kByte;
  return kind == theirs.kind && ours.cols == theirs.cols;
}

}  // namespace lever::test
