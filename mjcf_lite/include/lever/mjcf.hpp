// lever/mjcf.hpp: mjcf_lite, a parser and compiler for the subset of MJCF that arm models use.
//
// It follows MuJoCo 2.2.2's compiler wherever that defines the result (defaults, frames, inertia
// inferred from geoms, joint and actuator wiring), with one deliberate difference: `autolimits`
// defaults to true, as in MuJoCo 3. Anything outside the subset is refused with an error naming
// it; nothing is silently ignored. A load returns a complete Model or throws; never half a model.
#pragma once

#include <string>

#include <lever/error.hpp>
#include <lever/model.hpp>

namespace lever::mjcf {

/// A model file that cannot be loaded. what() reads like a compiler diagnostic:
///   arm2.xml:11: error: <joint name="elbow">: unknown attribute 'rnage' (did you mean 'range'?)
class ParseError : public Error {
 public:
  ParseError(std::string file, int line, std::string element, std::string attribute,
             std::string problem);

  const std::string& file() const { return file_; }            ///< as given to the loader
  int line() const { return line_; }                           ///< 1-based; 0 if none applies
  const std::string& element() const { return element_; }      ///< e.g. "joint"; "" if none
  const std::string& attribute() const { return attribute_; }  ///< e.g. "range"; "" if none
  const std::string& problem() const { return problem_; }      ///< the message without location

 private:
  std::string file_, element_, attribute_, problem_;
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

/// The supported subset as a Markdown table (elements, attributes, defaults).
std::string schema_markdown();

}  // namespace lever::mjcf
