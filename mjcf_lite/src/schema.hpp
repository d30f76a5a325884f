// The MJCF subset lever accepts, as one table (in the spirit of MuJoCo's own schema table in
// xml_native_reader.cc): for each element, where it may appear, how often, and its attributes with
// their kind, number count and built-in default. The reader validates every document against it,
// the parser takes built-in defaults from it, and docs/mjcf-subset.md is generated from it.
//
// The table also lists the valid MJCF that lever refuses (elements, attributes, keywords), so that
// an error can tell "valid MJCF that lever does not support" apart from "not MJCF at all".
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace lever::mjcf::detail {

enum class ValueKind {
  kReal,      ///< blank-separated real numbers
  kInteger,   ///< blank-separated integers
  kKeyword,   ///< one word from a fixed list
  kText,      ///< any text (names, class names)
  kEulerSeq,  ///< three letters from x y z X Y Z
};

struct AttributeRule {
  std::string_view name;
  ValueKind kind = ValueKind::kReal;
  int count = 1;                          ///< how many numbers (the maximum, if partial)
  bool partial = false;                   ///< 1..count numbers; the rest keep inherited values
  bool required = false;                  ///< must be written on the element
  std::string_view default_value;         ///< built-in default as MJCF text; "" = unset
  std::string_view keywords;              ///< kKeyword: accepted words, blank-separated
  std::string_view unsupported_keywords;  ///< kKeyword: valid MJCF words lever refuses
  std::string_view meaning;               ///< one line for the docs
  bool list = false;  ///< 1..count numbers, replacing what it inherits (user data)
};

struct ElementRule {
  std::string_view tag;
  std::string_view parent;  ///< tag of the enclosing element ("" for the root)
  char multiplicity = '*';  ///< '!' exactly one, '?' at most one, '*' any number
  std::vector<AttributeRule> attributes;
  std::string_view unsupported_attributes;  ///< valid MJCF attributes lever refuses
  std::string_view unsupported_children;    ///< valid MJCF child elements lever refuses
  std::string_view meaning;
};

/// The `user` attribute of bodies, joints, geoms, sites, tendons, actuators and sensors: MuJoCo's user
/// data, up to 1000 numbers (its reader's buffer), the whole list replacing what a class gave.
AttributeRule user_data_rule();

/// Every element rule, parents before children.
const std::vector<ElementRule>& schema();

/// The rule for `tag` directly inside `parent`, or nullptr.
const ElementRule* find_rule(std::string_view parent, std::string_view tag);

/// The rule of an attribute of `element`, or nullptr.
const AttributeRule* find_attribute(const ElementRule& element, std::string_view name);

/// The attribute rule for `name` of the element `tag` inside `parent`; it must exist.
const AttributeRule& attribute_rule(std::string_view parent, std::string_view tag,
                                    std::string_view name);

/// The words of a blank-separated list.
std::vector<std::string_view> words(std::string_view list);

/// Whether `word` is one of the words of `list`.
bool has_word(std::string_view list, std::string_view word);

/// Every element tag MJCF 2.2.2 knows (supported or not), for telling typos from valid MJCF.
bool is_known_mjcf_element(std::string_view tag);

/// Whether MuJoCo 3 added the element `tag` (attribute "") or the attribute of `tag`: names that
/// models written for MuJoCo 3 carry, which lever refuses by name (those it has are in the table).
bool is_mujoco3_name(std::string_view tag, std::string_view attribute);

/// The Markdown description of the subset (docs/mjcf-subset.md).
std::string markdown();

}  // namespace lever::mjcf::detail
