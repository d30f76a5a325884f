// The tinyxml2 backend of the first stage: tinyxml2's document -> Element, with lever's checks.
#include <tinyxml2.h>

#include <string>

#include "xml.hpp"

namespace lever::mjcf::detail {

namespace {

XmlError kind_of(tinyxml2::XMLError id) {
  switch (id) {
    case tinyxml2::XML_ERROR_EMPTY_DOCUMENT: return XmlError::kEmptyDocument;
    case tinyxml2::XML_ERROR_MISMATCHED_ELEMENT: return XmlError::kMismatchedElement;
    case tinyxml2::XML_ERROR_PARSING_ATTRIBUTE: return XmlError::kParsingAttribute;
    case tinyxml2::XML_ERROR_PARSING_TEXT: return XmlError::kParsingText;
    case tinyxml2::XML_ERROR_PARSING_ELEMENT: return XmlError::kParsingElement;
    case tinyxml2::XML_ERROR_PARSING_COMMENT: return XmlError::kParsingComment;
    case tinyxml2::XML_ERROR_PARSING_DECLARATION: return XmlError::kParsingDeclaration;
    case tinyxml2::XML_ERROR_PARSING_UNKNOWN: return XmlError::kParsingUnknown;
    case tinyxml2::XML_ERROR_PARSING_CDATA: return XmlError::kParsingCData;
    case tinyxml2::XML_ELEMENT_DEPTH_EXCEEDED: return XmlError::kDepthExceeded;
    default: return XmlError::kParsing;
  }
}

[[noreturn]] void fail_tinyxml2(const tinyxml2::XMLDocument& doc) {
  // tinyxml2's own text after "Line number=N: ", as the detail
  const std::string text = doc.ErrorStr();
  const size_t colon = text.find(": ", text.find("Line number="));
  fail_xml(kind_of(doc.ErrorID()), doc.ErrorLineNum(),
           colon == std::string::npos ? "" : text.substr(colon + 2));
}

Element convert(const tinyxml2::XMLElement& x, int depth) {
  Element e;
  e.tag = x.Value();
  e.line = x.GetLineNum();
  if (depth > kMaxDepth) fail_depth(e);
  for (const tinyxml2::XMLAttribute* a = x.FirstAttribute(); a; a = a->Next()) {
    e.attributes.push_back({a->Name(), a->Value(), a->GetLineNum()});
    check_attribute_length(e, e.attributes.back());
  }
  for (const tinyxml2::XMLNode* n = x.FirstChild(); n; n = n->NextSibling()) {
    if (const tinyxml2::XMLElement* child = n->ToElement()) {
      e.children.push_back(convert(*child, depth + 1));
    } else if (n->ToText() && !is_blank(n->Value())) {
      fail_text(e);
    }
  }
  return e;
}

}  // namespace

Element read_xml_tinyxml2(const std::string& xml) {
  tinyxml2::XMLDocument doc;
  if (doc.Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS) fail_tinyxml2(doc);
  const tinyxml2::XMLElement* first = doc.RootElement();
  if (!first) fail(Place{}, "", "malformed XML: the document has no element");
  if (const tinyxml2::XMLElement* second = first->NextSiblingElement()) {
    fail(Place{second->Value(), "", second->GetLineNum()}, "",
         "a document has one root element; this one is a second");
  }
  return convert(*first, 1);
}

}  // namespace lever::mjcf::detail
