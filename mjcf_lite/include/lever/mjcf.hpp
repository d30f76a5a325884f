// lever/mjcf.hpp: mjcf_lite, a parser and compiler for the subset of MJCF that arm models use.
//
// It follows MuJoCo 2.2.2's compiler wherever that defines the result (defaults, frames, inertia
// inferred from geoms, joint and actuator wiring), with one deliberate difference in the numbers:
// `autolimits` defaults to true, as in MuJoCo 3. Some inputs that 2.2.2 accepts but that are
// almost certainly mistakes are refused (non-finite numbers, a non-positive timestep, a number
// list ending in a blank, a zero quaternion; docs/mjcf-subset.md lists them all). Anything outside
// the subset is refused with an error naming it; nothing is silently ignored. A load returns a
// complete Model or throws; never half a model.
#pragma once

#include <lever/error.hpp>
#include <lever/model.hpp>
#include <string>

namespace lever::mjcf {

/// A model file that cannot be loaded. what() reads like a compiler diagnostic:
///   arm2.xml:11: error: <joint name="elbow">: unknown attribute 'rnage' (did you mean 'range'?)
/// Problems with the MJCF *language* (unknown element or attribute, typo) are told apart from
/// valid MJCF that lever does not support ("... is valid MJCF but not supported by lever").
class ParseError : public Error {
 public:
  /// `element_name` is the element's `name` attribute, shown in what() as <joint name="elbow">.
  ParseError(std::string file, int line, std::string element, std::string attribute,
             std::string problem, std::string element_name = "");

  const std::string& file() const { return file_; }                  ///< as given to the loader
  int line() const { return line_; }                                 ///< 1-based; 0 if none applies
  const std::string& element() const { return element_; }            ///< e.g. "joint"; "" if none
  const std::string& element_name() const { return element_name_; }  ///< its name=; "" if none
  const std::string& attribute() const { return attribute_; }        ///< e.g. "range"; "" if none
  const std::string& problem() const { return problem_; }  ///< the message without location

 private:
  std::string file_, element_, element_name_, attribute_, problem_;
  int line_;
};

struct LoadOptions {
  /// Ignore every <inertial> and infer all masses from geoms, as MuJoCo would without them
  /// (what `lever check` compares explicit inertias against).
  bool infer_inertia_from_geoms = false;
};

/// Load and compile an MJCF file. Throws ParseError.
Model load_file(const std::string& path, const LoadOptions& options = {});

/// Load and compile MJCF text; `filename` is used in messages. Throws ParseError.
Model load_string(const std::string& xml, const std::string& filename = "<string>",
                  const LoadOptions& options = {});

/// The supported subset as Markdown (elements, attributes, defaults), generated from the
/// schema table the reader validates against. docs/mjcf-subset.md is its output
/// (`lever model --schema > docs/mjcf-subset.md`).
std::string schema_markdown();

}  // namespace lever::mjcf
