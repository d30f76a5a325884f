// XML -> element tree (xml.hpp: tinyxml2 or lever's own reader), then structural validation
// against the schema table.
#include "reader.hpp"

#include <map>
#include <string>

#include "include.hpp"
#include "schema.hpp"
#include "xml.hpp"

namespace lever::mjcf::detail {

const Attribute* Element::find(std::string_view name) const {
  for (const Attribute& a : attributes) {
    if (a.name == name) return &a;
  }
  return nullptr;
}

Place Element::place() const {
  const Attribute* n = find("name");
  return Place{tag, n ? n->value : "", line, index, file};
}

Place Element::place(const Attribute& a) const {
  Place p = place();
  if (a.line > 0) p.line = a.line;
  return p;
}

// ---- the checks both XML backends make (xml.hpp) ------------------------------------------

namespace {

std::string describe(XmlError error) {
  switch (error) {
    case XmlError::kEmptyDocument: return "the document is empty";
    case XmlError::kMismatchedElement:
      return "a closing tag does not match its opening tag (an element left open?)";
    case XmlError::kParsingAttribute:
      return "cannot read an attribute (repeated, or its value not in quotes?)";
    case XmlError::kParsingText: return "cannot read text (is this an XML file?)";
    case XmlError::kParsingElement: return "cannot read an element";
    case XmlError::kParsingComment: return "cannot read a comment";
    case XmlError::kDepthExceeded:
      return "elements are nested more than " + std::to_string(kMaxDepth) + " levels deep";
    default: return "cannot parse the XML";
  }
}

}  // namespace

void fail_xml(XmlError error, int line, const std::string& detail) {
  std::string message = "malformed XML: " + describe(error);
  if (!detail.empty()) message += " [" + detail + "]";
  fail(Place{"", "", line}, "", message);
}

bool is_blank(const std::string& text) {
  for (const char c : text) {
    if (c != ' ' && c != '\t' && c != '\n' && c != '\r') return false;
  }
  return true;
}

void check_attribute_length(const Element& e, const Attribute& a) {
  if (a.value.size() > Limits::kAttributeBytes) {
    fail(e.place(a), a.name,
         "attribute '" + a.name + "' is " + std::to_string(a.value.size()) +
             " bytes long; lever accepts at most " + std::to_string(Limits::kAttributeBytes) +
             " (a limit, see docs/reliability.md)");
  }
}

void fail_depth(const Element& e) {
  fail(e.place(), "",
       "elements are nested more than " + std::to_string(kMaxDepth) + " levels deep");
}

void fail_text(const Element& e) {
  // MJCF carries everything in attributes; text would be silently dropped
  fail(e.place(), "", "unexpected text inside <" + e.tag + ">: MJCF elements take attributes only");
}

Element read_xml(const std::string& xml) {
#ifdef LEVER_XML_READER_TINYXML2
  return read_xml_tinyxml2(xml);
#else
  return read_xml_lever(xml);
#endif
}

namespace {

// ---- validation ------------------------------------------------------------------------------

const char* const kDocs = " (see docs/mjcf-subset.md)";

std::vector<std::string_view> child_tags(std::string_view parent) {
  std::vector<std::string_view> tags;
  for (const ElementRule& r : schema()) {
    if (r.parent == parent) tags.push_back(r.tag);
  }
  return tags;
}

std::vector<std::string_view> parents_of(std::string_view tag) {
  std::vector<std::string_view> parents;
  for (const ElementRule& r : schema()) {
    if (r.tag == tag && !r.parent.empty()) parents.push_back(r.parent);
  }
  return parents;
}

// why an element that MJCF knows cannot be here
std::string misplaced(std::string_view tag, std::string_view parent) {
  std::string message =
      "<" + std::string(tag) + "> is not allowed in <" + std::string(parent) + ">";
  if (parent == "worldbody" && (tag == "joint" || tag == "freejoint")) {
    return message + ": the world body cannot move; put the joint in a <body>";
  }
  if (parent == "worldbody" && tag == "inertial") {
    return message + ": the world body has no mass; put <inertial> in a <body>";
  }
  const std::vector<std::string_view> homes = parents_of(tag);
  if (!homes.empty()) {
    std::string where;
    for (size_t i = 0; i < homes.size(); ++i) {
      where +=
          (i == 0 ? "<" : (i + 1 == homes.size() ? " or <" : ", <")) + std::string(homes[i]) + ">";
    }
    message += "; it belongs in " + where;
  }
  return message;
}

[[noreturn]] void fail_element(const Element& e, std::string_view parent) {
  // one tag can have several rules (<tendon> in <mujoco>, <default> and <equality>): the one
  // that names this child as refused wins, so the message says so
  const ElementRule* parent_rule = nullptr;
  for (const ElementRule& r : schema()) {
    if (r.tag != parent) continue;
    if (!parent_rule || has_word(r.unsupported_children, e.tag)) parent_rule = &r;
    if (has_word(r.unsupported_children, e.tag)) break;
  }
  if (parent_rule && has_word(parent_rule->unsupported_children, e.tag)) {
    fail(e.place(), "", "<" + e.tag + "> is valid MJCF but not supported by lever" + kDocs);
  }
  if (is_known_mjcf_element(e.tag)) fail(e.place(), "", misplaced(e.tag, parent));
  if (is_mujoco3_name(e.tag, "")) {
    fail(e.place(), "",
         "<" + e.tag +
             "> is MuJoCo 3's: MuJoCo 2.2.2, which lever follows, does not have it, and "
             "neither does lever" +
             kDocs);
  }
  std::vector<std::string_view> candidates = child_tags(parent);
  if (parent_rule) {
    for (const std::string_view w : words(parent_rule->unsupported_children)) {
      candidates.push_back(w);
    }
  }
  fail(e.place(), "",
       "unknown element <" + e.tag + "> in <" + std::string(parent) + ">" +
           did_you_mean(e.tag, candidates));
}

// whether `name` is an attribute of the same tag somewhere else (e.g. joint name outside default)
bool known_elsewhere(std::string_view tag, std::string_view name) {
  for (const ElementRule& r : schema()) {
    if (r.tag == tag && (find_attribute(r, name) || has_word(r.unsupported_attributes, name))) {
      return true;
    }
  }
  return false;
}

void check_attribute(const Element& e, const ElementRule& rule, const Attribute& a) {
  if (find_attribute(rule, a.name)) return;
  if (has_word(rule.unsupported_attributes, a.name)) {
    fail(e.place(a), a.name,
         "attribute '" + a.name + "' is valid MJCF but not supported by lever" + kDocs);
  }
  if (rule.attributes.empty() && rule.unsupported_attributes.empty()) {
    fail(e.place(a), a.name, "<" + e.tag + "> takes no attributes (found '" + a.name + "')");
  }
  if (known_elsewhere(e.tag, a.name)) {
    fail(e.place(a), a.name,
         "attribute '" + a.name + "' is not allowed on <" + e.tag + "> inside <" +
             std::string(rule.parent) + ">");
  }
  if (is_mujoco3_name(e.tag, a.name)) {
    fail(e.place(a), a.name,
         "attribute '" + a.name +
             "' is MuJoCo 3's: MuJoCo 2.2.2, which lever follows, does not "
             "have it, and neither does lever" +
             kDocs);
  }
  std::vector<std::string_view> candidates;
  for (const AttributeRule& r : rule.attributes) candidates.push_back(r.name);
  for (const std::string_view w : words(rule.unsupported_attributes)) candidates.push_back(w);
  fail(e.place(a), a.name, "unknown attribute '" + a.name + "'" + did_you_mean(a.name, candidates));
}

void check_required(const Element& e, const ElementRule& rule) {
  for (const AttributeRule& r : rule.attributes) {
    if (r.required && !e.find(r.name)) {
      fail(e.place(), r.name, "missing required attribute '" + std::string(r.name) + "'");
    }
  }
}

// How many elements of each limited kind the document has so far (see Limits).
struct Counts {
  int bodies = 0, joints = 0, geoms = 0, sites = 0, motors = 0, classes = 0;

  // count `e`, a child of `parent`; refuse it if it is one too many
  void add(const Element& e, std::string_view parent) {
    const bool in_body = parent == "body" || parent == "worldbody";
    if (e.tag == "body") bump(e, bodies, Limits::kBodies, "bodies");
    if (in_body && e.tag == "joint") bump(e, joints, Limits::kJoints, "joints");
    if (in_body && e.tag == "geom") bump(e, geoms, Limits::kGeoms, "geoms");
    if (in_body && e.tag == "site") bump(e, sites, Limits::kSites, "sites");
    if (parent == "actuator") bump(e, motors, Limits::kMotors, "motors");
    if (e.tag == "default") bump(e, classes, Limits::kClasses, "default classes");
  }

  static void bump(const Element& e, int& count, int limit, const char* what) {
    if (++count > limit) {
      fail(e.place(), "",
           "more than " + std::to_string(limit) + " " + what + ": lever accepts at most " +
               std::to_string(limit) + " (a limit that bounds memory and time, see " +
               "docs/reliability.md)");
    }
  }
};

void validate(const Element& e, const ElementRule& rule, Counts& counts) {
  for (const Attribute& a : e.attributes) check_attribute(e, rule, a);
  check_required(e, rule);
  std::map<std::string, int> first_line;
  for (const Element& child : e.children) {
    const ElementRule* child_rule = find_rule(e.tag, child.tag);
    if (!child_rule) fail_element(child, e.tag);
    counts.add(child, e.tag);
    const auto [it, first] = first_line.emplace(child.tag, child.line);
    if (!first && child_rule->multiplicity != '*') {
      fail(child.place(), "",
           "<" + e.tag + "> can have only one <" + child.tag + "> (the first is at line " +
               std::to_string(it->second) + ")");
    }
    validate(child, *child_rule, counts);
  }
}

void check_root(const Element& root) {
  if (root.tag == "robot") {
    fail(root.place(), "", "this is URDF (<robot>); lever reads MJCF (<mujoco>) only");
  }
  if (root.tag != "mujoco") {
    fail(root.place(), "",
         "the root element must be <mujoco>, not <" + root.tag + ">" +
             did_you_mean(root.tag, {"mujoco"}));
  }
}

}  // namespace

// Limits checked on the raw text, before the XML reader builds a tree of it.
void check_size(const std::string& xml) {
  if (xml.size() > Limits::kDocumentBytes) {
    fail(Place{}, "",
         "the document is " + std::to_string(xml.size()) + " bytes long; lever accepts at most " +
             std::to_string(Limits::kDocumentBytes) + " (a limit, see docs/reliability.md)");
  }
  int tags = 0, line = 1;
  for (const char c : xml) {
    if (c == '\n') ++line;
    if (c == '<' && ++tags > Limits::kTags) {
      fail(Place{"", "", line}, "",
           "more than " + std::to_string(Limits::kTags) +
               " tags: lever accepts at most that many (a limit, see docs/reliability.md)");
    }
  }
}

namespace {

// Each element's index in document order (pre-order, the root 0): the same numbering any XML
// library's walk over the same text gives, which is how write.cpp finds an element again.
int number_elements(Element& e, int next) {
  e.index = next++;
  for (Element& child : e.children) next = number_elements(child, next);
  return next;
}

}  // namespace

Element read_document(const std::string& xml, const std::string& filename,
                      std::vector<std::string>* included) {
  check_size(xml);
  Element root = read_xml(xml);
  check_root(root);
  const std::vector<std::string> files = expand_includes(root, filename, xml.size());
  if (included) *included = files;
  number_elements(root, 0);
  Counts counts;
  validate(root, *find_rule("", "mujoco"), counts);
  return root;
}

}  // namespace lever::mjcf::detail
