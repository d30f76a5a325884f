// lever/model_check.hpp: whether a model's parameters make a model lever can evaluate.
//
// set_const() runs this check before it computes anything, so every path that prepares a model
// (a load, an edit from C++, Python or JavaScript followed by set_const) is checked the same way.
// Most of it is driven by the field table (lever/fields.hpp): every array's size, every double
// finite, and the ranges some arrays must keep (masses, inertias, armature, damping and stiffness
// non-negative; quaternions not zero; a range used by a flag ordered). What the table cannot say
// (the tree's wiring, the option block, the keyframes, the supported kinds) is checked by hand.
#pragma once

#include <lever/model.hpp>

namespace lever {

/// Throws ModelError at the first thing that makes the model's parameters unusable: counts that
/// disagree, an array of the wrong size, a tree that is not wired in order, a non-finite number,
/// a negative mass, inertia, armature, damping or stiffness, a zero quaternion, a used range with
/// lo >= hi, an unsupported kind. When one object is at fault the error names it (object() and
/// index(), so a loader can point at its element). The arrays set_const computes
/// (LEVER_MODEL_CONSTANTS) are not looked at. Changes nothing.
void validate(const Model& model);

}  // namespace lever
