// <tendon>: MuJoCo 2.2.2's fixed tendons (a weighted sum of joint coordinates) and spatial
// tendons (a path of sites, wrapping around spheres and cylinders, split by pulleys), read over
// their default class (read_tendons) and compiled into the Model's tendon_* and wrap_* arrays
// (assemble_tendons).
#pragma once

#include <lever/model.hpp>
#include <vector>

#include "defaults.hpp"
#include "reader.hpp"
#include "spec.hpp"

namespace lever::mjcf::detail {

/// Every <fixed> and <spatial> tendon of the <tendon> sections, in document order, over its class (its own
/// `class`, else the main class).
std::vector<TendonSpec> read_tendons(const Element& root, const DefaultClasses& classes);

/// tendon_* and wrap_* of the model (sized for tendons.size() and their paths) from the specs,
/// the joints, sites and geoms found by name among the model's (already assembled); `limited` is
/// each tendon's limited flag as the compiler resolved it. Throws Problem for an unknown object, a
/// joint that is not a hinge or a slide, a geom that is not a sphere or a cylinder, a spatial path
/// against MuJoCo's rules (see tendon.cpp), or a limited tendon whose range is not lower < upper.
void assemble_tendons(const std::vector<TendonSpec>& tendons, const std::vector<bool>& limited,
                      Model& m);

/// The number of objects in all the tendons' paths (the model's nwrap).
int wrap_count(const std::vector<TendonSpec>& tendons);

}  // namespace lever::mjcf::detail
