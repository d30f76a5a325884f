// The model room: Model and Data as arrays (the field table expanded, fields.cpp), Data's sizing
// (data.cpp) and the name lookups (model.cpp). What other rooms take from it: the entry check every
// public function runs at its door, argument-size checks, and warnings recorded into Data.
#pragma once

#include <lever/data.hpp>
#include <lever/fields.hpp>
#include <lever/model.hpp>

namespace lever {

/// Record a warning of kind w about index info (MuJoCo's mj_warning).
inline void record_warning(Data& data, Warning w, int info) {
  WarningStat& stat = data.warning[static_cast<int>(w)];
  ++stat.number;
  stat.lastinfo = info;
}

/// Whether the arrays a caller assigns (the state and the inputs) still have the model's sizes.
inline bool inputs_fit(const Model& model, const Data& data) {
  return data.qpos.size() == model.nq && data.qvel.size() == model.nv &&
         data.qacc.size() == model.nv && data.ctrl.size() == model.nu &&
         data.qfrc_applied.size() == model.nv;
}

/// The check at the door of every public function. Model and Data are matched where they meet:
/// set_const gives a model a fresh tag, and a Data that passed check_fit against a model keeps its
/// tag. A call then costs a comparison of tags and of the input arrays' sizes; only a Data meeting
/// a model (or a model edition) it has not been checked against walks the whole field table.
/// No guard object: nothing to unwind on the hot path. checked_before: this Data has met this
/// model edition and its inputs kept their sizes.
inline bool checked_before(const Model& model, const Data& data) {
  return model.fit_tag != 0 && data.model_tag == model.fit_tag && inputs_fit(model, data);
}

/// The entry check of a function that writes data: a Data that fits adopts the model's tag.
inline void check_entry(const Model& model, Data& data, const char* where) {
  if (checked_before(model, data)) return;
  check_fit(model, data, where);  // throws, naming the array that does not fit
  data.model_tag = model.fit_tag;
}

/// The same for functions that only read data (Jacobians, solves).
inline void check_entry(const Model& model, const Data& data, const char* where) {
  if (checked_before(model, data)) return;
  check_fit(model, data, where);
}

/// Throws StateError unless a vector argument has n elements.
void check_argument_size(long size, long n, const char* where, const char* what);

namespace detail {
/// Size every array of the field table in data for the model, zero-filled (the Data constructor).
void size_data_arrays(const Model& model, Data& data);
}  // namespace detail

}  // namespace lever
