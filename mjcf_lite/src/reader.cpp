// XML -> element tree (tinyxml2), then structural validation against the schema table.
#include "reader.hpp"

#include <tinyxml2.h>

#include <map>
#include <string>

#include "schema.hpp"

namespace lever::mjcf::detail {

const Attribute* Element::find(std::string_view name) const {
  for (const Attribute& a : attributes) {
    if (a.name == name) return &a;
  }
  return nullptr;
}

Place Element::place() const {
  const Attribute* n = find("name");
  return Place{tag, n ? n->value : "", line};
}

Place Element::place(const Attribute& a) const {
  Place p = place();
  if (a.line > 0) p.line = a.line;
  return p;
}

namespace {

// ---- tinyxml2 -> Element -------------------------------------------------------------------

std::string describe_xml_error(tinyxml2::XMLError id) {
  switch (id) {
    case tinyxml2::XML_ERROR_EMPTY_DOCUMENT: return "the document is empty";
    case tinyxml2::XML_ERROR_MISMATCHED_ELEMENT:
      return "a closing tag does not match its opening tag (an element left open?)";
    case tinyxml2::XML_ERROR_PARSING_ATTRIBUTE:
      return "cannot read an attribute (repeated, or its value not in quotes?)";
    case tinyxml2::XML_ERROR_PARSING_TEXT: return "cannot read text (is this an XML file?)";
    case tinyxml2::XML_ERROR_PARSING_ELEMENT: return "cannot read an element";
    case tinyxml2::XML_ERROR_PARSING_COMMENT: return "cannot read a comment";
    case tinyxml2::XML_ELEMENT_DEPTH_EXCEEDED:
      return "elements are nested more than " + std::to_string(kMaxDepth) + " levels deep";
    default: return "cannot parse the XML";
  }
}

[[noreturn]] void fail_xml(const tinyxml2::XMLDocument& doc) {
  std::string detail = doc.ErrorStr();
  const size_t colon = detail.find(": ", detail.find("Line number="));
  std::string message = "malformed XML: " + describe_xml_error(doc.ErrorID());
  if (colon != std::string::npos) message += " [" + detail.substr(colon + 2) + "]";
  fail(Place{"", "", doc.ErrorLineNum()}, "", message);
}

bool is_blank(const char* s) {
  for (; s && *s; ++s) {
    if (*s != ' ' && *s != '\t' && *s != '\n' && *s != '\r') return false;
  }
  return true;
}

Element convert(const tinyxml2::XMLElement& x, int depth) {
  Element e;
  e.tag = x.Value();
  e.line = x.GetLineNum();
  if (depth > kMaxDepth) {
    fail(e.place(), "",
         "elements are nested more than " + std::to_string(kMaxDepth) + " levels deep");
  }
  for (const tinyxml2::XMLAttribute* a = x.FirstAttribute(); a; a = a->Next()) {
    e.attributes.push_back({a->Name(), a->Value(), a->GetLineNum()});
    const Attribute& added = e.attributes.back();
    if (added.value.size() > Limits::kAttributeBytes) {
      fail(e.place(added), added.name,
           "attribute '" + added.name + "' is " + std::to_string(added.value.size()) +
               " bytes long; lever accepts at most " + std::to_string(Limits::kAttributeBytes) +
               " (a limit, see docs/reliability.md)");
    }
  }
  for (const tinyxml2::XMLNode* n = x.FirstChild(); n; n = n->NextSibling()) {
    if (const tinyxml2::XMLElement* child = n->ToElement()) {
      e.children.push_back(convert(*child, depth + 1));
    } else if (n->ToText() && !is_blank(n->Value())) {
      // MJCF carries everything in attributes; text would be silently dropped
      fail(e.place(), "",
           "unexpected text inside <" + e.tag +
               ">: MJCF elements take attributes "
               "only");
    }
  }
  return e;
}

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
  const ElementRule* parent_rule = nullptr;
  for (const ElementRule& r : schema()) {
    if (r.tag == parent) parent_rule = &r;
  }
  if (parent_rule && has_word(parent_rule->unsupported_children, e.tag)) {
    fail(e.place(), "", "<" + e.tag + "> is valid MJCF but not supported by lever" + kDocs);
  }
  if (is_known_mjcf_element(e.tag)) fail(e.place(), "", misplaced(e.tag, parent));
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

// Limits checked on the raw text, before tinyxml2 builds a tree of it.
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

}  // namespace

Element read_document(const std::string& xml) {
  check_size(xml);
  tinyxml2::XMLDocument doc;
  if (doc.Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS) fail_xml(doc);
  const tinyxml2::XMLElement* first = doc.RootElement();
  if (!first) fail(Place{}, "", "malformed XML: the document has no element");
  if (const tinyxml2::XMLElement* second = first->NextSiblingElement()) {
    fail(Place{second->Value(), "", second->GetLineNum()}, "",
         "a document has one root element; this one is a second");
  }
  Element root = convert(*first, 1);
  check_root(root);
  Counts counts;
  validate(root, *find_rule("", "mujoco"), counts);
  return root;
}

}  // namespace lever::mjcf::detail
