// Element tree -> ModelSpec; see parse.hpp. Follows mujoco 2.2.2's xml_native_reader.cc: sections
// are read in a fixed order (so <compiler> applies to the whole model wherever it is written), a
// joint, geom or site takes its class from its own `class` or else from the nearest enclosing
// `childclass`, a motor from its own `class` or else the top-level class.
#include "parse.hpp"

#include <algorithm>

#include "composite.hpp"
#include "defaults.hpp"
#include "equality.hpp"
#include "tendon.hpp"
#include "schema.hpp"

namespace lever::mjcf::detail {

namespace {

// typed reads of an attribute set; what was neither written nor inherited comes from the schema
class Fields {
 public:
  Fields(const AttrSet& set, std::string_view parent, std::string_view tag)
      : set_(set), parent_(parent), tag_(tag) {}

  bool has(std::string_view name) const { return set_.has(name); }

  std::vector<double> numbers(std::string_view name) const {
    if (const Value* v = set_.find(name)) return v->numbers;
    return default_numbers(attribute_rule(parent_, tag_, name));
  }

  template <size_t N>
  std::array<double, N> array(std::string_view name) const {
    const std::vector<double> v = numbers(name);
    std::array<double, N> out{};
    std::copy_n(v.begin(), std::min(N, v.size()), out.begin());
    return out;
  }

  template <size_t N>
  std::optional<std::array<double, N>> maybe(std::string_view name) const {
    if (!has(name)) return std::nullopt;
    return array<N>(name);
  }

  double real(std::string_view name) const { return array<1>(name)[0]; }
  int integer(std::string_view name) const { return static_cast<int>(real(name)); }

  std::string word(std::string_view name) const {
    if (const Value* v = set_.find(name)) return v->text;
    return std::string(attribute_rule(parent_, tag_, name).default_value);
  }

  Limited limited(std::string_view name) const {
    const std::string w = word(name);
    return w == "true" ? Limited::kTrue : (w == "false" ? Limited::kFalse : Limited::kAuto);
  }

  // the `user` list (empty if neither written nor inherited), located at the element
  UserData user(const Element& e) const {
    UserData u;
    if (const Value* v = set_.find("user")) u.numbers = v->numbers;
    const Attribute* written = e.find("user");
    u.at = written ? e.place(*written) : e.place();
    return u;
  }

  Orientation orientation() const {
    Orientation o;
    o.quat = array<4>("quat");
    o.axisangle = maybe<4>("axisangle");
    o.xyaxes = maybe<6>("xyaxes");
    o.zaxis = maybe<3>("zaxis");
    o.euler = maybe<3>("euler");
    o.fullinertia = maybe<6>("fullinertia");
    return o;
  }

 private:
  const AttrSet& set_;
  std::string_view parent_, tag_;
};

// the attributes an element writes, over a copy of its class prototype (or over nothing)
AttrSet resolve(const Element& e, std::string_view parent, const AttrSet& prototype = {}) {
  AttrSet set = prototype;
  set.apply(e, *find_rule(parent, e.tag));
  return set;
}

GeomType geom_type(const std::string& w) {
  if (w == "plane") return GeomType::kPlane;
  if (w == "capsule") return GeomType::kCapsule;
  if (w == "ellipsoid") return GeomType::kEllipsoid;
  if (w == "cylinder") return GeomType::kCylinder;
  if (w == "box") return GeomType::kBox;
  if (w == "mesh") return GeomType::kMesh;
  return GeomType::kSphere;
}

}  // namespace

// ---- one element each ------------------------------------------------------------------------

JointSpec read_joint(const Element& e, const AttrSet& set) {
  const Fields f(set, "body", "joint");
  JointSpec j;
  j.at = e.place();
  const std::string type = f.word("type");
  j.type = type == "slide"  ? JointType::kSlide
           : type == "ball" ? JointType::kBall
           : type == "free" ? JointType::kFree
                            : JointType::kHinge;
  j.pos = f.array<3>("pos");
  j.axis = f.array<3>("axis");
  j.range = f.array<2>("range");
  j.limited = f.limited("limited");
  j.damping = f.real("damping");
  j.stiffness = f.real("stiffness");
  j.springref = f.real("springref");
  j.armature = f.real("armature");
  j.ref = f.real("ref");
  j.margin = f.real("margin");
  j.solref = f.array<2>("solreflimit");
  j.solimp = f.array<5>("solimplimit");
  j.frictionloss = f.real("frictionloss");
  j.solref_friction = f.array<2>("solreffriction");
  j.solimp_friction = f.array<5>("solimpfriction");
  j.user = f.user(e);
  return j;
}

GeomSpec read_geom(const Element& e, const AttrSet& set) {
  const Fields f(set, "body", "geom");
  GeomSpec g;
  g.at = e.place();
  g.type = geom_type(f.word("type"));
  g.size = f.array<3>("size");
  g.fromto = f.maybe<6>("fromto");
  g.pos = f.array<3>("pos");
  g.orientation = f.orientation();
  g.density = f.real("density");
  g.shellinertia = f.word("shellinertia") == "true";
  if (f.has("mass")) g.mass = f.real("mass");
  g.group = f.integer("group");
  g.contype = f.integer("contype");
  g.conaffinity = f.integer("conaffinity");
  g.rgba = f.array<4>("rgba");
  g.condim = f.integer("condim");
  g.priority = f.integer("priority");
  g.solmix = f.real("solmix");
  g.margin = f.real("margin");
  g.gap = f.real("gap");
  g.friction = f.array<3>("friction");
  g.solref = f.array<2>("solref");
  g.solimp = f.array<5>("solimp");
  g.mesh = f.word("mesh");
  g.material = f.word("material");
  g.user = f.user(e);
  return g;
}

SiteSpec read_site(const Element& e, const AttrSet& set) {
  const Fields f(set, "body", "site");
  SiteSpec s;
  s.at = e.place();
  s.pos = f.array<3>("pos");
  s.orientation = f.orientation();
  s.size = f.array<3>("size");
  s.type = geom_type(f.word("type"));
  s.user = f.user(e);
  return s;
}

namespace {

InertialSpec read_inertial(const Element& e) {
  const AttrSet set = resolve(e, "body");
  const Fields f(set, "body", "inertial");
  InertialSpec i;
  i.at = e.place();
  i.pos = f.array<3>("pos");
  i.mass = f.real("mass");
  i.diaginertia = f.array<3>("diaginertia");
  i.orientation = f.orientation();
  return i;
}

MotorSpec read_actuator(const Element& e, const DefaultClasses& classes) {
  // childclass never reaches actuators: one without class uses the top-level class
  const int cls = classes.choose(e, "class", 0);
  AttrSet set = classes.at(cls).actuator;
  apply_actuator(set, e, *find_rule("actuator", e.tag));
  // every kind is read in <general>'s terms (apply_actuator filled in what a shortcut implies)
  const Fields f(set, "actuator", "general");
  MotorSpec m;
  m.at = e.place();
  m.joint = f.word("joint");
  m.tendon = f.word("tendon");
  m.jointinparent = f.word("jointinparent");
  m.site = f.word("site");
  m.refsite = f.word("refsite");
  m.cranksite = f.word("cranksite");
  m.slidersite = f.word("slidersite");
  m.body = f.word("body");
  m.cranklength = f.real("cranklength");
  m.lengthrange = f.array<2>("lengthrange");
  m.crank_attributes_written = e.find("cranklength") || e.find("slidersite");
  const std::string dyn = f.word("dyntype"), gain = f.word("gaintype"), bias = f.word("biastype");
  m.dyntype = dyn == "integrator" ? DynType::kIntegrator
              : dyn == "filter"   ? DynType::kFilter
              : dyn == "muscle"   ? DynType::kMuscle
              : dyn == "user"     ? DynType::kUser
                                  : DynType::kNone;
  m.gaintype = gain == "affine"   ? GainType::kAffine
               : gain == "muscle" ? GainType::kMuscle
               : gain == "user"   ? GainType::kUser
                                  : GainType::kFixed;
  m.biastype = bias == "affine"   ? BiasType::kAffine
               : bias == "muscle" ? BiasType::kMuscle
               : bias == "user"   ? BiasType::kUser
                                  : BiasType::kNone;
  m.dynprm = f.array<kDynParameters>("dynprm");
  m.actrange = f.array<2>("actrange");
  m.actlimited = f.limited("actlimited");
  m.gainprm = f.array<kGainParameters>("gainprm");
  m.biasprm = f.array<kBiasParameters>("biasprm");
  m.gear = f.array<6>("gear");
  m.ctrlrange = f.array<2>("ctrlrange");
  m.forcerange = f.array<2>("forcerange");
  m.ctrllimited = f.limited("ctrllimited");
  m.inheritrange = f.real("inheritrange");
  m.forcelimited = f.limited("forcelimited");
  m.user = f.user(e);
  return m;
}

// ---- the body tree -------------------------------------------------------------------------

struct TreeReader {
  const DefaultClasses& classes;
  bool ignore_inertials;
  AssetSpec& assets;
  CompositeOutput& generated;  ///< what composites add outside the body tree

  // the children of a <body> or <worldbody>; `active` is the class childclass selected
  void read_contents(const Element& e, int active, BodySpec& body) const {
    for (const Element& child : e.children) {
      if (child.tag == "inertial") {
        // read (and so checked) even when it is to be ignored
        InertialSpec inertial = read_inertial(child);
        if (!ignore_inertials) body.inertial = std::move(inertial);
      } else if (child.tag == "body") {
        body.children.push_back(read_body(child, active));
      } else if (child.tag == "freejoint") {
        // MuJoCo gives a <freejoint> no default class: its name and group, the rest built in
        JointSpec joint = read_joint(child, resolve(child, e.tag));
        joint.type = JointType::kFree;
        body.joints.push_back(joint);
      } else if (child.tag == "composite") {
        expand_composite(child, body, classes.at(0), assets, generated);
      } else {
        const int cls = classes.choose(child, "class", active);
        const AttrSet set = resolve(child, e.tag, classes.at(cls).prototype(child.tag));
        if (child.tag == "joint") body.joints.push_back(read_joint(child, set));
        if (child.tag == "geom") body.geoms.push_back(read_geom(child, set));
        if (child.tag == "site") body.sites.push_back(read_site(child, set));
        if (child.tag == "light") assets.lights.push_back(child.place().name);
        if (child.tag == "camera") assets.cameras.push_back(child.place().name);
      }
    }
  }

  BodySpec read_body(const Element& e, int parent_active) const {
    const int active = classes.choose(e, "childclass", parent_active);
    const AttrSet set = resolve(e, "body");
    const Fields f(set, "body", "body");
    BodySpec b;
    b.at = e.place();
    b.pos = f.array<3>("pos");
    b.orientation = f.orientation();
    b.mocap = f.word("mocap") == "true";
    b.user = f.user(e);
    read_contents(e, active, b);
    return b;
  }
};

// ---- sections ------------------------------------------------------------------------------

std::vector<const Element*> sections(const Element& root, std::string_view tag) {
  std::vector<const Element*> out;
  for (const Element& child : root.children) {
    if (child.tag == tag) out.push_back(&child);
  }
  return out;
}

CompilerSpec read_compiler(const Element& root) {
  // every <compiler> is applied in order over the same settings
  AttrSet set;
  for (const Element* e : sections(root, "compiler"))
    set.apply(*e, *find_rule("mujoco", "compiler"));
  const Fields f(set, "mujoco", "compiler");
  CompilerSpec c;
  c.degree = f.word("angle") == "degree";
  c.autolimits = f.word("autolimits") == "true";
  const std::string ifg = f.word("inertiafromgeom");
  c.inertiafromgeom = ifg == "true"
                          ? InertiaFromGeom::kTrue
                          : (ifg == "false" ? InertiaFromGeom::kFalse : InertiaFromGeom::kAuto);
  const std::array<double, 2> groups = f.array<2>("inertiagrouprange");
  c.inertiagrouprange = {static_cast<int>(groups[0]), static_cast<int>(groups[1])};
  c.eulerseq = f.word("eulerseq");
  c.boundmass = f.real("boundmass");
  c.boundinertia = f.real("boundinertia");
  c.balanceinertia = f.word("balanceinertia") == "true";
  c.settotalmass = f.real("settotalmass");
  c.meshdir = f.word("meshdir");
  c.texturedir = f.word("texturedir");
  c.exactmeshinertia = f.word("exactmeshinertia") == "true";
  c.convexhull = f.word("convexhull") == "true";
  // <compiler><lengthrange>: every one over the same settings, as the <compiler>s
  AttrSet lr;
  for (const Element* e : sections(root, "compiler")) {
    for (const Element& child : e->children) {
      if (child.tag == "lengthrange") lr.apply(child, *find_rule("compiler", "lengthrange"));
    }
  }
  const Fields l(lr, "compiler", "lengthrange");
  const std::string mode = l.word("mode");
  c.lengthrange.mode = mode == "none"         ? LengthRangeMode::kNone
                       : mode == "muscleuser" ? LengthRangeMode::kMuscleUser
                       : mode == "all"        ? LengthRangeMode::kAll
                                              : LengthRangeMode::kMuscle;
  c.lengthrange.useexisting = l.word("useexisting") == "true";
  c.lengthrange.uselimit = l.word("uselimit") == "true";
  c.lengthrange.accel = l.real("accel");
  c.lengthrange.maxforce = l.real("maxforce");
  c.lengthrange.timeconst = l.real("timeconst");
  c.lengthrange.timestep = l.real("timestep");
  c.lengthrange.inttotal = l.real("inttotal");
  c.lengthrange.inteval = l.real("inteval");
  c.lengthrange.tolrange = l.real("tolrange");
  return c;
}

// valid <option> values lever refuses, with what it has instead
void check_option_support(const Element& option) {
  if (const Attribute* noslip = option.find("noslip_iterations")) {
    const Value v =
        parse_value(option, *noslip, attribute_rule("mujoco", "option", "noslip_iterations"));
    if (v.numbers[0] != 0) {
      fail(option.place(*noslip), "noslip_iterations",
           "lever has no noslip solver (MuJoCo's post-processing of friction forces): "
           "noslip_iterations must be 0 (found " +
               noslip->value + ")");
    }
  }
}

// <option> numbers lever refuses although MuJoCo 2.2.2 reads them
void check_option_values(const Element& option, const AttrSet& set) {
  const auto refuse = [&](const char* name, bool bad, const std::string& rule) {
    const Attribute* a = option.find(name);
    if (a && bad)
      fail(option.place(*a), name, std::string(name) + " " + rule + " (found " + a->value + ")");
  };
  refuse("impratio", !(set.find("impratio") && set.find("impratio")->numbers[0] > 0),
         "must be positive: it divides the normal impedance");
  refuse("iterations", set.find("iterations") && set.find("iterations")->numbers[0] < 0,
         "must not be negative");
  refuse("tolerance", set.find("tolerance") && set.find("tolerance")->numbers[0] < 0,
         "must not be negative");
  refuse("mpr_tolerance", set.find("mpr_tolerance") && set.find("mpr_tolerance")->numbers[0] < 0,
         "must not be negative");
  refuse("mpr_iterations",
         set.find("mpr_iterations") && set.find("mpr_iterations")->numbers[0] < 0,
         "must not be negative");
  // MuJoCo 2.2.2 takes them as written: a negative one would drive the bodies, not drag them
  refuse("viscosity", set.find("viscosity") && set.find("viscosity")->numbers[0] < 0,
         "must not be negative");
  refuse("density", set.find("density") && set.find("density")->numbers[0] < 0,
         "must not be negative");
}

Options read_option(const Element& root) {
  AttrSet set, flags;
  for (const Element* e : sections(root, "option")) {
    check_option_support(*e);
    set.apply(*e, *find_rule("mujoco", "option"));
    check_option_values(*e, set);
    for (const Element& flag : e->children) flags.apply(flag, *find_rule("option", "flag"));
    const Attribute* timestep = e->find("timestep");
    if (timestep && !(set.find("timestep")->numbers[0] > 0)) {
      // mujoco 2.2.2 loads any timestep, and the first step then misbehaves
      fail(e->place(), "timestep", "timestep must be positive (found " + timestep->value + ")");
    }
  }
  const Fields f(set, "mujoco", "option");
  Options o;
  o.timestep = f.real("timestep");
  const Vec3 g = f.array<3>("gravity");
  o.gravity = Eigen::Vector3d(g[0], g[1], g[2]);
  const std::string integrator = f.word("integrator");
  o.integrator = integrator == "RK4"        ? Integrator::kRK4
                 : integrator == "implicit" ? Integrator::kImplicit
                 : integrator == "implicitfast" ? Integrator::kImplicitFast
                                            : Integrator::kEuler;
  // contact; the solver
  o.cone = f.word("cone") == "elliptic" ? Cone::kElliptic : Cone::kPyramidal;
  const std::string solver = f.word("solver");
  o.solver = solver == "PGS" ? Solver::kPGS : solver == "CG" ? Solver::kCG : Solver::kNewton;
  o.impratio = f.real("impratio");
  o.iterations = f.integer("iterations");
  o.tolerance = f.real("tolerance");
  const std::string jacobian = f.word("jacobian");
  o.jacobian = jacobian == "dense"    ? JacobianLayout::kDense
               : jacobian == "sparse" ? JacobianLayout::kSparse
                                      : JacobianLayout::kAuto;
  const Fields flag(flags, "option", "flag");
  for (int k = 0; k < kDisableBits; ++k) {
    if (flag.word(kDisableNames[k]) == "disable") o.disableflags |= 1 << k;
  }
  for (int k = 0; k < kEnableBits; ++k) {
    if (flag.word(kEnableNames[k]) == "enable") o.enableflags |= 1 << k;
  }
  o.o_margin = f.real("o_margin");
  o.o_solref = f.array<2>("o_solref");
  o.o_solimp = f.array<5>("o_solimp");
  o.mpr_tolerance = f.real("mpr_tolerance");
  o.mpr_iterations = f.integer("mpr_iterations");
  const Vec3 magnetic = f.array<3>("magnetic");
  o.magnetic = Eigen::Vector3d(magnetic[0], magnetic[1], magnetic[2]);
  o.viscosity = f.real("viscosity");
  o.density = f.real("density");
  const Vec3 wind = f.array<3>("wind");
  o.wind = Eigen::Vector3d(wind[0], wind[1], wind[2]);
  return o;
}

// <size>: nconmax and njmax (-1: MuJoCo's defaults, filled in by the compiler)
void read_size(const Element& root, ModelSpec& spec) {
  AttrSet set;
  for (const Element* e : sections(root, "size")) {
    set.apply(*e, *find_rule("mujoco", "size"));
    for (int k = 0; k < kUserKinds; ++k) {
      const char* name = user_size_attribute(static_cast<UserKind>(k));
      if (const Attribute* a = e->find(name)) {
        if (set.find(name)->numbers[0] < -1) {
          fail(e->place(*a), name,
               std::string(name) + " must be -1 (the longest list of the kind) or a count >= 0 "
               "(found " + a->value + ")");
        }
        spec.nuser.at[static_cast<size_t>(k)] = e->place(*a);
      }
    }
    for (const char* name : {"nconmax", "njmax"}) {
      const Attribute* a = e->find(name);
      if (a && set.find(name)->numbers[0] < -1) {
        fail(e->place(*a), name,
             std::string(name) + " must be -1 (MuJoCo's default) or a count >= 0 (found " +
                 a->value + ")");
      }
    }
  }
  const Fields f(set, "mujoco", "size");
  spec.nconmax = f.integer("nconmax");
  spec.njmax = f.integer("njmax");
  for (int k = 0; k < kUserKinds; ++k) {
    spec.nuser.width[static_cast<size_t>(k)] =
        f.integer(user_size_attribute(static_cast<UserKind>(k)));
  }
}

// <contact>: explicit pairs over their class (their own `class`, else the main class: a body's
// childclass does not reach them) and exclusions, in document order
void read_contact(const Element& root, const DefaultClasses& classes, ModelSpec& spec) {
  for (const Element* section : sections(root, "contact")) {
    for (const Element& e : section->children) {
      if (e.tag == "pair") {
        const int cls = classes.choose(e, "class", 0);
        const AttrSet set = resolve(e, "contact", classes.at(cls).pair);
        const Fields f(set, "contact", "pair");
        PairSpec p;
        p.at = e.place();
        p.geom1 = f.word("geom1");
        p.geom2 = f.word("geom2");
        p.geom1_at = e.place(*e.find("geom1"));
        p.geom2_at = e.place(*e.find("geom2"));
        p.condim = f.integer("condim");
        p.friction = f.array<5>("friction");
        p.solref = f.array<2>("solref");
        p.solimp = f.array<5>("solimp");
        p.margin = f.real("margin");
        p.gap = f.real("gap");
        spec.pairs.push_back(std::move(p));
      } else {
        const AttrSet set = resolve(e, "contact");
        const Fields f(set, "contact", "exclude");
        ExcludeSpec x;
        x.at = e.place();
        x.body1 = f.word("body1");
        x.body2 = f.word("body2");
        x.body1_at = e.place(*e.find("body1"));
        x.body2_at = e.place(*e.find("body2"));
        spec.excludes.push_back(std::move(x));
      }
    }
  }
}

// <keyframe><key>: the numbers as written; their counts are checked once the sizes are known
std::vector<KeySpec> read_keys(const Element& root) {
  std::vector<KeySpec> keys;
  for (const Element* section : sections(root, "keyframe")) {
    for (const Element& e : section->children) {
      KeySpec k;
      k.at = e.place();
      if (const Attribute* t = e.find("time")) {
        k.time = parse_value(e, *t, attribute_rule("keyframe", "key", "time")).numbers[0];
      }
      // the lists as written (an AttrSet would fill them to their maximum length)
      for (const char* name : {"qpos", "qvel", "ctrl", "act", "mpos", "mquat"}) {
        const Attribute* a = e.find(name);
        if (!a) continue;
        const std::vector<double> v =
            parse_value(e, *a, attribute_rule("keyframe", "key", name)).numbers;
        if (std::string_view(name) == "qpos") k.qpos = v;
        if (std::string_view(name) == "qvel") k.qvel = v;
        if (std::string_view(name) == "ctrl") k.ctrl = v;
        if (std::string_view(name) == "act") k.act = v;
        if (std::string_view(name) == "mpos") k.mpos = v;
        if (std::string_view(name) == "mquat") k.mquat = v;
      }
      keys.push_back(std::move(k));
    }
  }
  return keys;
}

// what a <mesh> says about its shape, over its class's mesh defaults (scale); MuJoCo computes a
// mesh's inertia at the geom density of the mesh's class
MeshSource read_mesh_source(const Element& e, const DefaultClass& cls) {
  AttrSet set = cls.visual_only;  // the class's mesh defaults live with the other visual ones
  set.apply(e, *find_rule("asset", "mesh"));
  const Fields f(set, "asset", "mesh");
  MeshSource m;
  m.refpos = f.array<3>("refpos");
  m.refquat = f.array<4>("refquat");
  const Quat& q = m.refquat;
  if (q[0] == 0 && q[1] == 0 && q[2] == 0 && q[3] == 0) {
    fail(e.place(), "refquat", "refquat is zero; a rotation needs a nonzero quaternion");
  }
  m.scale = f.array<3>("scale");
  if (const Value* density = cls.geom.find("density")) {
    m.density = density->numbers[0];
  } else {
    m.density = default_numbers(attribute_rule("body", "geom", "density"))[0];
  }
  return m;
}

// <asset>: names and mesh files (read later, only if needed); a mesh without a name is named
// after its file
AssetSpec read_assets(const Element& root, const DefaultClasses& classes) {
  AssetSpec assets;
  for (const Element* section : sections(root, "asset")) {
    for (const Element& e : section->children) {
      const int cls = classes.choose(e, "class", 0);  // an unknown class is an error
      Place at = e.place();
      if (e.tag == "mesh") {
        assets.mesh_sources.push_back(read_mesh_source(e, classes.at(cls)));
        const Attribute* file = e.find("file");
        std::string path = file ? file->value : "";
        if (at.name.empty() && !path.empty()) {
          // mujoco: the file name without folder and extension
          std::string base = path.substr(
              path.find_last_of("/\\") == std::string::npos ? 0 : path.find_last_of("/\\") + 1);
          const size_t dot = base.rfind('.');
          at.name = dot == std::string::npos ? base : base.substr(0, dot);
        }
        if (!file && !e.find("vertex")) {
          fail(e.place(), "file", "a <mesh> needs a file or vertex data");
        }
        if (file && path.empty()) fail(e.place(*file), "file", "a <mesh> file name is empty");
        assets.meshes.push_back(at);
        assets.mesh_files.push_back(path);
      }
      if (e.tag == "material") assets.materials.push_back(at);
      if (e.tag == "texture") assets.textures.push_back(at);
    }
  }
  return assets;
}

}  // namespace

ModelSpec parse_model(const Element& root, bool ignore_inertials) {
  ModelSpec spec;
  const AttrSet root_set = resolve(root, "");
  spec.name = Fields(root_set, "", "mujoco").word("model");
  spec.compiler = read_compiler(root);
  spec.opt = read_option(root);
  read_size(root, spec);
  DefaultClasses classes;
  for (const Element* e : sections(root, "default")) classes.read_section(*e);
  spec.assets = read_assets(root, classes);
  CompositeOutput generated;
  const TreeReader tree{classes, ignore_inertials, spec.assets, generated};
  spec.world.at = Place{"worldbody", "world", 0};
  for (const Element* e : sections(root, "worldbody")) {
    if (spec.world.at.line == 0) spec.world.at.line = e->line;
    tree.read_contents(*e, 0, spec.world);
  }
  // what composites generate comes first, as MuJoCo adds it while reading <worldbody>
  spec.excludes = std::move(generated.excludes);
  read_contact(root, classes, spec);
  spec.equalities = std::move(generated.equalities);
  for (EqualitySpec& q : read_equalities(root, classes)) spec.equalities.push_back(std::move(q));
  spec.tendons = std::move(generated.tendons);
  for (TendonSpec& t : read_tendons(root, classes)) spec.tendons.push_back(std::move(t));
  for (const Element* e : sections(root, "actuator")) {
    for (const Element& a : e->children) spec.motors.push_back(read_actuator(a, classes));
  }
  spec.keys = read_keys(root);
  spec.sensors = read_sensors(root);
  return spec;
}

}  // namespace lever::mjcf::detail
