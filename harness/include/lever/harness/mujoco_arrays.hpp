// lever/harness/mujoco_arrays.hpp: MuJoCo's mjModel and mjData arrays found by name, through
// MuJoCo's own list of them (mjxmacro.h's MJMODEL_POINTERS and MJDATA_POINTERS), so that a
// comparison can walk lever's field table (lever/fields.hpp) and find MuJoCo's array of the same
// name instead of naming each pair by hand.
#pragma once

#include <mujoco/mujoco.h>

#include <map>
#include <string>

#include <lever/fields.hpp>

namespace lever::test {

/// The element type of one of MuJoCo's arrays (kOther: float, char, structs: never compared).
enum class MjKind { kDouble, kInt, kByte, kOther };

/// One of MuJoCo's arrays: `rows x cols` elements from `data`, row-major. rows is the size
/// mjxmacro.h gives (for efc arrays: njmax, of which the first nefc are live).
struct MjArray {
  const void* data = nullptr;
  MjKind kind = MjKind::kOther;
  int rows = 0, cols = 0;
};

/// Every array of MJMODEL_POINTERS, by name.
std::map<std::string, MjArray> mujoco_model_arrays(const mjModel* m);
/// Every array of MJDATA_POINTERS, by name, and MJDATA_VECTOR's fixed vectors (energy: 1 x 2).
std::map<std::string, MjArray> mujoco_data_arrays(const mjModel* m, const mjData* d);

/// Element i of MuJoCo's array as a double (kOther: NaN).
double element(const MjArray& array, long i);
/// Element i of lever's array as a double.
double element(const FieldView& view, long i);

/// Whether lever's element type and column count are MuJoCo's (the `mujoco` flag's promise).
bool same_layout(const FieldView& ours, const MjArray& theirs);

}  // namespace lever::test
