// The MJCF subset as a table; see schema.hpp. Built-in defaults are MuJoCo 2.2.2's, except
// compiler/autolimits, which defaults to true as in MuJoCo 3.
#include "schema.hpp"

#include "sensors.hpp"

#include <algorithm>
#include <cctype>
#include <sstream>

namespace lever::mjcf::detail {

AttributeRule user_data_rule() {
  AttributeRule r;
  r.name = "user";
  r.kind = ValueKind::kReal;
  r.count = 1000;
  r.list = true;
  r.meaning =
      "user data: numbers the engine never reads, padded with zeros to `size/nuser_*` (-1: the "
      "longest list of the kind)";
  return r;
}

namespace {

// ---- attribute constructors, so that each table row reads as one line ------------------------

AttributeRule real(std::string_view name, int count, std::string_view def,
                   std::string_view meaning) {
  AttributeRule r;
  r.name = name;
  r.kind = ValueKind::kReal;
  r.count = count;
  r.default_value = def;
  r.meaning = meaning;
  return r;
}

// a vector that may be given in part: the missing tail keeps the inherited (class) values
AttributeRule partial(std::string_view name, int count, std::string_view def,
                      std::string_view meaning) {
  AttributeRule r = real(name, count, def, meaning);
  r.partial = true;
  return r;
}

AttributeRule user_data() { return user_data_rule(); }

AttributeRule integer(std::string_view name, int count, std::string_view def,
                      std::string_view meaning) {
  AttributeRule r = real(name, count, def, meaning);
  r.kind = ValueKind::kInteger;
  return r;
}

AttributeRule keyword(std::string_view name, std::string_view def, std::string_view accepted,
                      std::string_view refused, std::string_view meaning) {
  AttributeRule r;
  r.name = name;
  r.kind = ValueKind::kKeyword;
  r.default_value = def;
  r.keywords = accepted;
  r.unsupported_keywords = refused;
  r.meaning = meaning;
  return r;
}

AttributeRule text(std::string_view name, std::string_view def, std::string_view meaning) {
  AttributeRule r;
  r.name = name;
  r.kind = ValueKind::kText;
  r.default_value = def;
  r.meaning = meaning;
  return r;
}

AttributeRule required(AttributeRule r) {
  r.required = true;
  return r;
}

std::vector<AttributeRule> join(std::vector<AttributeRule> a, const std::vector<AttributeRule>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// ---- attribute groups shared by several elements -----------------------------------------------

std::vector<AttributeRule> naming(std::string_view what) {
  return {text("name", "", what), text("class", "", "default class (else the body's childclass)")};
}

// the orientation alternatives to `quat`; at most one orientation per element
std::vector<AttributeRule> alternatives() {
  return {real("axisangle", 4, "", "rotation axis and angle; the angle in degrees unless radian"),
          real("xyaxes", 6, "", "x and y axes of the frame (y is orthogonalized)"),
          real("zaxis", 3, "", "z axis of the frame (minimal rotation from +z)"),
          real("euler", 3, "", "Euler angles in compiler/eulerseq order; degrees unless radian")};
}

std::vector<AttributeRule> joint_attributes() {
  return {
      keyword("type", "hinge", "hinge slide ball free", "", "joint type"),
      real("pos", 3, "0 0 0", "anchor, body frame"),
      real("axis", 3, "0 0 1", "axis, body frame; normalized, must not be zero"),
      real("range", 2, "0 0", "lower and upper limit: rad/m; hinge in degrees unless radian"),
      keyword("limited", "auto", "false true auto", "",
              "auto: limited if range is given (compiler/autolimits)"),
      real("damping", 1, "0", "N m s/rad or N s/m"),
      real("stiffness", 1, "0", "spring stiffness, N m/rad or N/m"),
      real("springref", 1, "0",
           "spring rest position (qpos_spring); hinge in degrees unless radian"),
      real("armature", 1, "0", "rotor inertia added to the mass matrix diagonal"),
      integer("group", 1, "0", "visualisation group (kept; no effect on dynamics)"),
      real("ref", 1, "0", "reference position (qpos0); hinge in degrees unless radian"),
      real("margin", 1, "0", "limit activation margin"),
      partial("solreflimit", 2, "0.02 1", "limit solref (timeconst, dampratio)"),
      partial("solimplimit", 5, "0.9 0.95 0.001 0.5 2",
              "limit solimp (d0, dmax, width, mid, power)"),
      real("frictionloss", 1, "0",
           "dry friction: a constraint row per dof whose force is at most this (N m or N)"),
      partial("solreffriction", 2, "0.02 1", "friction loss solref (timeconst, dampratio)"),
      partial("solimpfriction", 5, "0.9 0.95 0.001 0.5 2",
              "friction loss solimp (d0, dmax, width, mid, power)"),
      user_data(),
  };
}

std::vector<AttributeRule> geom_attributes() {
  return join(
      {
          keyword("type", "sphere", "plane sphere capsule ellipsoid cylinder box mesh", "hfield",
                  "shape; a plane only in a body fixed to the world; a mesh geom needs no mesh "
                  "file unless it must give its body mass"),
          text("mesh", "",
               "mesh asset of a mesh geom (its file is read only if the geom must "
               "give its body mass)"),
          text("material", "", "material asset (kept; no effect on dynamics)"),
          partial("size", 3, "0 0 0",
                  "sphere r; capsule, cylinder r, half-length; ellipsoid, box half-sizes; plane "
                  "drawn half-sizes (0: infinite) and grid spacing (must be positive)"),
          real("fromto", 6, "", "segment end points; sets pos, quat and the length"),
          real("pos", 3, "0 0 0", "centre, body frame"),
          real("quat", 4, "1 0 0 0", "orientation (w x y z), normalized; must not be zero"),
      },
      join(alternatives(),
           {
               real("density", 1, "1000", "kg/m^3, for the mass inferred from the volume"),
               keyword("shellinertia", "false", "false true", "",
                       "a mesh geom's inertia as a shell (its surface area as the volume; MuJoCo "
                       "2.2.2's frame and inertia box of the surface); meshes only"),
               real("mass", 1, "", "kg; overrides density"),
               integer("group", 1, "0", "group; compiler/inertiagrouprange selects mass"),
               integer("contype", 1, "1",
                       "contact type bits: two geoms collide if one's contype shares a bit with "
                       "the other's conaffinity"),
               integer("conaffinity", 1, "1", "contact affinity bits"),
               real("rgba", 4, "0.5 0.5 0.5 1", "colour"),
               integer("condim", 1, "3",
                       "contact dimensionality: 1 (normal only), 3 (sliding friction), 4 (and "
                       "torsional), 6 (and rolling)"),
               partial("friction", 3, "1 0.005 0.0001", "sliding, torsional, rolling friction"),
               partial("solref", 2, "0.02 1", "contact solref (timeconst, dampratio)"),
               partial("solimp", 5, "0.9 0.95 0.001 0.5 2",
                       "contact solimp (d0, dmax, width, mid, power)"),
               real("margin", 1, "0", "contacts are detected within this distance"),
               real("gap", 1, "0", "contacts within margin - gap become constraints"),
               integer("priority", 1, "0",
                       "of two geoms in contact, the higher priority's parameters are used"),
               real("solmix", 1, "1", "weight of this geom's solref/solimp at equal priority"),
               user_data(),
           }));
}

std::vector<AttributeRule> site_attributes() {
  return join({keyword("type", "sphere", "sphere capsule ellipsoid cylinder box", "",
                       "shape (kept; a site has no mass and does not collide)"),
               integer("group", 1, "0", "visualisation group (kept)"),
               text("material", "", "material asset (kept)"),
               real("rgba", 4, "0.5 0.5 0.5 1", "colour (kept)"),
               real("pos", 3, "0 0 0", "position, body frame"),
               real("quat", 4, "1 0 0 0", "orientation (w x y z); must not be zero")},
              join(alternatives(),
                   {partial("size", 3, "0.005 0.005 0.005", "sphere radius (first number)"),
                    user_data()}));
}

std::vector<AttributeRule> motor_class_attributes() {
  return {
      partial("gear", 6, "1 0 0 0 0 0", "gear ratio (only the first number acts on a joint)"),
      real("ctrlrange", 2, "0 0", "control range (never converted from degrees)"),
      keyword("ctrllimited", "auto", "false true auto", "", "auto: limited if ctrlrange is given"),
      real("forcerange", 2, "0 0", "force range"),
      keyword("forcelimited", "auto", "false true auto", "",
              "auto: limited if forcerange is given"),
      user_data(),
  };
}

// what a <pair> sets, in a default class and in <contact>; MuJoCo 2.2.2 takes nothing from the
// two geoms: what is not written comes from the class, else from these built-in values
std::vector<AttributeRule> pair_attributes() {
  return {
      integer("condim", 1, "3", "contact dimensionality: 1, 3, 4 or 6"),
      partial("friction", 5, "1 1 0.005 0.0001 0.0001",
              "tangent1, tangent2, torsional, rolling1, rolling2 friction"),
      partial("solref", 2, "0.02 1", "contact solref (timeconst, dampratio)"),
      partial("solimp", 5, "0.9 0.95 0.001 0.5 2", "contact solimp (d0, dmax, width, mid, power)"),
      real("margin", 1, "0", "contacts are detected within this distance"),
      real("gap", 1, "0", "contacts within margin - gap become constraints"),
  };
}

// what an equality constraint takes from its class (MuJoCo 2.2.2 reads only these in <default>)
std::vector<AttributeRule> equality_class_attributes() {
  return {
      keyword("active", "true", "false true", "", "false: the constraint makes no rows"),
      partial("solref", 2, "0.02 1", "solref (timeconst, dampratio)"),
      partial("solimp", 5, "0.9 0.95 0.001 0.5 2", "solimp (d0, dmax, width, mid, power)"),
  };
}

// <equality> and its constraints: MuJoCo 2.2.2's connect, weld and joint coupling (compiled by
// equality.cpp)
void add_equality_rules(std::vector<ElementRule>& s) {
  const auto own = [](std::vector<AttributeRule> a) {
    return join({text("name", "", "constraint name"),
                 text("class", "", "default class (else the main class)")},
                join(std::move(a), equality_class_attributes()));
  };
  s.push_back({"equality",
               "mujoco",
               '*',
               {},
               "",
               "distance",
               "equality constraints: rows of the constraint solver, first in MuJoCo's order"});
  s.push_back({"connect", "equality", '*',
               own({required(text("body1", "", "first body")),
                    text("body2", "", "second body (else the world)"),
                    required(real("anchor", 3, "0 0 0", "the joined point, body1's frame"))}),
               "", "", "a ball joint: a point of body1 held on the same point of body2"});
  s.push_back({"weld", "equality", '*',
               own({required(text("body1", "", "first body")),
                    text("body2", "", "second body (else the world)"),
                    real("relpose", 7, "0 0 0 0 0 0 0",
                         "body2's pose in body1's frame (position, quaternion); a zero "
                         "quaternion: the pose at qpos0"),
                    real("anchor", 3, "0 0 0", "the welded point, body2's frame"),
                    real("torquescale", 1, "1", "weight of the rotational rows")}),
               "", "", "body1 held at a fixed pose relative to body2"});
  s.push_back({"joint", "equality", '*',
               own({required(text("joint1", "", "the coupled joint (hinge or slide)")),
                    text("joint2", "", "the joint it follows (else none: joint1 held)"),
                    real("polycoef", 5, "0 1 0 0 0",
                         "q1 - q1_0 = c0 + c1 x + c2 x^2 + c3 x^3 + c4 x^4, x = q2 - q2_0")}),
               "", "", "a joint coupled to another by a polynomial (or held)"});
  s.push_back({"tendon", "equality", '*',
               own({required(text("tendon1", "", "the coupled tendon")),
                    text("tendon2", "", "the tendon it follows (else none: tendon1 held)"),
                    real("polycoef", 5, "0 1 0 0 0",
                         "L1 - L1_0 = c0 + c1 x + c2 x^2 + c3 x^3 + c4 x^4, x = L2 - L2_0 (lengths "
                         "about those at qpos0)")}),
               "", "", "a tendon's length coupled to another's by a polynomial (or held)"});
}

// what a tendon takes from its class (<default><tendon>)
std::vector<AttributeRule> tendon_class_attributes() {
  return {
      integer("group", 1, "0", "visualisation group (kept; no effect on dynamics)"),
      keyword("limited", "auto", "false true auto", "",
              "auto: limited if range is given (compiler/autolimits)"),
      real("range", 2, "0 0", "lower and upper length (length units, never degrees)"),
      partial("solreflimit", 2, "0.02 1", "limit solref (timeconst, dampratio)"),
      partial("solimplimit", 5, "0.9 0.95 0.001 0.5 2",
              "limit solimp (d0, dmax, width, mid, power)"),
      partial("solreffriction", 2, "0.02 1", "friction loss solref (timeconst, dampratio)"),
      partial("solimpfriction", 5, "0.9 0.95 0.001 0.5 2",
              "friction loss solimp (d0, dmax, width, mid, power)"),
      real("frictionloss", 1, "0", "dry friction: a constraint row whose force is at most this"),
      real("springlength", 1, "-1", "the spring's rest length; negative: the length at springref"),
      real("margin", 1, "0", "limit rows start this far from a stop"),
      real("stiffness", 1, "0", "spring stiffness along the tendon"),
      real("damping", 1, "0", "damping along the tendon"),
      real("width", 1, "0.003", "drawn width (spatial tendons)"),
      text("material", "", "visual only: read and kept, no effect on dynamics"),
      real("rgba", 4, "0.5 0.5 0.5 1", "visual only: read and kept, no effect on dynamics"),
      user_data(),
  };
}

// <tendon>: fixed and spatial tendons and their paths (tendon.cpp)
void add_tendon_rules(std::vector<ElementRule>& s) {
  s.push_back({"tendon", "mujoco", '*', {}, "", "",
               "tendons: lengths along paths of joints (fixed) or of sites (spatial)"});
  s.push_back({"fixed", "tendon", '*',
               join({text("name", "", "tendon name"),
                     text("class", "", "default class (else the main class)")},
                    tendon_class_attributes()),
               "", "",
               "a fixed tendon: length sum coef_k q_k over its joints; a spring-damper, limits and "
               "friction loss along it"});
  s.push_back({"joint", "fixed", '*',
               {required(text("joint", "", "a hinge or slide of the path")),
                required(real("coef", 1, "0", "its coefficient in the length"))},
               "", "", "one joint of a fixed tendon's path"});
  s.push_back({"spatial", "tendon", '*',
               join({text("name", "", "tendon name"),
                     text("class", "", "default class (else the main class)")},
                    tendon_class_attributes()),
               "", "",
               "a spatial tendon: a path through sites, wrapping around spheres and cylinders "
               "between them, split by pulleys; a spring-damper, limits and friction loss along "
               "it"});
  s.push_back({"site", "spatial", '*',
               {required(text("site", "", "a site the path passes through"))},
               "", "", "a site of a spatial tendon's path"});
  s.push_back({"geom", "spatial", '*',
               {required(text("geom", "", "a sphere or cylinder between two sites of the path")),
                text("sidesite", "", "a site on the side the tendon passes (inside the geom: "
                                     "through it)")},
               "", "", "a geom the path wraps around when the straight line would cross it"});
  s.push_back({"pulley", "spatial", '*',
               {required(real("divisor", 1, "0", "the branch's length is divided by this"))},
               "", "", "starts a new branch of the path, its length divided by divisor"});
}

const char* const kUnsupportedJointAttributes = "springdamper";
const char* const kUnsupportedGeomAttributes =
    "hfield fitscale fluidshape fluidcoef";
const char* const kUnsupportedSiteAttributes = "fromto";

// attributes every actuator kind shares, in a default class and in <actuator>
std::vector<AttributeRule> general_class_attributes() {
  return join(motor_class_attributes(),
              {
                  integer("group", 1, "0", "visualisation group (kept; no effect on dynamics)"),
                  keyword("dyntype", "none", "none integrator filter muscle user", "",
                          "activation dynamics: none (ctrl acts directly); integrator (act' = "
                          "ctrl), filter (act' = (ctrl - act) / dynprm[0]), muscle (MuJoCo's "
                          "activation time constants dynprm[0..1]), user (the model's "
                          "actuator_dyn_callback, MuJoCo's mjcb_act_dyn; 0 without one): the "
                          "force follows act"),
                  keyword("gaintype", "fixed", "fixed affine muscle user", "",
                          "gain: fixed = gainprm[0]; affine = gainprm[0] + gainprm[1] length + "
                          "gainprm[2] velocity; muscle = the force-length-velocity curves; user "
                          "= the model's actuator_gain_callback (mjcb_act_gain; 1 without one)"),
                  keyword("biastype", "none", "none affine muscle user", "",
                          "bias: affine = biasprm[0] + biasprm[1] length + biasprm[2] velocity; "
                          "muscle = the passive force curve; user = the model's "
                          "actuator_bias_callback (mjcb_act_bias; 0 without one)"),
                  partial("gainprm", 10, "1 0 0 0 0 0 0 0 0 0", "gain parameters"),
                  partial("biasprm", 10, "0 0 0 0 0 0 0 0 0 0", "bias parameters"),
                  partial("dynprm", 10, "1 0 0 0 0 0 0 0 0 0", "activation-dynamics parameters"),
                  keyword("actlimited", "auto", "false true auto", "",
                          "auto: the activation is clamped to actrange if actrange is given"),
                  real("actrange", 2, "0 0", "activation range (needs dynamics)"),
              });
}

// <muscle>'s own attributes: they set gainprm = biasprm and dynprm (MuJoCo 2.2.2's reader)
std::vector<AttributeRule> muscle_class_attributes() {
  return join(motor_class_attributes(),
              {integer("group", 1, "0", "visualisation group (kept; no effect on dynamics)"),
               real("timeconst", 2, "0.01 0.04", "activation and deactivation time constants, s"),
               real("range", 2, "0.75 1.05", "operating range of normalized length"),
               real("force", 1, "-1", "peak active force; negative: scale / acc0"),
               real("scale", 1, "200", "the peak force's scale when force is negative"),
               real("lmin", 1, "0.5", "least normalized length with active force"),
               real("lmax", 1, "1.6", "greatest normalized length with active force"),
               real("vmax", 1, "1.5", "shortening velocity (optimal lengths/s) with no force"),
               real("fpmax", 1, "1.3", "passive force at lmax, relative to the peak force"),
               real("fvmax", 1, "1.2", "the lengthening force, relative to the peak force")});
}

std::vector<AttributeRule> shortcut_class_attributes(std::string_view gain_name,
                                                     std::string_view meaning) {
  return join(motor_class_attributes(),
              {integer("group", 1, "0", "visualisation group (kept; no effect on dynamics)"),
               real(gain_name, 1, "1", meaning)});
}

// <position>'s attributes beside kp that MuJoCo 3 added (3.1.0: kv; 3.1.3: inheritrange), with
// MuJoCo 3's meaning; MuJoCo 2.2.2 refuses both
std::vector<AttributeRule> position_class_attributes() {
  return join(shortcut_class_attributes("kp", "position gain, N m/rad or N/m"),
              {real("kv", 1, "",
                    "MuJoCo 3's: damping, N m s/rad or N s/m: biasprm[2] = -kv (unset: the "
                    "class's kv, else 0); must not be negative"),
               real("inheritrange", 1, "0",
                    "MuJoCo 3's: if positive, ctrlrange is the joint's range about its middle, "
                    "scaled by this factor (the joint needs a range; no ctrlrange with it)")});
}

// <intvelocity>: an integrator whose activation a position servo follows (MuJoCo 2.2.2's reader
// sets actlimited, so actrange is needed)
std::vector<AttributeRule> intvelocity_class_attributes() {
  return join(shortcut_class_attributes("kp", "position gain on the integrated control"),
              {real("actrange", 2, "0 0",
                    "range of the activation, the integrated control (always limited: needed)")});
}

// <damper>: ctrllimited is implied, so ctrlrange is required and must not be negative
std::vector<AttributeRule> damper_class_attributes() {
  std::vector<AttributeRule> out =
      shortcut_class_attributes("kv", "damping per unit control, N m s/rad or N s/m; its class's "
                                      "kv is not inherited (0 unless written)");
  std::erase_if(out, [](const AttributeRule& r) { return r.name == "ctrllimited"; });
  for (AttributeRule& r : out) {
    if (r.name == "ctrlrange") {
      r = required(real("ctrlrange", 2, "0 0", "control range, not negative (always limited)"));
    }
  }
  return out;
}

// <cylinder>: a first-order filter (timeconst) on the pressure, times the area, plus an affine
// bias
std::vector<AttributeRule> cylinder_class_attributes() {
  return join(motor_class_attributes(),
              {integer("group", 1, "0", "visualisation group (kept; no effect on dynamics)"),
               real("timeconst", 1, "1", "the pressure's time constant, s: dynprm[0]"),
               real("area", 1, "1", "piston area: gainprm[0]"),
               real("diameter", 1, "", "piston diameter: gainprm[0] = pi/4 diameter^2 (over area)"),
               real("bias", 3, "0 0 0", "biasprm[0..2]: the force's affine bias")});
}

// <adhesion>: gain times a control in [0, ctrlrange], pulling the body onto what it touches
std::vector<AttributeRule> adhesion_class_attributes() {
  return {integer("group", 1, "0", "visualisation group (kept; no effect on dynamics)"),
          required(real("ctrlrange", 2, "0 0", "control range, not negative (always limited)")),
          real("forcerange", 2, "0 0", "force range"),
          keyword("forcelimited", "auto", "false true auto", "",
                  "auto: limited if forcerange is given"),
          real("gain", 1, "1", "force per unit control, not negative; its class's gain is not "
                               "inherited (1 unless written)"),
          user_data()};
}

std::vector<AttributeRule> actuator_wiring(std::string_view what) {
  return {text("name", "", what), text("class", "", "default class (else the top-level class)"),
          text("joint", "", "the joint it drives (one transmission of joint, jointinparent, "
                            "tendon, site, cranksite)"),
          text("jointinparent", "", "the joint it drives, a ball's or free joint's gear in the "
                                    "parent's frame (a hinge or slide: as joint)"),
          text("tendon", "", "the tendon it drives"),
          text("site", "", "the site it pushes: gear is a wrench (force, torque) in its frame"),
          text("refsite", "", "with site: the reference site whose frame holds the gear and the "
                              "length"),
          text("cranksite", "", "a slider-crank's crank site (with slidersite and cranklength)"),
          text("slidersite", "", "a slider-crank's slider site: its z axis is the slide"),
          real("cranklength", 1, "0", "a slider-crank's rod length, positive"),
          real("lengthrange", 2, "0 0", "the range of its length (else the compiler's <lengthrange> "
                                        "finds a muscle's)")};
}

// <muscle>: the wiring of the others but site and refsite (MuJoCo 2.2.2 has none on a muscle)
std::vector<AttributeRule> muscle_wiring() {
  std::vector<AttributeRule> out = actuator_wiring("muscle name");
  std::erase_if(out, [](const AttributeRule& r) { return r.name == "site" || r.name == "refsite"; });
  return out;
}

// <general>'s transmission onto a body: the contacts' normals (MuJoCo's adhesion)
AttributeRule body_transmission() {
  return text("body", "", "the body whose contacts it acts through: the moment is minus the "
                          "mean of its contacts' normal Jacobians (adhesion)");
}

// visual-only assets and elements: read, checked by name, kept as text; no effect on dynamics
std::vector<AttributeRule> texts(std::string_view names, std::string_view meaning) {
  std::vector<AttributeRule> out;
  for (const std::string_view n : words(names)) out.push_back(text(n, "", meaning));
  return out;
}

const char* const kVisualOnly = "visual only: read and kept, no effect on dynamics";
const char* const kMeshAttributes = "name class file vertex normal texcoord face smoothnormal";

// the <mesh> attributes that change its mass properties (used only when lever reads the file)
std::vector<AttributeRule> mesh_attributes() {
  std::vector<AttributeRule> out = texts(kMeshAttributes, kVisualOnly);
  out.push_back(real("refpos", 3, "0 0 0", "reference position: subtracted from the vertices"));
  out.push_back(real("refquat", 4, "1 0 0 0",
                     "reference orientation: the vertices are rotated by its inverse; must not be "
                     "zero"));
  out.push_back(real("scale", 3, "1 1 1", "scale of the vertices (after refpos and refquat)"));
  return out;
}
const char* const kMaterialAttributes =
    "name class texture texrepeat texuniform emission specular shininess reflectance rgba";
const char* const kTextureAttributes =
    "name type file gridsize gridlayout fileright fileleft fileup filedown filefront fileback "
    "builtin rgb1 rgb2 mark markrgb random width height hflip vflip";
const char* const kCameraAttributes =
    "name class fovy ipd pos quat axisangle xyaxes zaxis euler mode target user";
const char* const kLightAttributes =
    "name class directional castshadow active pos dir attenuation cutoff exponent ambient "
    "diffuse specular mode target";

// one row per element: tag, parent, multiplicity, attributes, refused attributes, refused
// children, meaning
// clang-format off
// The attributes named in `names` of the list `from`, in the list's order: a composite's
// <geom>, <joint>, <tendon> and <site> take a subset of the ordinary element's attributes.
std::vector<AttributeRule> attributes_named(const std::vector<AttributeRule>& from,
                                            std::string_view names) {
  std::vector<AttributeRule> out;
  for (const AttributeRule& r : from) {
    if (has_word(names, r.name)) out.push_back(r);
  }
  return out;
}

AttributeRule partial_integers(std::string_view name, int count, std::string_view def,
                       std::string_view meaning) {
  AttributeRule r = partial(name, count, def, meaning);
  r.kind = ValueKind::kInteger;
  return r;
}

const char* const kCompositeTypes =
    "particle grid rope loop cloth box cylinder ellipsoid";

// <composite>: MuJoCo 2.2.2's generated bodies (composite.cpp expands it into ordinary elements
// before compilation); its children set the generated elements' attributes over MuJoCo's built-in
// defaults, never over the model's default classes
void add_composite_rules(std::vector<ElementRule>& s) {
  const std::vector<AttributeRule> composite = {
      text("prefix", "", "prefix of the generated elements' names (B, J, G, S, T ... and indices)"),
      required(keyword("type", "", kCompositeTypes, "",
                       "what is generated: particle (free particles), grid (1D or 2D, sites and "
                       "tendons), rope and loop (a chain of bodies), cloth (a 2D tree of bodies), "
                       "box, cylinder, ellipsoid (a 3D shell)")),
      required(partial_integers("count", 3, "1 1 1",
                        "elements along x, y, z; each >= 1, the singletons last")),
      required(real("spacing", 1, "", "distance between neighbours; must be positive")),
      real("offset", 3, "0 0 0", "centre of a particle set or grid, in the parent body's frame"),
      real("flatinertia", 1, "0",
           "cloth: positive: each body's inertia that of a flat box (this thickness ratio)"),
      partial("solrefsmooth", 2, "0.02 1", "solref of the loop and 3D smoothing constraints"),
      partial("solimpsmooth", 5, "0.9 0.95 0.001 0.5 2",
              "solimp of the loop and 3D smoothing constraints"),
  };
  for (const char* parent : {"worldbody", "body"}) {
    s.push_back({"composite", parent, '*', composite, "", "",
                 "a composite object, expanded as MuJoCo 2.2.2 expands it into bodies, joints, "
                 "geoms, sites, tendons, equality constraints and contact exclusions named "
                 "prefix + B, J, G, S, T ... with their indices (rope and cloth: inside the body "
                 "named for the origin, prefix + B<x> or B<x>_<y>)"});
  }
  const AttributeRule solreffix =
      partial("solreffix", 2, "0.02 1", "solref of the equality constraint that holds the kind");
  const AttributeRule solimpfix = partial("solimpfix", 5, "0.9 0.95 0.001 0.5 2",
                                          "solimp of the equality constraint that holds the kind");
  const AttributeRule limited_ignored =
      keyword("limited", "auto", "false true auto", "",
              "read and ignored, as MuJoCo 2.2.2 ignores it (its reader looks for it on "
              "`<composite>`): auto");
  s.push_back({"joint", "composite", '*',
               join({required(keyword("kind", "", "main twist stretch", "",
                                      "which generated joints: main, twist or stretch (rope and "
                                      "cloth; twist and stretch are added only if written)")),
                     solreffix, solimpfix, limited_ignored},
                    attributes_named(joint_attributes(),
                         "group stiffness damping armature range margin solreflimit "
                         "solimplimit frictionloss solreffriction solimpfriction")),
               "", "", "attributes of the generated joints of one kind"});
  s.push_back({"tendon", "composite", '*',
               join({required(keyword("kind", "", "main shear", "",
                                      "which generated tendons: main or shear (2D grid and cloth; "
                                      "shear is added only if written)")),
                     solreffix, solimpfix, limited_ignored},
                    attributes_named(tendon_class_attributes(),
                         "group stiffness damping range margin solreflimit solimplimit "
                         "frictionloss solreffriction solimpfriction material rgba width")),
               "", "", "attributes of the generated tendons of one kind"});
  s.push_back({"skin", "composite", '?',
               join({keyword("texcoord", "false", "false true", "", kVisualOnly),
                     integer("group", 1, "0", "visual only; must be 0 to 5")},
                    texts("material rgba inflate subgrid", kVisualOnly)),
               "", "",
               "the skin MuJoCo draws over the composite: visual only; lever has no skins and "
               "builds none (the attributes are checked as MuJoCo 2.2.2 checks them)"});
  s.push_back({"geom", "composite", '?',
               attributes_named(geom_attributes(),
                    "type contype conaffinity condim group priority size material rgba friction "
                    "mass density solmix solref solimp margin gap"),
               "", "", "attributes of the generated geoms (sphere, capsule or ellipsoid)"});
  s.push_back({"site", "composite", '?',
               attributes_named(site_attributes(), "group size material rgba"), "", "",
               "attributes of the generated sites"});
  s.push_back({"pin", "composite", '*',
               {required(partial_integers("coord", 2, "0 0", "grid coordinates of an element left "
                                                        "without joints (fixed to the parent)"))},
               "", "", "a grid element pinned in place"});
}

std::vector<ElementRule> build() {
  std::vector<ElementRule> s;
  s.push_back({"mujoco", "", '!', {text("model", "MuJoCo Model", "model name")}, "",
               "custom", "the root element"});
  s.push_back({"compiler", "mujoco", '*',
               {
                   keyword("angle", "degree", "radian degree", "",
                           "unit of euler, axisangle and hinge range/ref/springref"),
                   keyword("autolimits", "true", "false true", "",
                           "a range alone makes a joint or motor limited (lever: default true)"),
                   keyword("inertiafromgeom", "auto", "false true auto", "",
                           "infer body mass from geoms: auto = when a body has no `<inertial>`"),
                   integer("inertiagrouprange", 2, "0 5", "geom groups that contribute mass"),
                   {"eulerseq", ValueKind::kEulerSeq, 1, false, false, "xyz", "", "",
                    "euler axis order: lower case rotating, upper case fixed axes"},
                   real("boundmass", 1, "0", "lower bound on every body mass"),
                   real("boundinertia", 1, "0", "lower bound on every principal moment"),
                   keyword("balanceinertia", "false", "false true", "",
                           "replace an inertia violating A + B >= C by the mean moment"),
                   real("settotalmass", 1, "-1", "if > 0, scale all masses to this total"),
                   keyword("coordinate", "local", "local", "global", "frames are local"),
                   text("meshdir", "",
                        "folder of mesh files, relative to the model's folder (a file is read "
                        "only if a mesh geom must give a body mass or can collide)"),
                   keyword("exactmeshinertia", "false", "false true", "",
                           "mesh volume and inertia: true = signed pyramid volumes; false = "
                           "MuJoCo 2.2.2's legacy: each face's absolute volume, the inertia box's volume"),
                   keyword("convexhull", "true", "false true", "",
                           "true: a mesh that can collide gets its convex hull's graph (qhull), "
                           "along which its support point is found; false: every vertex is visited"),
                   text("texturedir", "", "folder of texture files (kept; never read)"),
               },
               "strippath fitaabb discardvisual usethread fusestatic",
               "", "compiler settings; apply to the whole model wherever written"});
  s.push_back({"lengthrange", "compiler", '?',
               {keyword("mode", "muscle", "none muscle muscleuser all", "",
                        "which actuators get a computed length range (muscleuser: muscles and "
                        "actuators with a user gain or bias)"),
                keyword("useexisting", "true", "false true", "", "keep a lengthrange as written"),
                keyword("uselimit", "false", "false true", "",
                        "take a limited joint's or tendon's range"),
                real("accel", 1, "20", "the simulation's target acceleration of the length"),
                real("maxforce", 1, "0", "the most applied force (0: no bound)"),
                real("timeconst", 1, "1", "s: the velocity's decay in the simulation"),
                real("timestep", 1, "0.01", "s: the simulation's timestep (0: the model's)"),
                real("inttotal", 1, "10", "s: simulated time per side"),
                real("inteval", 1, "2", "s: the final interval whose lengths give the range"),
                real("tolrange", 1, "0.05", "how far the lengths may spread, relative to the range")},
               "", "", "how the compiler finds actuators' length ranges (MuJoCo's "
               "mj_setLengthRange)"});
  s.push_back({"option", "mujoco", '*',
               {
                   real("timestep", 1, "0.002", "s; must be positive"),
                   real("gravity", 3, "0 0 -9.81", "m/s^2, world frame"),
                   keyword("integrator", "Euler", "Euler RK4 implicit implicitfast", "",
                           "integrator: implicit is MuJoCo 2.2.2's (implicit in every "
                           "velocity-dependent force); implicitfast is MuJoCo 3's (implicit in "
                           "the joint damping and actuator velocity terms only)"),
                   real("impratio", 1, "1",
                        "frictional-to-normal impedance ratio of elliptic-cone contacts; must be "
                        "positive"),
                   keyword("cone", "pyramidal", "pyramidal elliptic", "", "friction cone"),
                   keyword("solver", "Newton", "PGS CG Newton", "",
                           "constraint solver: Newton (lever solves the problem exactly), "
                           "MuJoCo's conjugate gradients or its projected Gauss-Seidel (both "
                           "stopped by tolerance and iterations)"),
                   integer("iterations", 1, "100",
                           "most CG iterations or PGS sweeps (lever's Newton solve ends at "
                           "convergence); must not be negative"),
                   real("tolerance", 1, "1e-8",
                        "CG's tolerance on the cost's decrease and gradient (0: the exact "
                        "minimizer CG converges to, as Newton's), PGS's on a sweep's decrease "
                        "(0: every sweep of iterations); must not be negative"),
                   integer("noslip_iterations", 1, "0",
                           "noslip solver iterations: lever has no noslip solver, so only 0"),
                   real("noslip_tolerance", 1, "1e-6",
                        "noslip solver tolerance (kept; no effect without noslip iterations)"),
                   keyword("jacobian", "auto", "dense sparse auto", "",
                           "MuJoCo's layout of the constraint Jacobian (dense, sparse, or "
                           "sparse from 60 dofs on): lever keeps its own, and sums its products "
                           "with the rows in the order MuJoCo's layout sums them"),
                   real("mpr_tolerance", 1, "1e-6",
                        "boundary tolerance of the MPR that collides convex pairs (cylinders, "
                        "ellipsoids, meshes); must not be negative"),
                   integer("mpr_iterations", 1, "50",
                           "most MPR iterations per convex pair; must not be negative"),
                   real("magnetic", 3, "0 -0.5 0",
                        "Earth's magnetic field, world frame (what a magnetometer reads)"),
                   real("viscosity", 1, "0",
                        "the medium's viscosity, Pa s: Stokes drag on each body's inertia box "
                        "(MuJoCo 2.2.2's passive fluid forces); must not be negative"),
                   real("density", 1, "0",
                        "the medium's density, kg/m^3: quadratic drag on each body's inertia "
                        "box; must not be negative"),
                   real("wind", 3, "0 0 0", "the medium's velocity, m/s, world frame"),
                   real("o_margin", 1, "0",
                        "with <flag override=\"enable\">: every contact's margin"),
                   partial("o_solref", 2, "0.02 1",
                           "with <flag override=\"enable\">: every contact's solref"),
                   partial("o_solimp", 5, "0.9 0.95 0.001 0.5 2",
                           "with <flag override=\"enable\">: every contact's solimp"),
               },
               "apirate collision",
               "", "simulation options"});
  s.push_back({"flag", "option", '?',
               {
                   keyword("constraint", "enable", "enable disable", "",
                           "disable: no constraint stage at all (no rows, no contacts)"),
                   keyword("equality", "enable", "enable disable", "",
                           "disable: no equality constraint rows"),
                   keyword("frictionloss", "enable", "enable disable", "",
                           "disable: no friction-loss rows (joints and tendons)"),
                   keyword("limit", "enable", "enable disable", "",
                           "disable: no limit rows (joints and tendons)"),
                   keyword("contact", "enable", "enable disable", "",
                           "disable: no collision detection, no contacts"),
                   keyword("passive", "enable", "enable disable", "",
                           "disable: no springs, damping or fluid forces"),
                   keyword("gravity", "enable", "enable disable", "", "disable: no gravity"),
                   keyword("clampctrl", "enable", "enable disable", "",
                           "disable: ctrl is not clamped to ctrlrange"),
                   keyword("warmstart", "enable", "enable disable", "",
                           "the solver's warm start: lever's solver always starts from "
                           "qacc_smooth (MuJoCo's disabled warm start), which changes where "
                           "MuJoCo's iterations stop, not its converged answer"),
                   keyword("filterparent", "enable", "enable disable", "",
                           "disable: a body's geoms may collide with its parent's"),
                   keyword("actuation", "enable", "enable disable", "",
                           "disable: no actuator forces"),
                   keyword("refsafe", "enable", "enable disable", "",
                           "disable: solref's time constant may be shorter than 2 timesteps"),
                   keyword("sensor", "enable", "enable disable", "",
                           "disable: the sensor stages are skipped (sensordata kept)"),
                   keyword("override", "disable", "disable enable", "",
                           "enable: every contact takes option o_margin, o_solref, o_solimp"),
                   keyword("energy", "disable", "disable enable", "",
                           "enable: forward computes the potential and kinetic energy"),
                   keyword("fwdinv", "disable", "disable enable", "",
                           "enable: each step compares forward and inverse dynamics "
                           "(solver_fwdinv)"),
                   keyword("multiccd", "disable", "disable enable", "",
                           "enable: up to four more contacts per convex pair, found by MPR with "
                           "the geoms turned slightly about the first contact (MuJoCo 2.2.2)"),
                   keyword("sensornoise", "disable", "disable enable", "",
                           "enable: add each sensor's noise (its standard deviation `noise`)"),
               },
               "", "", "simulation flags"});
  s.push_back({"size", "mujoco", '*',
               {
                   integer("nconmax", 1, "-1",
                           "most contacts at once (-1: 100); more is an error in lever"),
                   integer("njmax", 1, "-1",
                           "most constraint rows at once (-1: 500); more is an error in lever"),
                   integer("nstack", 1, "-1", "MuJoCo's stack size (kept; lever sizes its own)"),
                   integer("nuser_body", 1, "-1",
                           "numbers of user data per body (-1: the longest `user` of the bodies)"),
                   integer("nuser_jnt", 1, "-1", "the same per joint"),
                   integer("nuser_geom", 1, "-1", "the same per geom"),
                   integer("nuser_site", 1, "-1", "the same per site"),
                   integer("nuser_tendon", 1, "-1", "the same per tendon"),
                   integer("nuser_actuator", 1, "-1", "the same per actuator"),
                   integer("nuser_sensor", 1, "-1", "the same per sensor"),
               },
               "nuserdata nkey nuser_cam",
               "", "sizes of MuJoCo's mjData"});
  s.push_back({"contact", "mujoco", '*', {}, "", "", "explicit contact pairs and exclusions"});
  add_equality_rules(s);
  add_tendon_rules(s);
  s.push_back({"pair", "contact", '*', join({text("name", "", "pair name"),
                                            text("class", "", "default class (else the main class)"),
                                            required(text("geom1", "", "first geom")),
                                            required(text("geom2", "", "second geom"))},
                                           pair_attributes()),
               "", "",
               "a geom pair that collides whatever contype, conaffinity and the body filters say, "
               "with its own parameters (not mixed from the geoms')"});
  s.push_back({"exclude", "contact", '*', {text("name", "", "exclusion name"),
                                          required(text("body1", "", "first body")),
                                          required(text("body2", "", "second body"))},
               "", "", "a body pair whose geoms never collide (pairs from <pair> still do)"});
  s.push_back({"default", "mujoco", '*', {text("class", "main", "class name (top level: main)")},
               "", "",
               "default class: attribute values that elements of the class start from"});
  s.push_back({"default", "default", '*', {required(text("class", "", "class name"))}, "", "",
               "nested class: starts as a copy of its parent"});
  s.push_back({"joint", "default", '?', joint_attributes(), kUnsupportedJointAttributes, "",
               "joint defaults of the class"});
  s.push_back({"geom", "default", '?', geom_attributes(), kUnsupportedGeomAttributes, "",
               "geom defaults of the class"});
  s.push_back({"site", "default", '?', site_attributes(), kUnsupportedSiteAttributes, "",
               "site defaults of the class"});
  s.push_back({"pair", "default", '?', pair_attributes(), "", "",
               "contact pair defaults of the class"});
  s.push_back({"equality", "default", '?', equality_class_attributes(), "", "",
               "equality constraint defaults of the class"});
  s.push_back({"tendon", "default", '?', tendon_class_attributes(), "", "",
               "tendon defaults of the class"});
  // MuJoCo 2.2.2 takes cranklength in a class for every actuator kind but adhesion; a class's
  // value reaches the actuators of the class, a slider-crank's rod or, on another transmission,
  // kept in actuator_cranklength as MuJoCo keeps it
  const auto with_crank = [](std::vector<AttributeRule> rules) {
    return join(std::move(rules),
                {real("cranklength", 1, "0", "a slider-crank's rod length, positive")});
  };
  s.push_back({"motor", "default", '?',
               with_crank(join(motor_class_attributes(),
                               {integer("group", 1, "0", "visualisation group (kept)")})),
               "", "", "actuator defaults of the class, as a motor"});
  s.push_back({"general", "default", '?', with_crank(general_class_attributes()), "", "",
               "actuator defaults of the class"});
  s.push_back({"muscle", "default", '?', with_crank(muscle_class_attributes()), "", "",
               "actuator defaults of the class, as a muscle"});
  s.push_back({"position", "default", '?', with_crank(position_class_attributes()), "", "",
               "actuator defaults of the class, as a position servo"});
  s.push_back({"velocity", "default", '?',
               with_crank(shortcut_class_attributes("kv", "velocity gain, N m s/rad or N s/m")),
               "", "", "actuator defaults of the class, as a velocity servo"});
  s.push_back({"intvelocity", "default", '?', with_crank(intvelocity_class_attributes()), "", "",
               "actuator defaults of the class, as an integrated-velocity servo"});
  s.push_back({"damper", "default", '?', with_crank(damper_class_attributes()), "", "",
               "actuator defaults of the class, as a damper"});
  s.push_back({"cylinder", "default", '?', with_crank(cylinder_class_attributes()), "", "",
               "actuator defaults of the class, as a cylinder"});
  s.push_back({"adhesion", "default", '?', adhesion_class_attributes(), "", "",
               "actuator defaults of the class, as adhesion"});
  s.push_back({"mesh", "default", '?',
               {real("scale", 3, "1 1 1", "scale of the vertices of the class's meshes")}, "", "",
               "mesh defaults"});
  s.push_back({"material", "default", '?',
               texts("texture emission specular shininess reflectance rgba texrepeat texuniform",
                     kVisualOnly),
               "", "", "material defaults"});
  s.push_back({"camera", "default", '?',
               texts("fovy ipd pos quat axisangle xyaxes zaxis euler mode user", kVisualOnly), "",
               "", "camera defaults"});
  s.push_back({"light", "default", '?',
               texts("pos dir directional castshadow active attenuation cutoff exponent ambient "
                     "diffuse specular mode", kVisualOnly),
               "", "", "light defaults"});
  s.push_back({"asset", "mujoco", '*', {}, "", "hfield skin",
               "assets: meshes, materials and textures (no file is read unless a mesh must give mass "
               "or can collide)"});
  s.push_back({"mesh", "asset", '*', mesh_attributes(), "", "",
               "a mesh; its file (binary STL or OBJ) is read only if a mesh geom must give a "
               "body mass or can collide; then its volume, centre, inertia, vertices and convex "
               "hull are MuJoCo 2.2.2's"});
  s.push_back({"material", "asset", '*', texts(kMaterialAttributes, kVisualOnly), "", "",
               "a material"});
  s.push_back({"texture", "asset", '*', texts(kTextureAttributes, kVisualOnly), "", "",
               "a texture"});
  s.push_back({"visual", "mujoco", '*', {}, "", "", "visualisation settings (kept as text)"});
  s.push_back({"global", "visual", '?',
               texts("fovy ipd azimuth elevation linewidth glow offwidth offheight", kVisualOnly),
               "", "", "visual/global"});
  s.push_back({"quality", "visual", '?',
               texts("shadowsize offsamples numslices numstacks numquads", kVisualOnly), "", "",
               "visual/quality"});
  s.push_back({"headlight", "visual", '?', texts("ambient diffuse specular active", kVisualOnly),
               "", "", "visual/headlight"});
  s.push_back({"map", "visual", '?',
               texts("stiffness stiffnessrot force torque alpha fogstart fogend znear zfar haze "
                     "shadowclip shadowscale actuatortendon", kVisualOnly),
               "", "", "visual/map"});
  s.push_back({"scale", "visual", '?',
               texts("forcewidth contactwidth contactheight connect com camera light selectpoint "
                     "jointlength jointwidth actuatorlength actuatorwidth framelength framewidth "
                     "constraint slidercrank", kVisualOnly),
               "", "", "visual/scale"});
  s.push_back({"rgba", "visual", '?',
               texts("fog haze force inertia joint actuator actuatornegative actuatorpositive com "
                     "camera light selectpoint connect contactpoint contactforce contactfriction "
                     "contacttorque contactgap rangefinder constraint slidercrank crankbroken",
                     kVisualOnly),
               "", "", "visual/rgba"});
  s.push_back({"statistic", "mujoco", '*', texts("meanmass meansize extent center", kVisualOnly),
               "meaninertia", "", "model statistics for the viewer (kept)"});
  s.push_back({"keyframe", "mujoco", '*', {}, "", "", "named states to start from"});
  s.push_back({"key", "keyframe", '*',
               {text("name", "", "keyframe name"), real("time", 1, "0", "s"),
                partial("qpos", 1000, "", "nq numbers (default: qpos0)"),
                partial("qvel", 1000, "", "nv numbers (default: zero)"),
                partial("ctrl", 1000, "", "nu numbers (default: zero)"),
                partial("act", 1000, "", "na numbers (default: zero)"),
                partial("mpos", 3000, "", "3 nmocap numbers (default: the mocap bodies' pos)"),
                partial("mquat", 4000, "",
                        "4 nmocap numbers, normalized (default: the mocap bodies' quat)")},
               "", "", "a keyframe (mj_resetDataKeyframe)"});
  s.push_back({"worldbody", "mujoco", '*', {}, "", "",
               "the world body: static geoms, sites and the body tree; takes no attributes"});
  const std::vector<AttributeRule> body = join(
      {text("name", "", "body name"),
       text("childclass", "", "default class for everything inside this body"),
       real("pos", 3, "0 0 0", "position in the parent frame"),
       real("quat", 4, "1 0 0 0", "orientation in the parent frame; must not be zero"),
       keyword("mocap", "false", "false true", "",
               "true: a mocap body, placed by data.mocap_pos and mocap_quat (a child of the "
               "world without joints)"),
       user_data()},
      alternatives());
  s.push_back({"body", "worldbody", '*', body, "", "", "a body fixed to the world "
               "unless it has joints"});
  s.push_back({"body", "body", '*', body, "", "", "a child body"});
  for (const char* parent : {"worldbody", "body"}) {
    s.push_back({"camera", parent, '*', texts(kCameraAttributes, kVisualOnly), "", "",
                 "a camera (kept)"});
    s.push_back({"light", parent, '*', texts(kLightAttributes, kVisualOnly), "", "",
                 "a light (kept)"});
  }
  s.push_back({"inertial", "body", '?',
               join({required(real("pos", 3, "", "centre of mass, body frame")),
                     real("quat", 4, "1 0 0 0", "principal axes; must not be zero"),
                     required(real("mass", 1, "", "kg; must not be negative")),
                     real("diaginertia", 3, "0 0 0", "principal moments, kg m^2 (not sorted)"),
                     real("fullinertia", 6, "", "Ixx Iyy Izz Ixy Ixz Iyz; diagonalized")},
                    alternatives()),
               "", "", "explicit mass and inertia of the body (else inferred from geoms)"});
  s.push_back({"freejoint", "body", '?',
               {text("name", "", "joint name"),
                integer("group", 1, "0", "visualisation group (kept; no effect on dynamics)")},
               "", "",
               "a free joint, taking no default class: the body moves freely (its pose is its "
               "qpos: position and quaternion; 6 dofs)"});
  s.push_back({"joint", "body", '*', join(naming("joint name"), joint_attributes()),
               kUnsupportedJointAttributes, "", "a joint between the body and its parent"});
  s.push_back({"geom", "body", '*', join(naming("geom name"), geom_attributes()),
               kUnsupportedGeomAttributes, "", "a shape; gives the body mass unless `<inertial>`"});
  s.push_back({"geom", "worldbody", '*', join(naming("geom name"), geom_attributes()),
               kUnsupportedGeomAttributes, "", "a static shape (no mass)"});
  s.push_back({"site", "body", '*', join(naming("site name"), site_attributes()),
               kUnsupportedSiteAttributes, "", "a named frame: no mass, no collision"});
  s.push_back({"site", "worldbody", '*', join(naming("site name"), site_attributes()),
               kUnsupportedSiteAttributes, "", "a named frame fixed to the world"});
  add_composite_rules(s);
  s.push_back({"actuator", "mujoco", '*', {}, "", "", "actuators"});
  s.push_back({"motor", "actuator", '*',
               join(actuator_wiring("motor name"),
                    join(motor_class_attributes(),
                         {integer("group", 1, "0",
                                  "visualisation group (kept; no effect on dynamics)")})),
               "",
               "", "a torque (hinge) or force (slide) motor: force = gear * ctrl"});
  s.push_back({"general", "actuator", '*',
               join(join(actuator_wiring("actuator name"), {body_transmission()}),
                    general_class_attributes()),
               "", "",
               "an actuator: force = gain * ctrl + bias (fixed or affine gain, affine bias)"});
  s.push_back({"position", "actuator", '*',
               join(actuator_wiring("actuator name"),
                    position_class_attributes()),
               "", "",
               "a position servo: force = kp (ctrl - q) - kv qd (kv is MuJoCo 3's)"});
  s.push_back({"muscle", "actuator", '*',
               join(muscle_wiring(), muscle_class_attributes()), "", "",
               "a muscle: MuJoCo's force-length-velocity and activation model"});
  s.push_back({"velocity", "actuator", '*',
               join(actuator_wiring("actuator name"),
                    shortcut_class_attributes("kv", "velocity gain, N m s/rad or N s/m")),
               "", "", "a velocity servo: force = kv (ctrl - qd)"});
  s.push_back({"intvelocity", "actuator", '*',
               join(actuator_wiring("actuator name"), intvelocity_class_attributes()), "", "",
               "an integrated-velocity servo: act' = ctrl, force = kp (act - length)"});
  s.push_back({"damper", "actuator", '*',
               join(actuator_wiring("actuator name"), damper_class_attributes()), "", "",
               "an active damper: force = -kv ctrl velocity, ctrl in a non-negative range"});
  s.push_back({"cylinder", "actuator", '*',
               join(actuator_wiring("actuator name"), cylinder_class_attributes()), "", "",
               "a pneumatic or hydraulic cylinder: act' = (ctrl - act) / timeconst, force = "
               "area act + bias[0] + bias[1] length + bias[2] velocity"});
  s.push_back({"adhesion", "actuator", '*',
               join({text("name", "", "actuator name"),
                     text("class", "", "default class (else the top-level class)"),
                     required(body_transmission())},
                    adhesion_class_attributes()),
               "", "",
               "adhesion: force = gain ctrl, pulling the body onto the geoms it touches along the "
               "mean of its contacts' normals (contacts in the margin's gap count too)"});
  for (ElementRule& r : sensor_rules()) s.push_back(std::move(r));
  return s;
}
// clang-format on

// every element tag of MJCF 2.2.2, supported or not
const char* const kAllMjcfElements =
    "mujoco compiler lengthrange option flag size visual global quality headlight map scale rgba "
    "statistic default mesh material joint geom site camera light pair equality tendon general "
    "motor position velocity intvelocity damper cylinder muscle adhesion custom numeric text tuple "
    "element asset texture hfield skin bone worldbody body inertial freejoint composite pin "
    "contact exclude connect weld distance spatial fixed pulley actuator sensor touch "
    "accelerometer velocimeter gyro force torque magnetometer rangefinder jointpos jointvel "
    "tendonpos tendonvel actuatorpos actuatorvel actuatorfrc ballquat ballangvel jointlimitpos "
    "jointlimitvel jointlimitfrc tendonlimitpos tendonlimitvel tendonlimitfrc framepos framequat "
    "framexaxis frameyaxis framezaxis framelinvel frameangvel framelinacc frameangacc subtreecom "
    "subtreelinvel subtreeangmom clock user keyframe key include";

// names MuJoCo 3 added that lever does not have, per element ("" lists elements)
struct Mujoco3Names {
  std::string_view tag, names;
};
const Mujoco3Names kMujoco3Names[] = {
    {"", "replicate frame plugin extension attach flexcomp flex deformable model instance"},
    {"compiler", "assetdir alignfree saveinertial"},
    {"option",
     "ls_iterations ls_tolerance ccd_iterations ccd_tolerance sdf_iterations "
     "sdf_initpoints actuatorgroupdisable"},
    {"flag", "eulerdamp nativeccd island midphase autoreset"},
    {"joint", "actuatorfrcrange actuatorfrclimited actuatorgravcomp"},
    {"body", "gravcomp"},
    {"position", "dampratio timeconst"},
    {"general", "actearly actdim"},
};

}  // namespace

bool is_mujoco3_name(std::string_view tag, std::string_view attribute) {
  for (const Mujoco3Names& n : kMujoco3Names) {
    if (attribute.empty() ? (n.tag.empty() && has_word(n.names, tag))
                          : (n.tag == tag && has_word(n.names, attribute))) {
      return true;
    }
  }
  return false;
}

const std::vector<ElementRule>& schema() {
  static const std::vector<ElementRule> table = build();
  return table;
}

const ElementRule* find_rule(std::string_view parent, std::string_view tag) {
  for (const ElementRule& r : schema()) {
    if (r.parent == parent && r.tag == tag) return &r;
  }
  return nullptr;
}

const AttributeRule* find_attribute(const ElementRule& element, std::string_view name) {
  for (const AttributeRule& a : element.attributes) {
    if (a.name == name) return &a;
  }
  return nullptr;
}

const AttributeRule& attribute_rule(std::string_view parent, std::string_view tag,
                                    std::string_view name) {
  static const AttributeRule missing;
  const ElementRule* e = find_rule(parent, tag);
  const AttributeRule* a = e ? find_attribute(*e, name) : nullptr;
  return a ? *a : missing;
}

std::vector<std::string_view> words(std::string_view list) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < list.size()) {
    while (i < list.size() && list[i] == ' ') ++i;
    size_t j = i;
    while (j < list.size() && list[j] != ' ') ++j;
    if (j > i) out.push_back(list.substr(i, j - i));
    i = j;
  }
  return out;
}

bool has_word(std::string_view list, std::string_view word) {
  for (const std::string_view w : words(list)) {
    if (w == word) return true;
  }
  return false;
}

bool is_known_mjcf_element(std::string_view tag) { return has_word(kAllMjcfElements, tag); }

// ---- docs/mjcf-subset.md -------------------------------------------------------------------

namespace {

const char* const kIntroduction = R"(# The MJCF subset lever reads

Generated from the schema table in `mjcf_lite/src/schema.cpp` by `lever model --schema`;
do not edit by hand. To regenerate:

    build/tools/lever/lever model --schema > docs/mjcf-subset.md

`lever::mjcf::load_file()` reads this subset of MJCF and compiles it the way MuJoCo 2.2.2 does
(defaults and classes, frames, orientation forms, inertia inferred from geoms, joint and motor
wiring), so that every compiled number agrees with MuJoCo's to 1e-12. Anything else is refused
with an error that names it and says whether it is valid MJCF that lever does not support or not
MJCF at all (with a suggestion for typos). Nothing is silently ignored.

## Deliberate differences from MuJoCo 2.2.2

* `compiler/autolimits` defaults to `true`, as in MuJoCo 3: a `range` alone makes a joint
  limited, a `ctrlrange` alone makes a motor control-limited.
* Refused although MuJoCo 2.2.2 accepts them (they are almost certainly mistakes):
  * non-finite numbers (`nan`, `inf`) in any attribute;
  * `option/timestep` that is zero or negative;
  * a number list that ends in a blank with fewer numbers than the maximum, e.g. `pos="1 2 "`
    (MuJoCo 2.2.2 reads the last number twice and loads `1 2 2`);
  * a quaternion of (near) zero length, e.g. `quat="0 0 0 0"` (MuJoCo stores it unnormalized);
  * an integer attribute that is not a whole integer, e.g. `group="1.7"` (MuJoCo reads 1);
  * a negative `mass`, `density` or inertia anywhere (MuJoCo clamps some to 0 silently);
  * a `compiler/eulerseq` with letters other than x, y, z, X, Y, Z, even if no `euler` uses it;
  * two default classes with the same name, also when a top-level `<default class=...>`
    renames the main class;
  * text inside an element (MuJoCo ignores it);
  * finite numbers whose compiled result overflows (e.g. a `fromto` of 1e308);
  * a negative `kp` or `kv` on `<position>`, `<velocity>` or `<intvelocity>` (a servo that
    pushes away from its target, or a damper that feeds energy in);
  * `option/impratio` that is zero or negative, a negative `option/iterations` or
    `option/tolerance`, and `size/nconmax` or `size/njmax` below -1 (MuJoCo reads any negative
    value as the default).
* Refused because lever does not have them: `option/noslip_iterations` above 0 (no noslip solver),
  `geom/type="hfield"`.
* Every `option/flag` of MuJoCo 2.2.2, as `model.opt.disableflags` and `enableflags` (mjtDisableBit's
  and mjtEnableBit's bits), honoured where MuJoCo reads each (docs/contact.md, "Option flags"), with
  `override`'s `option/o_margin`, `o_solref` and `o_solimp`.
* `<sensor><user>`: a sensor whose numbers `Model::sensor_callback` writes (MuJoCo's
  `mjcb_sensor`), with its own `dim`, `datatype`, `needstage` and object; without a callback its
  numbers stay zero, as MuJoCo leaves them. The rangefinder's ray meets meshes triangle by
  triangle (MuJoCo's `mj_rayMesh`); a model with a rangefinder has every mesh read.
* `<include file="..."/>` anywhere: the included file's root element (of any tag; its
  attributes are ignored) is dropped and its children take the `<include>`'s place, their own
  includes expanded in turn, as MuJoCo 2.2.2 does before it reads a model. Paths are relative to
  the folder of the main model file, in nested includes too (2.2.2 never changes that folder; an
  error says so when the path was meant from the including file's folder), and
  `compiler/meshdir` applies to the merged model, relative to the main file's folder. A file
  included twice (so a cycle), an `<include>` with children or an included file with nothing in
  its root is an error, as in 2.2.2; an error inside an included file names that file and its
  line. (`compiler/assetdir` is MuJoCo 3's, and refused.)
* MuJoCo 3's names that real model files carry, with MuJoCo 3's meaning (MuJoCo 2.2.2 refuses
  them): `<position kv>` (biasprm[2] = -kv; an element without kv takes its class's kv: lever
  clears the rest of a `<position>`'s biasprm as 2.2.2 does, where MuJoCo 3 keeps its class's, so
  the two differ only for a `<position>` without kv whose class's actuator default leaves
  biasprm[0] or biasprm[2] nonzero: a `<velocity>`, or a `<general>` that sets them) and `<position inheritrange>` (ctrlrange = the joint's compiled range about its middle,
  scaled; refused beside a ctrlrange or on a joint without a range, as MuJoCo 3 refuses it), and
  `option/integrator="implicitfast"` (MuJoCo 3's integrator: implicit in the joint damping and
  the actuators' velocity terms only, its matrix factored as M is). Other
  names MuJoCo 3 added (`dampratio`, `timeconst`, `actearly`, `gravcomp`,
  `actuatorfrcrange`, `assetdir`, `<replicate>`, `<frame>`, `<plugin>`, ...) are refused by name.
* `<composite>` (every type of MuJoCo 2.2.2: particle, grid, rope, loop, cloth, box, cylinder,
  ellipsoid) is expanded as 2.2.2 expands it, before compilation, into the bodies, joints, geoms,
  sites, tendons, equality constraints and contact exclusions it stands for, named as MuJoCo
  names them (prefix + `B`, `J`, `JT`, `JS`, `G`, `S`, `T`, `TS` ... and the indices), with
  MuJoCo's built-in defaults as 2.2.2 adjusts them per type (never the model's classes); the
  tendons, constraints and exclusions it makes come before the model's own. The `<skin>` MuJoCo
  builds over a composite is drawn only: lever has no skin arrays and builds none; `<skin>` and
  its attributes (`texcoord`, `material`, `subgrid`, ...) are checked as 2.2.2 checks them and
  refuse nothing. As in 2.2.2, `limited` on a composite's `<joint>` or `<tendon>` is read and
  ignored.
* `option/jacobian` (`dense`, `sparse`, `auto`: sparse from 60 dofs on) chooses MuJoCo's layout
  of the constraint Jacobian, and with it the order in which MuJoCo sums each product with a row
  (J qvel, and the PGS solver's products with J M^-1 J^T); lever keeps its own layout whatever it
  says, and sums those products in the order MuJoCo's layout sums them, so that their last bits
  are MuJoCo's.
* Kept, changing no dynamics: `<asset>` (`<mesh>`, `<material>`, `<texture>`), `<light>`,
  `<camera>`, `<visual>`, `<statistic>`, `compiler/meshdir` and `texturedir`, and geom
  `material`, `rgba`, `group`. Their names are in `Model::visual`.
* Mesh geoms: lever reads a mesh file only when a mesh geom must give its body mass (the body
  has no `<inertial>`, or `inertiafromgeom="true"`, and the geom's group is in
  `inertiagrouprange`) or can collide (`contype` or `conaffinity` not 0). Then it computes what MuJoCo 2.2.2 does (its float vertices and
  roundings included): `refpos`, `refquat`, `scale`, the volume and centre of mass from face
  pyramids (`exactmeshinertia`), the inertia at the geom density of the mesh's class, the
  principal axes, the geom's frame moved to them, its size the bounding box, its mass from
  `density` or `mass`. It reads binary STL and OBJ (`v` and `f` lines: triangles and convex
  quadrilaterals, one group); ASCII STL, MSH, OBJ faces of more than four vertices, an OBJ
  without faces (MuJoCo would take the convex hull) and inline `vertex`/`face` meshes are
  refused by name, and so is a missing, unreadable or degenerate file, with a message naming
  the geom, the mesh and the file and saying to add `<inertial>` (for a mesh read only to
  collide, a warning: its pairs are skipped). For collision it keeps the vertices and, unless
  `convexhull="false"`, the graph of their convex hull, built with qhull from the vertices as
  read, as MuJoCo 2.2.2 does (a mesh qhull cannot hull, a flat one, is refused as MuJoCo refuses
  it). Other mesh geoms are massless
  in lever and keep their frame as written and their size zero, where MuJoCo moves the frame to
  the mesh's centre and principal axes and sizes it from the file; nothing in the dynamics uses
  either. A geom of another type with `mesh=` (fitted to the mesh by MuJoCo) is refused.
* Contacts: the geoms' contact parameters, `<contact><pair>` and `<exclude>` compile to
  MuJoCo 2.2.2's `geom_*`, `pair_*` and `exclude_signature` arrays (a `<pair>` takes what it does
  not write from its class, never from its two geoms, as 2.2.2 does). lever collides every pair
  of geom types MuJoCo 2.2.2 collides (cylinders, ellipsoids and meshes by MuJoCo's MPR, with
  `option/mpr_tolerance`, `mpr_iterations` and `flag/multiccd`; docs/contact.md). A geom
  pair that can collide (compatible `contype`/`conaffinity`, bodies neither welded together nor
  parent and child nor excluded, or named by a `<pair>`) but that lever cannot compute (a mesh
  whose file lever did not read) is named in a warning at load (`Model::warnings`, printed by
  the command line) with what to use instead. The WebAssembly build (the lab page) collides the
  same pairs (MPR is lever's own); it has no qhull, so there a mesh that can collide is refused.

Value rules: numbers are decimal (`1`, `-.5`, `1e-3`); a list must have the stated count
("1-3" marks a partial vector whose missing numbers keep the class's values); keywords are
case-sensitive. Names are unique per kind (body, joint, geom, site, actuator, keyframe, mesh,
material).

)";

const char* multiplicity_text(char m) {
  switch (m) {
    case '!': return "exactly one";
    case '?': return "at most one";
    default: return "any number";
  }
}

std::string value_text(const AttributeRule& a) {
  switch (a.kind) {
    case ValueKind::kReal:
      if (a.count == 1) return "real";
      return (a.partial || a.list ? "1-" : "") + std::to_string(a.count) + " reals";
    case ValueKind::kInteger:
      return a.count == 1 ? "integer" : std::to_string(a.count) + " integers";
    case ValueKind::kKeyword: {
      std::string s;
      for (const std::string_view w : words(a.keywords))
        s += (s.empty() ? "" : " \\| ") + std::string(w);
      return s;
    }
    case ValueKind::kEulerSeq: return "3 of xyzXYZ";
    case ValueKind::kText: return "text";
  }
  return "";
}

std::string code_list(std::string_view list, std::string_view open, std::string_view close) {
  std::string s;
  for (const std::string_view w : words(list)) {
    s += (s.empty() ? "" : ", ") + std::string(open) + std::string(w) + std::string(close);
  }
  return s;
}

void describe(std::ostringstream& md, const ElementRule& e) {
  md << "## `<" << e.tag << ">`";
  if (!e.parent.empty()) md << " in `<" << e.parent << ">`";
  md << " (" << multiplicity_text(e.multiplicity) << ")\n\n";
  // the meaning as a sentence
  if (!e.meaning.empty()) {
    md << static_cast<char>(std::toupper(static_cast<unsigned char>(e.meaning[0])))
       << e.meaning.substr(1) << ".\n\n";
  }
  if (!e.attributes.empty()) {
    md << "| attribute | value | default | meaning |\n|---|---|---|---|\n";
    for (const AttributeRule& a : e.attributes) {
      md << "| `" << a.name << "` | " << value_text(a) << " | ";
      if (a.required) {
        md << "required";
      } else if (a.default_value.empty()) {
        md << "unset";
      } else {
        md << "`" << a.default_value << "`";
      }
      md << " | " << a.meaning;
      if (!a.unsupported_keywords.empty()) {
        md << "; refused: " << code_list(a.unsupported_keywords, "`", "`");
      }
      md << " |\n";
    }
    md << "\n";
  }
  std::vector<std::string_view> children;
  for (const ElementRule& c : schema()) {
    // rules are keyed by the parent's tag: a composite's <tendon> is not a section's
    if (e.parent == "composite") break;
    if (c.parent == e.tag && std::find(children.begin(), children.end(), c.tag) == children.end()) {
      children.push_back(c.tag);
    }
  }
  for (size_t i = 0; i < children.size(); ++i) {
    md << (i == 0 ? "Children: `<" : ", `<") << children[i] << ">`";
  }
  if (!children.empty()) md << ".\n\n";
  if (!e.unsupported_attributes.empty() || !e.unsupported_children.empty()) {
    md << "Valid MJCF that lever refuses:";
    if (!e.unsupported_attributes.empty()) {
      md << " attributes " << code_list(e.unsupported_attributes, "`", "`");
    }
    if (!e.unsupported_children.empty()) {
      md << (e.unsupported_attributes.empty() ? "" : ";") << " elements "
         << code_list(e.unsupported_children, "`<", ">`");
    }
    md << ".\n\n";
  }
}

}  // namespace

std::string markdown() {
  std::ostringstream md;
  md << kIntroduction;
  for (const ElementRule& e : schema()) describe(md, e);
  std::string out = md.str();
  while (out.size() > 1 && out[out.size() - 1] == '\n' && out[out.size() - 2] == '\n') {
    out.pop_back();
  }
  return out;
}

}  // namespace lever::mjcf::detail
