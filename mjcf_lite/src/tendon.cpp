// <tendon><fixed> read and compiled as MuJoCo 2.2.2 does (xml_native_reader.cc's OneTendon and
// its <joint joint coef> children, user_objects.cc's mjCTendon and mjCWrap); see tendon.hpp. The
// path's joints become wrap_* rows (type joint, the joint's id, coef); the tendon keeps its
// attributes as written over its class: range in length units (never converted from degrees),
// springlength -1 unless written (set_const then takes the length at qpos_spring).
#include "tendon.hpp"

#include <algorithm>
#include <string>

#include "schema.hpp"

namespace lever::mjcf::detail {

namespace {

std::vector<double> tendon_numbers(const AttrSet& set, std::string_view name) {
  if (const Value* v = set.find(name)) return v->numbers;
  return default_numbers(attribute_rule("tendon", "fixed", name));
}

template <size_t N>
std::array<double, N> tendon_array(const AttrSet& set, std::string_view name) {
  const std::vector<double> v = tendon_numbers(set, name);
  std::array<double, N> out{};
  std::copy_n(v.begin(), std::min(N, v.size()), out.begin());
  return out;
}

double tendon_real(const AttrSet& set, std::string_view name) {
  return tendon_array<1>(set, name)[0];
}

TendonSpec read_fixed(const Element& e, const DefaultClasses& classes) {
  const int cls = classes.choose(e, "class", 0);
  AttrSet set = classes.at(cls).tendon;
  set.apply(e, *find_rule("tendon", e.tag));
  TendonSpec t;
  t.at = e.place();
  const Value* limited = set.find("limited");
  const std::string word =
      limited ? limited->text : std::string(attribute_rule("tendon", "fixed", "limited").default_value);
  t.limited = word == "true" ? Limited::kTrue : word == "false" ? Limited::kFalse : Limited::kAuto;
  t.range = tendon_array<2>(set, "range");
  t.solref_limit = tendon_array<2>(set, "solreflimit");
  t.solimp_limit = tendon_array<5>(set, "solimplimit");
  t.solref_friction = tendon_array<2>(set, "solreffriction");
  t.solimp_friction = tendon_array<5>(set, "solimpfriction");
  t.margin = tendon_real(set, "margin");
  t.stiffness = tendon_real(set, "stiffness");
  t.damping = tendon_real(set, "damping");
  t.frictionloss = tendon_real(set, "frictionloss");
  t.springlength = tendon_real(set, "springlength");
  t.width = tendon_real(set, "width");
  for (const Element& j : e.children) {
    AttrSet js;
    js.apply(j, *find_rule("fixed", j.tag));
    TendonJointSpec joint;
    joint.at = j.place(*j.find("joint"));  // required: the reader has checked it is there
    joint.name = js.find("joint")->text;
    joint.coef = js.find("coef")->numbers[0];  // required too
    t.joints.push_back(joint);
  }
  if (t.joints.empty()) {
    fail(t.at, "joint", "a fixed tendon needs at least one <joint joint=\"...\" coef=\"...\"/>");
  }
  return t;
}

}  // namespace

std::vector<TendonSpec> read_tendons(const Element& root, const DefaultClasses& classes) {
  std::vector<TendonSpec> out;
  for (const Element& section : root.children) {
    if (section.tag != "tendon") continue;
    for (const Element& e : section.children) out.push_back(read_fixed(e, classes));
  }
  return out;
}

int wrap_count(const std::vector<TendonSpec>& tendons) {
  int n = 0;
  for (const TendonSpec& t : tendons) n += static_cast<int>(t.joints.size());
  return n;
}

void assemble_tendons(const std::vector<TendonSpec>& tendons, const std::vector<bool>& limited,
                      Model& m) {
  int w = 0;
  for (size_t i = 0; i < tendons.size(); ++i) {
    const TendonSpec& t = tendons[i];
    m.tendon_name[i] = t.at.name;
    m.tendon_adr[i] = w;
    m.tendon_num[i] = static_cast<int>(t.joints.size());
    for (const TendonJointSpec& j : t.joints) {
      const auto it = std::find(m.jnt_name.begin(), m.jnt_name.end(), j.name);
      if (it == m.jnt_name.end() || j.name.empty()) {
        std::vector<std::string_view> candidates(m.jnt_name.begin(), m.jnt_name.end());
        fail(j.at, "joint", "unknown joint '" + j.name + "'" + did_you_mean(j.name, candidates));
      }
      const int id = static_cast<int>(it - m.jnt_name.begin());
      const JointType type = m.jnt_type[static_cast<size_t>(id)];
      if (type != JointType::kHinge && type != JointType::kSlide) {
        fail(j.at, "joint",
             "joint '" + j.name + "' is a ball or free joint; a fixed tendon runs along hinges "
             "and slides");
      }
      m.wrap_type[static_cast<size_t>(w)] = WrapType::kJoint;
      m.wrap_objid[static_cast<size_t>(w)] = id;
      m.wrap_prm[static_cast<size_t>(w)] = j.coef;
      ++w;
    }
    if (limited[i] && !(t.range[0] < t.range[1])) {
      fail(t.at, "range",
           "with limited the range needs lower < upper; it is \"" + show(t.range[0]) + " " +
               show(t.range[1]) + "\"");
    }
    m.tendon_limited[i] = limited[i];
    m.tendon_range[i] = t.range;
    m.tendon_solref_lim[i] = t.solref_limit;
    m.tendon_solimp_lim[i] = t.solimp_limit;
    m.tendon_solref_fri[i] = t.solref_friction;
    m.tendon_solimp_fri[i] = t.solimp_friction;
    m.tendon_margin[i] = t.margin;
    m.tendon_stiffness[i] = t.stiffness;
    m.tendon_damping[i] = t.damping;
    m.tendon_frictionloss[i] = t.frictionloss;
    m.tendon_lengthspring[i] = t.springlength;
    m.tendon_width[i] = t.width;
  }
}

}  // namespace lever::mjcf::detail
