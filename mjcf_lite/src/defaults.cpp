// Default classes and attribute inheritance; see defaults.hpp.
#include "defaults.hpp"

namespace lever::mjcf::detail {

namespace {

const char* const kOrientations[] = {"quat",  "axisangle", "xyaxes",
                                     "zaxis", "euler",     "fullinertia"};

// mujoco refuses two orientation forms written on one element (inherited ones do not count)
void check_one_orientation(const Element& e) {
  std::vector<std::string_view> found;
  for (const char* name : kOrientations) {
    if (e.find(name)) found.push_back(name);
  }
  if (found.size() > 1) {
    fail(e.place(*e.find(found[1])), found[1],
         "more than one orientation (" + quoted_list(found, "and") + "); give only one");
  }
}

// lever refuses values that 2.2.2 accepts but that cannot describe a real machine
void check_physical(const Element& e, const Attribute& a, const AttributeRule& r, const Value& v) {
  double sum_of_squares = 0;
  for (const double x : v.numbers) sum_of_squares += x * x;
  // only a quaternion read as numbers: a visual-only element (a camera) keeps its text
  if (a.name == "quat" && r.kind == ValueKind::kReal && sum_of_squares < 1e-14) {
    // mujoco 2.2.2 keeps such a quaternion unnormalized (a zero quat then means "world frame")
    fail(e.place(a), a.name, "quaternion '" + a.value + "' has (nearly) zero length");
  }
  // negative armature, damping or stiffness makes a joint gain energy from nothing (and
  // set_const() refuses them): say so where they are written
  // a negative servo gain pushes away from its target: MuJoCo 2.2.2 loads it, lever refuses it
  const bool must_not_be_negative =
      (a.name == "mass" || a.name == "density" || a.name == "diaginertia" || a.name == "armature" ||
       a.name == "damping" || a.name == "stiffness" || a.name == "kp" || a.name == "kv" ||
       a.name == "inheritrange");
  for (const double x : v.numbers) {
    if (must_not_be_negative && x < 0) {
      fail(e.place(a), a.name,
           "attribute '" + a.name + "' must not be negative (found " + show(x) + ")");
    }
  }
}

// valid MJCF values lever refuses with more to say than the schema's generic sentence
void check_refused_value(const Element& e, const Attribute& a) {
  if (e.tag == "geom" && a.name == "type" && a.value == "hfield") {
    fail(e.place(a), a.name,
         "type 'hfield' is valid MJCF but lever has no height fields: model the ground with a "
         "plane (type=\"plane\") and raised parts with boxes");
  }
}

}  // namespace

const Value* AttrSet::find(std::string_view name) const {
  const auto it = values_.find(name);
  return it == values_.end() ? nullptr : &it->second;
}

void AttrSet::apply(const Element& e, const ElementRule& rule) {
  check_one_orientation(e);
  for (const Attribute& a : e.attributes) {
    const AttributeRule* r = find_attribute(rule, a.name);
    if (!r) continue;  // the reader has already refused it
    check_refused_value(e, a);
    Value v = parse_value(e, a, *r);
    check_physical(e, a, *r, v);
    if (r->partial) {
      // the unwritten tail keeps the inherited numbers, or the built-in ones
      const Value* old = find(a.name);
      std::vector<double> full = old ? old->numbers : default_numbers(*r);
      for (size_t i = 0; i < v.numbers.size(); ++i) full[i] = v.numbers[i];
      v.numbers = full;
    }
    values_[a.name] = std::move(v);
  }
}

namespace {

bool is_actuator(std::string_view tag) {
  return tag == "motor" || tag == "general" || tag == "position" || tag == "velocity" ||
         tag == "muscle";
}

Value word_value(const char* w) { return Value{{}, w, 0}; }

// <muscle> in <general>'s terms (MuJoCo 2.2.2's reader): the parameters it starts from that are
// still <general>'s built-in values take the muscle's defaults, its own attributes set them, and
// the bias takes the gain's first nine numbers; dynamics, gain and bias are a muscle's
void apply_muscle(AttrSet& set) {
  const auto numbers = [&](const char* name) {
    const Value* v = set.find(name);
    return v ? v->numbers : default_numbers(attribute_rule("actuator", "general", name));
  };
  std::vector<double> dyn = numbers("dynprm"), gain = numbers("gainprm"), bias = numbers("biasprm");
  if (dyn[0] == 1) dyn[0] = 0.01;
  if (dyn[1] == 0) dyn[1] = 0.04;
  constexpr double kMuscleGain[9] = {0.75, 1.05, -1, 200, 0.5, 1.6, 1.5, 1.3, 1.2};
  if (gain[0] == 1) gain[0] = kMuscleGain[0];
  for (int k = 1; k < 9; ++k) {
    if (gain[static_cast<size_t>(k)] == 0) gain[static_cast<size_t>(k)] = kMuscleGain[k];
  }
  struct Own {
    const char* name;
    std::vector<double>* target;
    size_t first;
  };
  const Own own[] = {{"timeconst", &dyn, 0}, {"range", &gain, 0}, {"force", &gain, 2},
                     {"scale", &gain, 3},    {"lmin", &gain, 4},  {"lmax", &gain, 5},
                     {"vmax", &gain, 6},     {"fpmax", &gain, 7}, {"fvmax", &gain, 8}};
  for (const Own& o : own) {
    if (const Value* v = set.find(o.name)) {
      for (size_t k = 0; k < v->numbers.size(); ++k) (*o.target)[o.first + k] = v->numbers[k];
    }
    set.erase(o.name);  // held in dynprm and gainprm from here on, for later elements too
  }
  for (size_t k = 0; k < 9; ++k) bias[k] = gain[k];
  set.set("dynprm", Value{dyn, "", 0});
  set.set("gainprm", Value{gain, "", 0});
  set.set("biasprm", Value{bias, "", 0});
  set.set("dyntype", word_value("muscle"));
  set.set("gaintype", word_value("muscle"));
  set.set("biastype", word_value("muscle"));
}

}  // namespace

void apply_actuator(AttrSet& set, const Element& e, const ElementRule& rule) {
  set.apply(e, rule);
  const std::string_view tag = e.tag;
  if (tag == "general") return;
  if (tag == "muscle") {
    apply_muscle(set);
    return;
  }
  set.set("dyntype", word_value("none"));
  set.set("gaintype", word_value("fixed"));
  const auto numbers = [&](const char* name) {
    const Value* v = set.find(name);
    return v ? v->numbers : default_numbers(attribute_rule("actuator", "general", name));
  };
  std::vector<double> gain = numbers("gainprm");
  if (tag == "motor") {
    gain[0] = 1;
    set.set("gainprm", Value{gain, "", 0});
    set.set("biastype", word_value("none"));
    return;
  }
  // position and velocity servos
  const char* gain_name = tag == "position" ? "kp" : "kv";
  if (const Value* k = set.find(gain_name)) gain[0] = k->numbers[0];
  set.erase(gain_name);  // held as gainprm[0] from here on, for later elements of the class too
  std::vector<double> bias(kBiasParameters, 0.0);
  bias[tag == "position" ? 1 : 2] = -gain[0];
  if (tag == "position") {
    // MuJoCo 3's kv: biasprm[2] = -kv. 2.2.2 clears the bias of a <position> (and MuJoCo 3 keeps
    // the class's), so the class's kv is held under its own name to reach its elements
    if (const Value* kv = set.find("kv")) set.set(kPositionKv, *kv);
    set.erase("kv");
    if (const Value* kv = set.find(kPositionKv)) bias[2] = -kv->numbers[0];
    const Value* inherit = set.find("inheritrange");
    const Value* ctrlrange = set.find("ctrlrange");
    if (inherit && inherit->numbers[0] > 0 && ctrlrange &&
        (ctrlrange->numbers[0] != 0 || ctrlrange->numbers[1] != 0)) {
      const Attribute* written = e.find("inheritrange");
      fail(written ? e.place(*written) : e.place(), "inheritrange",
           "ctrlrange and inheritrange cannot both be defined (inheritrange sets ctrlrange from "
           "the joint's range)");
    }
  }
  set.set("gainprm", Value{gain, "", 0});
  set.set("biasprm", Value{bias, "", 0});
  set.set("biastype", word_value("affine"));
}

const AttrSet& DefaultClass::prototype(std::string_view tag) const {
  if (tag == "pair") return pair;
  if (tag == "equality") return equality;
  if (tag == "tendon") return tendon;
  if (tag == "joint") return joint;
  if (tag == "geom") return geom;
  if (tag == "site") return site;
  if (is_actuator(tag)) return actuator;
  return visual_only;
}

AttrSet& DefaultClass::prototype(std::string_view tag) {
  if (tag == "pair") return pair;
  if (tag == "equality") return equality;
  if (tag == "tendon") return tendon;
  if (tag == "joint") return joint;
  if (tag == "geom") return geom;
  if (tag == "site") return site;
  if (is_actuator(tag)) return actuator;
  return visual_only;
}

DefaultClasses::DefaultClasses() {
  DefaultClass main;
  main.name = "main";
  classes_.push_back(std::move(main));
}

int DefaultClasses::find(std::string_view name) const {
  for (size_t i = 0; i < classes_.size(); ++i) {
    if (classes_[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

void DefaultClasses::read_section(const Element& section) {
  // a top-level <default> re-enters (and renames) the top-level class, as in mujoco 2.2.2
  const Attribute* name = section.find("class");
  const std::string new_name = name ? name->value : "main";
  const int other = find(new_name);
  if (other > 0) {
    // mujoco would silently keep two classes of that name and use the first
    fail(section.place(), "class", "default class '" + new_name + "' is defined twice");
  }
  classes_[0].name = new_name;
  read(section, 0);
}

void DefaultClasses::read(const Element& section, int id) {
  // the class's own element defaults first, whatever their position among nested classes
  for (const Element& child : section.children) {
    if (child.tag == "default") continue;
    AttrSet& prototype = classes_[static_cast<size_t>(id)].prototype(child.tag);
    if (is_actuator(child.tag)) {
      apply_actuator(prototype, child, *find_rule("default", child.tag));
    } else {
      prototype.apply(child, *find_rule("default", child.tag));
    }
  }
  for (const Element& child : section.children) {
    if (child.tag != "default") continue;
    const std::string name = child.find("class")->value;
    if (name.empty()) fail(child.place(), "class", "a nested default class needs a name");
    if (find(name) >= 0) {
      fail(child.place(), "class", "default class '" + name + "' is defined twice");
    }
    DefaultClass copy = classes_[static_cast<size_t>(id)];
    copy.name = name;
    classes_.push_back(std::move(copy));
    read(child, static_cast<int>(classes_.size()) - 1);
  }
}

int DefaultClasses::choose(const Element& e, std::string_view attribute, int fallback) const {
  const Attribute* a = e.find(attribute);
  if (!a) return fallback;
  const int id = find(a->value);
  if (id < 0) {
    std::vector<std::string_view> names;
    for (const DefaultClass& c : classes_) names.push_back(c.name);
    fail(e.place(*a), attribute,
         "unknown default class '" + a->value + "'" + did_you_mean(a->value, names));
  }
  return id;
}

}  // namespace lever::mjcf::detail
