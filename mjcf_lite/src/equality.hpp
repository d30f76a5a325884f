// <equality>: MuJoCo 2.2.2's connect, weld, joint and tendon constraints, read over their default
// class (parse) and compiled into the Model's eq_* arrays (compile).
#pragma once

#include <lever/model.hpp>
#include <vector>

#include "defaults.hpp"
#include "reader.hpp"
#include "spec.hpp"

namespace lever::mjcf::detail {

/// Every constraint of the <equality> sections, in document order, over its class (its own
/// `class`, else the main class), with eq_data as MuJoCo 2.2.2's reader leaves it.
std::vector<EqualitySpec> read_equalities(const Element& root, const DefaultClasses& classes);

/// eq_* of the model (sized for equalities.size()) from the specs, the objects found by name
/// among the model's bodies, joints and tendons (already assembled); throws Problem for an unknown or
/// repeated object, or a joint that is not a hinge or a slide.
void assemble_equalities(const std::vector<EqualitySpec>& equalities, Model& m);

}  // namespace lever::mjcf::detail
