// <equality> read and compiled as MuJoCo 2.2.2 does (xml_native_reader.cc's OneEquality,
// user_objects.cc's mjCEquality); see equality.hpp. eq_data as the reader leaves it: every entry
// zero but entries 1 and 10, which start at 1 (polycoef's linear term and a weld's torquescale);
// a connect's anchor (body 1's frame) at 0-2; a weld's anchor (body 2's frame) at 0-2, zero when
// not written, its relpose at 3-9 (zero when not written: set_const then takes the pose at
// qpos0), torquescale at 10; a joint coupling's polycoef at 0-4. set_const completes the rest.
#include "equality.hpp"

#include <algorithm>
#include <string>

#include "schema.hpp"

namespace lever::mjcf::detail {

namespace {

// The numbers of attribute `name` of an equality element, as written or from its class, else the
// schema's built-in value.
std::vector<double> equality_numbers(const AttrSet& set, std::string_view tag,
                                     std::string_view name) {
  if (const Value* v = set.find(name)) return v->numbers;
  return default_numbers(attribute_rule("equality", tag, name));
}

std::string equality_word(const AttrSet& set, std::string_view tag, std::string_view name) {
  if (const Value* v = set.find(name)) return v->text;
  return std::string(attribute_rule("equality", tag, name).default_value);
}

EqualitySpec read_equality(const Element& e, const DefaultClasses& classes) {
  const int cls = classes.choose(e, "class", 0);
  AttrSet set = classes.at(cls).equality;
  set.apply(e, *find_rule("equality", e.tag));
  const std::string_view tag = e.tag;
  EqualitySpec q;
  q.at = e.place();
  q.type = tag == "weld"     ? EqualityType::kWeld
           : tag == "joint"  ? EqualityType::kJoint
           : tag == "tendon" ? EqualityType::kTendon
                             : EqualityType::kConnect;
  const bool joint = q.type == EqualityType::kJoint;
  const bool tendon = q.type == EqualityType::kTendon;
  const char* first = joint ? "joint1" : tendon ? "tendon1" : "body1";
  const char* second = joint ? "joint2" : tendon ? "tendon2" : "body2";
  q.name1 = equality_word(set, tag, first);
  q.name1_at = e.place(*e.find(first));  // required: the reader has checked it is there
  if (const Attribute* a = e.find(second)) {
    q.name2 = a->value;
    q.name2_at = e.place(*a);
  }
  q.active = equality_word(set, tag, "active") == "true";
  const std::vector<double> solref = equality_numbers(set, tag, "solref");
  const std::vector<double> solimp = equality_numbers(set, tag, "solimp");
  std::copy_n(solref.begin(), 2, q.solref.begin());
  std::copy_n(solimp.begin(), 5, q.solimp.begin());

  q.data.fill(0.0);
  q.data[1] = 1.0;
  q.data[10] = 1.0;
  const auto put = [&](std::string_view name, int at) {
    const std::vector<double> v = equality_numbers(set, tag, name);
    std::copy(v.begin(), v.end(), q.data.begin() + at);
  };
  if (q.type == EqualityType::kConnect) put("anchor", 0);
  if (q.type == EqualityType::kWeld) {
    put("anchor", 0);  // zero when not written
    put("relpose", 3);
    put("torquescale", 10);
  }
  if (joint || tendon) put("polycoef", 0);
  return q;
}

// The id of the object named `name` in `names`, or a Problem at `at`.
int find_object(const std::vector<std::string>& names, const std::string& name, const Place& at,
                const char* attribute, const char* kind) {
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end() || name.empty()) {
    std::vector<std::string_view> candidates(names.begin(), names.end());
    fail(at, attribute,
         "unknown " + std::string(kind) + " '" + name + "'" + did_you_mean(name, candidates));
  }
  return static_cast<int>(it - names.begin());
}

}  // namespace

std::vector<EqualitySpec> read_equalities(const Element& root, const DefaultClasses& classes) {
  std::vector<EqualitySpec> out;
  for (const Element& section : root.children) {
    if (section.tag != "equality") continue;
    for (const Element& e : section.children) out.push_back(read_equality(e, classes));
  }
  return out;
}

void assemble_equalities(const std::vector<EqualitySpec>& equalities, Model& m) {
  for (size_t i = 0; i < equalities.size(); ++i) {
    const EqualitySpec& q = equalities[i];
    const bool joint = q.type == EqualityType::kJoint;
    const bool tendon = q.type == EqualityType::kTendon;
    const std::vector<std::string>& names = joint ? m.jnt_name : tendon ? m.tendon_name : m.body_name;
    const char* kind = joint ? "joint" : tendon ? "tendon" : "body";
    const std::string first = std::string(kind) + "1", second = std::string(kind) + "2";
    const int id1 = find_object(names, q.name1, q.name1_at, first.c_str(), kind);
    // no second object: the world for a connect or weld, none for a coupling
    int id2 = joint || tendon ? -1 : 0;
    if (!q.name2.empty()) id2 = find_object(names, q.name2, q.name2_at, second.c_str(), kind);
    if (id1 == id2) {
      fail(q.at, second.c_str(), std::string(kind) + " '" + q.name1 + "' is constrained to itself");
    }
    for (const int j : {id1, id2}) {
      if (!joint || j < 0) continue;
      const JointType type = m.jnt_type[static_cast<size_t>(j)];
      if (type != JointType::kHinge && type != JointType::kSlide) {
        fail(j == id1 ? q.name1_at : q.name2_at, j == id1 ? "joint1" : "joint2",
             "joint '" + m.jnt_name[static_cast<size_t>(j)] +
                 "' is a ball or free joint; a joint coupling needs hinges or slides");
      }
    }
    m.eq_name[i] = q.at.name;
    m.eq_type[i] = q.type;
    m.eq_obj1id[i] = id1;
    m.eq_obj2id[i] = id2;
    m.eq_active[i] = q.active;
    m.eq_solref[i] = q.solref;
    m.eq_solimp[i] = q.solimp;
    m.eq_data[i] = q.data;
  }
}

}  // namespace lever::mjcf::detail
