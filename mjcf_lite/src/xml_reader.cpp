// lever's own XML reader: the part of XML that MJCF files use (elements, attributes, comments, the
// five standard entities and character references), with tinyxml2's rules for everything else, so
// that it can stand in for tinyxml2 where that library is not available (the WebAssembly build).
//
// It reads in two passes, as the tinyxml2 path does: first the whole text into a tree (any
// malformed XML is reported here, with tinyxml2's error kind and line), then the tree into
// Elements with lever's checks in document order (convert()). Lines count '\n' characters.
//
// tinyxml2's rules it follows (tests/mjcf/xml_reader_test.cpp compares the two on every model, the
// bad-input corpus and random mutations of them):
//   - the text ends at its first NUL byte; a UTF-8 byte order mark after leading blanks is skipped
//   - "<?...?>" is a declaration, allowed only before anything else in the document
//   - "<!--...-->" comments and "<!...>" declarations (DOCTYPE) are skipped; "<![CDATA[...]]>" is
//     text (so refused inside an element unless blank)
//   - blanks are allowed after '<' and after '</'; a closing tag takes no attributes
//   - names start with a letter, '_', ':' or any byte >= 128, then also digits, '.' and '-'
//   - attribute values in single or double quotes may hold anything but their quote; a repeated
//     attribute is an error
//   - in text and values, "&amp;" "&lt;" "&gt;" "&quot;" "&apos;" and "&#N;" "&#xN;" are replaced;
//     any other '&' stays as it is; CR LF, LF CR and a lone CR become LF
//   - nesting stops at tinyxml2's depth (an element at level 99 cannot have children)
//   - a closing tag at the top level ends the document; text at the top level must be followed by
//     a '<'
#include <cstdint>
#include <string>
#include <vector>

#include "xml.hpp"

namespace lever::mjcf::detail {

namespace {

// tinyxml2's TINYXML2_MAX_ELEMENT_DEPTH: the document counts as one level of parsing
constexpr int kParseDepth = 100;

// A parsed node: an element with its children, or text that is not blank.
struct Node {
  Element element;             // children left empty: they are in `children`
  std::vector<Node> children;  // in document order
  bool is_text = false;
};

bool is_alpha(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); }
bool is_name_start(char c) {
  return static_cast<unsigned char>(c) >= 128 || is_alpha(c) || c == ':' || c == '_';
}
bool is_name_char(char c) { return is_name_start(c) || is_digit(c) || c == '.' || c == '-'; }

// UTF-8 of a character reference; nothing for code points beyond 0x1FFFFF (as tinyxml2)
void append_utf8(uint64_t code, std::string& out) {
  if (code < 0x80) {
    out += static_cast<char>(code);
  } else if (code < 0x800) {
    out += static_cast<char>(0xC0 | (code >> 6));
    out += static_cast<char>(0x80 | (code & 0x3F));
  } else if (code < 0x10000) {
    out += static_cast<char>(0xE0 | (code >> 12));
    out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (code & 0x3F));
  } else if (code < 0x200000) {
    out += static_cast<char>(0xF0 | (code >> 18));
    out += static_cast<char>(0x80 | ((code >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (code & 0x3F));
  }
}

// "&#...;" at raw[i]: appends the character and returns the index after ';', or returns i when the
// reference is not well formed (the '&' is then kept as text)
size_t character_reference(const std::string& raw, size_t i, std::string& out) {
  if (i + 2 >= raw.size()) return i + 2 >= raw.size() && i + 2 == raw.size() ? i + 2 : i;
  const bool hex = raw[i + 2] == 'x';
  const size_t digits = i + (hex ? 3 : 2);
  if (hex && digits >= raw.size()) return i;
  const size_t semicolon = raw.find(';', digits);
  if (semicolon == std::string::npos) return i;
  // digits are read from the last one backwards, with tinyxml2's 32-bit place value
  uint64_t code = 0;
  uint32_t place = 1;
  for (size_t k = semicolon; k > digits; --k) {
    const char c = raw[k - 1];
    uint32_t digit = 0;
    if (is_digit(c)) {
      digit = static_cast<uint32_t>(c - '0');
    } else if (hex && c >= 'a' && c <= 'f') {
      digit = static_cast<uint32_t>(c - 'a' + 10);
    } else if (hex && c >= 'A' && c <= 'F') {
      digit = static_cast<uint32_t>(c - 'A' + 10);
    } else {
      return i;
    }
    code += static_cast<uint32_t>(place * digit);
    place *= hex ? 16u : 10u;
  }
  append_utf8(code, out);
  return semicolon + 1;
}

// Text or an attribute value as tinyxml2 gives it: entities replaced, newlines normalized, cut at
// a NUL (which a reference to character 0 produces).
std::string decode(const std::string& raw, bool entities) {
  static const struct {
    const char* name;
    char value;
  } kEntities[] = {{"quot", '"'}, {"amp", '&'}, {"apos", '\''}, {"lt", '<'}, {"gt", '>'}};
  std::string out;
  out.reserve(raw.size());
  size_t i = 0;
  while (i < raw.size()) {
    const char c = raw[i];
    if (c == '\r' || c == '\n') {
      const char pair = c == '\r' ? '\n' : '\r';
      i += (i + 1 < raw.size() && raw[i + 1] == pair) ? 2 : 1;
      out += '\n';
    } else if (c == '&' && entities && i + 1 < raw.size() && raw[i + 1] == '#') {
      const size_t next = character_reference(raw, i, out);
      if (next == i) {
        out += c;
        ++i;
      } else {
        i = next;
      }
    } else if (c == '&' && entities) {
      bool found = false;
      for (const auto& e : kEntities) {
        const std::string name = e.name;
        if (raw.compare(i + 1, name.size(), name) == 0 && i + 1 + name.size() < raw.size() &&
            raw[i + 1 + name.size()] == ';') {
          out += e.value;
          i += name.size() + 2;
          found = true;
          break;
        }
      }
      if (!found) {
        out += c;
        ++i;
      }
    } else {
      out += c;
      ++i;
    }
  }
  const size_t nul = out.find('\0');
  if (nul != std::string::npos) out.resize(nul);
  return out;
}

class Parser {
 public:
  explicit Parser(const std::string& text) : text_(text) {}

  // The document's top-level nodes (elements and non-blank text).
  std::vector<Node> document() {
    skip_space();
    if (text_.compare(pos_, 3, "\xEF\xBB\xBF") == 0) pos_ += 3;
    if (at_end()) fail_xml(XmlError::kEmptyDocument, 0, "");
    std::vector<Node> nodes;
    std::string end_tag;
    children(nodes, /*depth=*/1, /*in_document=*/true, end_tag);
    return nodes;
  }

 private:
  bool at_end() const { return pos_ >= text_.size(); }
  char peek(size_t ahead = 0) const {
    return pos_ + ahead < text_.size() ? text_[pos_ + ahead] : '\0';
  }
  bool starts(const char* s) const { return text_.compare(pos_, std::string(s).size(), s) == 0; }

  void skip_space() {
    while (!at_end() && is_space(text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
  }

  // Everything up to `end`; moves past it. False (and pos_ unchanged) if `end` never comes.
  bool until(const std::string& end, std::string* content) {
    const size_t found = text_.find(end, pos_);
    if (found == std::string::npos) return false;
    for (size_t k = pos_; k < found; ++k) {
      if (text_[k] == '\n') ++line_;
    }
    if (content) *content = text_.substr(pos_, found - pos_);
    pos_ = found + end.size();
    return true;
  }

  std::string name() {
    const size_t start = pos_;
    if (at_end() || !is_name_start(text_[pos_])) return "";
    while (!at_end() && is_name_char(text_[pos_])) ++pos_;
    return text_.substr(start, pos_ - start);
  }

  // The nodes inside an element (or the document) up to its closing tag, whose name goes to
  // `end_tag` ("" when the text ended first). `depth` counts parsing levels as tinyxml2 does.
  void children(std::vector<Node>& nodes, int depth, bool in_document, std::string& end_tag) {
    if (depth == kParseDepth) {
      fail_xml(XmlError::kDepthExceeded, line_, "elements nested too deep");
    }
    bool only_declarations = true;  // in the document: nothing but declarations so far
    while (true) {
      const size_t start = pos_;
      const int start_line = line_;
      skip_space();
      if (at_end()) return;
      const int node_line = line_;
      if (starts("<?")) {
        pos_ += 2;
        if (!until("?>", nullptr)) fail_xml(XmlError::kParsingDeclaration, node_line, "");
        if (!in_document || !only_declarations) {
          fail_xml(XmlError::kParsingDeclaration, node_line, "a declaration after other content");
        }
        continue;
      }
      only_declarations = false;
      if (starts("<!--")) {
        pos_ += 4;
        if (!until("-->", nullptr)) fail_xml(XmlError::kParsingComment, node_line, "");
      } else if (starts("<![CDATA[")) {
        pos_ += 9;
        std::string content;
        if (!until("]]>", &content)) fail_xml(XmlError::kParsingCData, node_line, "");
        if (!is_blank(decode(content, false))) nodes.push_back(text_node(node_line));
      } else if (starts("<!")) {
        pos_ += 2;
        if (!until(">", nullptr)) fail_xml(XmlError::kParsingUnknown, node_line, "");
      } else if (peek() == '<') {
        ++pos_;
        Node element;
        std::string closing;
        const bool is_closing_tag = element_node(element, depth, closing);
        if (is_closing_tag) {
          end_tag = closing;
          return;
        }
        nodes.push_back(std::move(element));
      } else {
        // text: from the blanks before it up to the next '<', which must come
        pos_ = start;
        line_ = start_line;
        std::string content;
        if (!until("<", &content)) {
          fail_xml(XmlError::kParsingText, node_line, "text without a tag after it");
        }
        // the '<' starts the next node; tinyxml2 calls a '<' that ends the text a parse error
        if (at_end()) fail_xml(XmlError::kParsing, node_line, "");
        --pos_;
        if (!is_blank(decode(content, true))) nodes.push_back(text_node(node_line));
      }
    }
  }

  static Node text_node(int line) {
    Node n;
    n.is_text = true;
    n.element.line = line;
    return n;
  }

  // An element after its '<'. Returns true when it is a closing tag (its name in `closing`);
  // otherwise fills `node`, reading its children and checking its closing tag.
  bool element_node(Node& node, int depth, std::string& closing) {
    const int element_line = line_;
    skip_space();
    const bool is_closing_tag = peek() == '/';
    if (is_closing_tag) ++pos_;
    node.element.tag = name();
    node.element.line = element_line;
    if (node.element.tag.empty())
      fail_xml(XmlError::kParsing, element_line, "an element without a name");
    // attributes, then '>' or '/>'
    bool self_closed = false;
    while (true) {
      skip_space();
      if (at_end()) fail_xml(XmlError::kParsingElement, element_line, "<" + node.element.tag + ">");
      if (is_name_start(peek())) {
        Attribute a;
        a.line = line_;
        if (!attribute(a) || node.element.find(a.name)) {
          fail_xml(XmlError::kParsingAttribute, a.line, "<" + node.element.tag + ">");
        }
        node.element.attributes.push_back(std::move(a));
      } else if (peek() == '>') {
        ++pos_;
        break;
      } else if (peek() == '/' && peek(1) == '>') {
        pos_ += 2;
        self_closed = true;
        break;
      } else {
        fail_xml(XmlError::kParsingElement, element_line, "<" + node.element.tag + ">");
      }
    }
    // "</name/>" is an empty element for tinyxml2, like "<name/>"
    if (self_closed) return false;
    if (is_closing_tag) {
      closing = node.element.tag;
      return true;
    }
    // an open element at the very end of the text: tinyxml2 reports it as unmatched
    if (at_end())
      fail_xml(XmlError::kMismatchedElement, element_line, "<" + node.element.tag + ">");
    std::string end_tag;
    children(node.children, depth + 1, false, end_tag);
    if (end_tag.empty()) fail_xml(XmlError::kParsing, element_line, "<" + node.element.tag + ">");
    if (end_tag != node.element.tag) {
      fail_xml(XmlError::kMismatchedElement, element_line,
               "<" + node.element.tag + "> closed by </" + end_tag + ">");
    }
    return false;
  }

  // name = "value" or name = 'value'
  bool attribute(Attribute& a) {
    a.name = name();
    if (at_end()) return false;
    skip_space();
    if (peek() != '=') return false;
    ++pos_;
    skip_space();
    const char quote = peek();
    if (quote != '"' && quote != '\'') return false;
    ++pos_;
    std::string raw;
    if (!until(std::string(1, quote), &raw)) return false;
    a.value = decode(raw, true);
    return true;
  }

  const std::string& text_;
  size_t pos_ = 0;
  int line_ = 1;
};

// Parsed nodes -> Element, with the checks made in the same order as on tinyxml2's tree.
Element convert(Node& node, int depth) {
  Element e = std::move(node.element);
  if (depth > kMaxDepth) fail_depth(e);
  for (const Attribute& a : e.attributes) check_attribute_length(e, a);
  for (Node& child : node.children) {
    if (child.is_text) fail_text(e);
    e.children.push_back(convert(child, depth + 1));
  }
  return e;
}

}  // namespace

Element read_xml_lever(const std::string& xml) {
  const std::string text = xml.substr(0, xml.find('\0'));
  if (text.empty()) fail_xml(XmlError::kEmptyDocument, 0, "");
  std::vector<Node> nodes = Parser(text).document();
  Node* root = nullptr;
  for (Node& n : nodes) {
    if (n.is_text) continue;
    if (root) {
      fail(Place{n.element.tag, "", n.element.line}, "",
           "a document has one root element; this one is a second");
    }
    root = &n;
  }
  if (!root) fail(Place{}, "", "malformed XML: the document has no element");
  return convert(*root, 1);
}

}  // namespace lever::mjcf::detail
