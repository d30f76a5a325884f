// lever/mjcf/write.hpp: an MJCF file written again with some of a model's numbers replaced.
//
// What a program that fits a model to data (lever::identify) needs to hand its result back in the
// user's own file: each body's <inertial>, each joint's armature and damping, each actuator's gain
// (and the bias entry a servo ties to it), written where the file says them, everything else kept
// as written (other elements, attributes, default classes, comments). The elements are found by
// the locations the loader records for each compiled object, not by counting tags.
#pragma once

#include <string>

#include <lever/model.hpp>

namespace lever::mjcf {

/// `source` (MJCF text, `filename` for messages) with the parts of `model` that differ from what
/// `source` compiles to written in:
/// - a body whose mass, centre of mass, principal moments or their frame differ: its <inertial>
///   (inserted if the body has none) with pos, quat, mass and diaginertia; any other orientation
///   or fullinertia on it is removed;
/// - a joint whose armature or damping differ: both attributes on its element (a <freejoint>
///   becomes <joint type="free">, the element that takes them);
/// - an actuator whose gainprm or biasprm differ: kp of a <position>, kv of a <velocity> (the
///   tied bias follows), gainprm (and biasprm for an affine bias) of a <general>; a <motor>
///   becomes a <general> with dyntype, gaintype, biastype and gainprm written out.
/// When an <inertial> is written, compiler/inertiafromgeom="true" (which would ignore it) becomes
/// "auto" and every other body with an <inertial> element is written too (so that nothing that
/// "true" ignored starts to count); compiler/settotalmass (which would rescale what is written)
/// is removed and every body with mass is written.
/// Read back, the written file compiles to `model` exactly, but for principal axes (body_iquat)
/// that no quaternion normalizes to exactly: those are written as the nearest that does, within
/// 4 machine epsilons per component.
/// `model` must have the file's structure (bodies and their parents, joints and their types,
/// actuators and their joints); other fields it holds are not written, and must equal the file's
/// (throws lever::Error naming the first that does not, so that nothing is silently dropped).
/// Throws ParseError if `source` does not load, lever::Error if the model does not fit it or the
/// build has no XML writer (the WebAssembly build).
std::string write_string(const std::string& source, const Model& model,
                         const std::string& filename = "<string>");

/// write_string() from the file `source_path` to the file `out_path`, which is written only when
/// everything succeeded. Throws as write_string, or lever::Error if `out_path` cannot be written.
void write_file(const std::string& source_path, const Model& model, const std::string& out_path);

}  // namespace lever::mjcf
