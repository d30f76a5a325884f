// <composite>: MuJoCo 2.2.2's composite objects (user_composite.cc, read by xml_native_reader.cc's
// OneComposite), expanded while the body tree is read into the ordinary elements they stand for:
// bodies, joints, geoms, sites (into the body tree), tendons, equality constraints and contact
// exclusions (ahead of the model's own, as MuJoCo adds them while it reads <worldbody>). Types
// particle, grid, rope, loop, cloth, box, cylinder and ellipsoid. Names are MuJoCo's (prefix + B,
// J, JT, JS, G, S, T, TS ... with the indices). The generated elements take MuJoCo's built-in
// defaults, adjusted per type as MuJoCo adjusts them and overwritten by the composite's <joint>,
// <tendon>, <geom> and <site> children; the model's default classes never reach them. The skin
// MuJoCo generates is drawn only: lever has no skins and builds none.
#pragma once

#include <vector>

#include "defaults.hpp"
#include "reader.hpp"
#include "spec.hpp"

namespace lever::mjcf::detail {

/// What composites add outside the body tree, in the order generated.
struct CompositeOutput {
  std::vector<TendonSpec> tendons;
  std::vector<EqualitySpec> equalities;
  std::vector<ExcludeSpec> excludes;
};

/// Expand the <composite> element `e`, written inside `body` (a rope's, loop's or cloth's origin,
/// named prefix + B<x> or B<x>_<y>; else the parent of the generated bodies), `main` being the
/// model's top-level default class (the few constraints MuJoCo adds without a composite default
/// start from its equality defaults). Throws Problem, located at the composite, for what MuJoCo
/// 2.2.2 refuses.
void expand_composite(const Element& e, BodySpec& body, const DefaultClass& main,
                      const AssetSpec& assets, CompositeOutput& out);

}  // namespace lever::mjcf::detail
