// A Model or Data as plain Python values (a dict of numbers, strings and bytes), and back: what
// pickle, copy and multiprocessing see of lever.Model and lever.Data.
//
// Every array of the field table (lever/fields.hpp) is carried under its own name as its raw
// bytes, so a new row of the table is pickled without a line here; what lies outside the table
// (the counts, the names, the keyframes, the options, the asset lists, Data's contacts, warnings,
// efc_J and the factor of M) is listed in state.cpp, next to static_asserts that fail when one of
// those structs grows a member.
#pragma once

#include <pybind11/pybind11.h>

#include <lever/data.hpp>
#include <lever/fields.hpp>
#include <lever/model.hpp>

#include <cstddef>
#include <memory>
#include <vector>

namespace lever_python {

namespace py = pybind11;

/// One member of lever::Contact (MuJoCo's mjContact), from lever's contact field table: data.contact's
/// members are shown as strided numpy views and pickled member by member.
using ContactMember = lever::ContactField;
inline const std::vector<ContactMember>& contact_members() { return lever::contact_field_table(); }
inline bool is_int(const ContactMember& m) { return m.scalar == lever::Scalar::kInt; }

/// The model as a dict: the format version, the counts, the names, the keyframes, the options and
/// asset lists, the warnings, and every array of the field table as bytes.
py::dict model_state(const lever::Model& model);

/// The model model_state described: sized by its counts, every array written back, set_const run,
/// then the table's arrays written again, so that each holds exactly the pickled bytes (a
/// constant edited by hand, or not yet recomputed after an edit, stays as it was). Throws
/// lever::StateError when the state is not one model_state wrote.
std::shared_ptr<lever::Model> model_from_state(const py::dict& state);

/// The data as a dict: time, ncon, nefc, every array of the field table (efc arrays: the nefc live
/// rows), efc_J's live rows, the factor of M (qLD) and the spatial inertias (cinert) that later
/// calls read, the ncon contacts member by member, and the warnings.
py::dict data_state(const lever::Model& model, const lever::Data& data);

/// Writes a data_state into `data`, a Data built for `model`. Throws lever::StateError, naming
/// the array, when the state does not fit the model.
void restore_data(const lever::Model& model, lever::Data& data, const py::dict& state);

}  // namespace lever_python
