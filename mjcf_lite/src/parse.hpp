// From the validated element tree to a ModelSpec: sections in MuJoCo's order (compiler, option,
// default, worldbody, actuator, wherever they are written), classes applied, values typed.
#pragma once

#include "defaults.hpp"
#include "reader.hpp"
#include "spec.hpp"

namespace lever::mjcf::detail {

/// One <joint>, <geom> or <site> from the attributes it resolved to (`set`: its class's prototype
/// with its own attributes over it); what `set` lacks takes the schema's built-in value. `e` gives
/// the place and the user data. composite.cpp makes its generated elements with them.
JointSpec read_joint(const Element& e, const AttrSet& set);
GeomSpec read_geom(const Element& e, const AttrSet& set);
SiteSpec read_site(const Element& e, const AttrSet& set);

/// `ignore_inertials`: read the model as if it had no <inertial> elements.
ModelSpec parse_model(const Element& root, bool ignore_inertials);

}  // namespace lever::mjcf::detail
