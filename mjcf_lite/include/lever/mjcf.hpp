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

#include <cstddef>
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

/// What one load accepts at most (docs/reliability.md). Each bounds the memory and time of a load
/// and of the Data it leads to (Data holds nv x nv and 2 njnt x 2 njnt matrices); beyond a limit
/// the load throws a ParseError that names the limit and the element where it was reached.
struct Limits {
  static constexpr std::size_t kDocumentBytes = std::size_t{8} << 20;  ///< 8 MiB of MJCF text
  static constexpr int kTags = 200000;  ///< '<' in the text: tags, comments, declarations
  static constexpr int kDepth = 100;    ///< element nesting (tinyxml2's own limit too)
  static constexpr std::size_t kAttributeBytes = 4096;  ///< one attribute value
  static constexpr int kBodies = 10000;  ///< <body> elements (the world body not counted)
  static constexpr int kJoints = 1000;   ///< <joint> elements in bodies (so nq = nv <= 1000)
  static constexpr int kGeoms = 10000;   ///< <geom> elements in bodies
  static constexpr int kSites = 10000;   ///< <site> elements in bodies
  static constexpr int kMotors = 1000;   ///< <motor> elements
  static constexpr int kClasses = 1000;  ///< <default> elements (default classes)
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
