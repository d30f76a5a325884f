// XML text -> Element tree, the first stage of reading a model. Two interchangeable backends give
// the same tree (and the same error, class and line) for the same text:
//   read_xml_tinyxml2()  tinyxml2 (Debian's libtinyxml2), the native default
//   read_xml_lever()     lever's own small reader (xml_reader.cpp), for builds where tinyxml2 is
//                        not available (the WebAssembly build); tests/mjcf proves the two agree
// Both refuse what tinyxml2 refuses and skip what it skips (comments, <!DOCTYPE ...>, <?...?>
// declarations at the start), and both apply lever's limits (depth, attribute size) and refuse
// text inside elements, in document order.
#pragma once

#include <string>

#include "reader.hpp"

namespace lever::mjcf::detail {

/// Kinds of malformed XML, the ones tinyxml2 reports (its XMLError names).
enum class XmlError {
  kEmptyDocument,
  kMismatchedElement,
  kParsingAttribute,
  kParsingText,
  kParsingElement,
  kParsingComment,
  kParsingDeclaration,
  kParsingUnknown,
  kParsingCData,
  kParsing,
  kDepthExceeded,
};

/// Throw the Problem for malformed XML at `line`: "malformed XML: <what it means> [detail]".
[[noreturn]] void fail_xml(XmlError error, int line, const std::string& detail);

/// The first stage with the backend this build uses (LEVER_XML_READER in CMake).
Element read_xml(const std::string& xml);

Element read_xml_lever(const std::string& xml);
Element read_xml_tinyxml2(const std::string& xml);  ///< defined only where tinyxml2 is linked

/// The checks both backends make on the tree, element by element in document order: nesting
/// depth, the length of each attribute value, no text inside an element.
void check_attribute_length(const Element& e, const Attribute& a);
[[noreturn]] void fail_depth(const Element& e);
[[noreturn]] void fail_text(const Element& e);

/// Whether text is blank for MJCF's purpose (space, tab, newline, carriage return only).
bool is_blank(const std::string& text);

}  // namespace lever::mjcf::detail
