// XML to an element tree with line numbers, checked against the schema table. No physics here:
// after read_document() the structure is known to be valid (known elements in allowed places,
// known and supported attributes, required ones present); values are checked later.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <lever/mjcf.hpp>

#include "problem.hpp"

namespace lever::mjcf::detail {

struct Attribute {
  std::string name;
  std::string value;
  int line = 0;
};

struct Element {
  std::string tag;
  int line = 0;
  int index = -1;    ///< position in document order, the root 0 (read_document numbers them)
  std::string file;  ///< the included file it comes from; "" for the model file itself
  std::vector<Attribute> attributes;  ///< in document order
  std::vector<Element> children;      ///< in document order

  /// The attribute called `name`, or nullptr.
  const Attribute* find(std::string_view name) const;
  /// Where this element is, for error messages.
  Place place() const;
  /// Where one of its attributes is (its own line, for elements written over several lines).
  Place place(const Attribute& a) const;
};

/// Deepest element nesting lever accepts (tinyxml2 itself stops at 100).
constexpr int kMaxDepth = Limits::kDepth;

/// Parse MJCF text, replace its <include> elements by the files they name (include.hpp) and
/// validate its structure; throws Problem. `filename` is the model file's path, from whose folder
/// included files are found; `included`, if given, receives their paths in the order read.
Element read_document(const std::string& xml, const std::string& filename = "",
                      std::vector<std::string>* included = nullptr);

/// The limits on the raw text of one file (size, tags), checked before it is read into a tree.
void check_size(const std::string& xml);

/// Character classes of XML text and attribute values (ASCII only, whatever the locale: what the C
/// locale's isspace and isdigit accept). The XML reader and the value parser share them.
inline bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\v' || c == '\f' || c == '\r';
}
inline bool is_digit(char c) { return c >= '0' && c <= '9'; }

}  // namespace lever::mjcf::detail
