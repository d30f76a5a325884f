// <tendon><fixed> and <spatial> read and compiled as MuJoCo 2.2.2 does (xml_native_reader.cc's
// OneTendon and its path children, user_objects.cc's mjCTendon and mjCWrap); see tendon.hpp. The
// path's objects become wrap_* rows: a joint (its id, coef), a site (its id, 0), a geom (its id,
// its side site's id or -1; wrap_type sphere or cylinder by the geom's type), a pulley (-1, its
// divisor). The tendon keeps its attributes as written over its class: range in length units
// (never converted from degrees), springlength -1 unless written (set_const then takes the length
// at qpos_spring).
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

TendonSpec read_tendon(const Element& e, const DefaultClasses& classes) {
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
  t.spatial = e.tag == "spatial";
  if (const Value* user = set.find("user")) t.user.numbers = user->numbers;
  const Attribute* user_written = e.find("user");
  t.user.at = user_written ? e.place(*user_written) : e.place();
  for (const Element& child : e.children) {
    AttrSet cs;
    cs.apply(child, *find_rule(e.tag, child.tag));
    TendonPathSpec obj;
    if (child.tag == "joint") {
      obj.type = WrapType::kJoint;
      obj.at = child.place(*child.find("joint"));  // required: the reader has checked it is there
      obj.name = cs.find("joint")->text;
      obj.prm = cs.find("coef")->numbers[0];  // required too
    } else if (child.tag == "site") {
      obj.type = WrapType::kSite;
      obj.at = child.place(*child.find("site"));
      obj.name = cs.find("site")->text;
    } else if (child.tag == "geom") {
      obj.type = WrapType::kSphere;  // a cylinder once the geom is found (assemble_tendons)
      obj.at = child.place(*child.find("geom"));
      obj.name = cs.find("geom")->text;
      if (const Attribute* side = child.find("sidesite")) {
        obj.sidesite = cs.find("sidesite")->text;
        obj.sidesite_at = child.place(*side);
      }
    } else {  // pulley
      obj.type = WrapType::kPulley;
      obj.at = child.place(*child.find("divisor"));
      obj.prm = cs.find("divisor")->numbers[0];
    }
    t.path.push_back(obj);
  }
  if (t.path.empty()) {
    fail(t.at, t.spatial ? "site" : "joint",
         t.spatial ? "a spatial tendon needs a path: at least two <site site=\"...\"/>"
                   : "a fixed tendon needs at least one <joint joint=\"...\" coef=\"...\"/>");
  }
  return t;
}

}  // namespace

std::vector<TendonSpec> read_tendons(const Element& root, const DefaultClasses& classes) {
  std::vector<TendonSpec> out;
  for (const Element& section : root.children) {
    if (section.tag != "tendon") continue;
    for (const Element& e : section.children) out.push_back(read_tendon(e, classes));
  }
  return out;
}

int wrap_count(const std::vector<TendonSpec>& tendons) {
  int n = 0;
  for (const TendonSpec& t : tendons) n += static_cast<int>(t.path.size());
  return n;
}

namespace {

// The id of the object named `name` among `names` (a joint's, site's or geom's), or a failure at
// `at` naming what is unknown, with the nearest names.
int find_named(const std::vector<std::string>& names, const std::string& name, const Place& at,
               const char* attribute, const char* kind) {
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end() || name.empty()) {
    std::vector<std::string_view> candidates(names.begin(), names.end());
    fail(at, attribute, std::string("unknown ") + kind + " '" + name + "'" + did_you_mean(name, candidates));
  }
  return static_cast<int>(it - names.begin());
}

// One object of the path as wrap_* holds it, its name found among the model's objects.
void assemble_path_object(const TendonPathSpec& obj, const Model& m, WrapType& type, int& id,
                          double& prm) {
  type = obj.type;
  prm = obj.prm;
  id = -1;
  switch (obj.type) {
    case WrapType::kJoint: {
      id = find_named(m.jnt_name, obj.name, obj.at, "joint", "joint");
      const JointType jt = m.jnt_type[static_cast<size_t>(id)];
      if (jt != JointType::kHinge && jt != JointType::kSlide) {
        fail(obj.at, "joint",
             "joint '" + obj.name + "' is a ball or free joint; a fixed tendon runs along hinges "
             "and slides");
      }
      break;
    }
    case WrapType::kSite: id = find_named(m.site_name, obj.name, obj.at, "site", "site"); break;
    case WrapType::kPulley:
      if (!(obj.prm > 0)) {
        // MuJoCo 2.2.2 takes a zero divisor and divides by it (an infinite length)
        fail(obj.at, "divisor", "a pulley's divisor must be positive; it is " + show(obj.prm));
      }
      break;
    default: {  // a geom
      id = find_named(m.geom_name, obj.name, obj.at, "geom", "geom");
      const GeomType gt = m.geom_type[static_cast<size_t>(id)];
      if (gt != GeomType::kSphere && gt != GeomType::kCylinder) {
        fail(obj.at, "geom",
             "geom '" + obj.name + "' is not a sphere or a cylinder: a tendon wraps around those only");
      }
      type = gt == GeomType::kCylinder ? WrapType::kCylinder : WrapType::kSphere;
      prm = obj.sidesite.empty()
                ? -1.0
                : find_named(m.site_name, obj.sidesite, obj.sidesite_at, "sidesite", "side site");
    }
  }
}

// MuJoCo's rules for a spatial path: every object placed where it can act.
void check_spatial_path(const TendonSpec& t) {
  const std::vector<TendonPathSpec>& path = t.path;
  const size_t n = path.size();
  if (n < 2) fail(t.at, "site", "a spatial tendon's path needs at least two objects");
  if (!(t.width > 0)) fail(t.at, "width", "a spatial tendon's width must be positive; it is " + show(t.width));
  auto type_at = [&](size_t i) { return path[i].type; };
  for (size_t i = 0; i < n; ++i) {
    const TendonPathSpec& obj = path[i];
    switch (obj.type) {
      case WrapType::kPulley:
        if (i > 0 && type_at(i - 1) == WrapType::kPulley) {
          fail(obj.at, "divisor", "two pulleys in a row: a pulley starts a branch, which needs sites");
        }
        if (i == n - 1) fail(obj.at, "divisor", "the path ends with a pulley; a branch needs sites after it");
        break;
      case WrapType::kSite: {
        const bool alone_before = i == 0 || type_at(i - 1) == WrapType::kPulley;
        const bool alone_after = i == n - 1 || type_at(i + 1) == WrapType::kPulley;
        if (alone_before && alone_after) {
          fail(obj.at, "site", "site '" + obj.name + "' has no neighbour in the path but pulleys: "
                               "a branch needs two sites");
        }
        if (i + 1 < n && type_at(i + 1) == WrapType::kSite && path[i + 1].name == obj.name) {
          fail(path[i + 1].at, "site", "site '" + obj.name + "' follows itself in the path");
        }
        break;
      }
      default:  // a geom
        if (i == 0 || i == n - 1 || type_at(i - 1) != WrapType::kSite ||
            type_at(i + 1) != WrapType::kSite) {
          fail(obj.at, "geom", "geom '" + obj.name + "' must come between two sites in the path");
        }
    }
  }
}

}  // namespace

void assemble_tendons(const std::vector<TendonSpec>& tendons, const std::vector<bool>& limited,
                      Model& m) {
  int w = 0;
  for (size_t i = 0; i < tendons.size(); ++i) {
    const TendonSpec& t = tendons[i];
    m.tendon_name[i] = t.at.name;
    m.tendon_adr[i] = w;
    m.tendon_num[i] = static_cast<int>(t.path.size());
    for (const TendonPathSpec& obj : t.path) {
      const size_t k = static_cast<size_t>(w);
      assemble_path_object(obj, m, m.wrap_type[k], m.wrap_objid[k], m.wrap_prm[k]);
      ++w;
    }
    if (t.spatial) check_spatial_path(t);
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
