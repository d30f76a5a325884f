// The bad-input corpus: MJCF texts that must each be refused with one ParseError that names the
// line, element and attribute, with a key phrase of the problem. tests/mjcf checks lever's error;
// tests/compile checks what MuJoCo 2.2.2 does with the same text (`mujoco` column).
//
// Every text starts on the line of <mujoco>, so `line` counts from it.
#pragma once

namespace lever::test {

/// What MuJoCo 2.2.2 does with a bad input.
enum class MuJoCo {
  kRejects,  ///< it refuses it too
  kAccepts,  ///< it loads it; lever refuses on purpose (see `why`)
};

struct BadInput {
  const char* id;
  const char* xml;
  int line;               ///< 0: the error has no line (empty input)
  const char* element;    ///< "" when the problem is the XML itself
  const char* attribute;  ///< "" when the element as a whole is at fault
  const char* phrase;     ///< must appear in the message
  MuJoCo mujoco;
  const char* why;  ///< for kAccepts: why lever refuses what MuJoCo 2.2.2 accepts
};

// clang-format off
inline const BadInput kBadInputs[] = {
  // ---- malformed XML (tinyxml2's line: the element left open) -----------------------------
  {"xml-unclosed", R"(<mujoco>
  <worldbody>
    <body name="b">
  </worldbody>
</mujoco>)", 3, "", "", "malformed XML", MuJoCo::kRejects, ""},
  {"xml-empty", "", 0, "", "", "empty", MuJoCo::kRejects, ""},
  {"xml-text-only", "this is not xml", 1, "", "", "malformed XML", MuJoCo::kRejects, ""},
  {"xml-repeated-attribute", R"(<mujoco>
  <worldbody>
    <geom size="0.1" size="0.2"/>
  </worldbody>
</mujoco>)", 3, "", "", "cannot read an attribute", MuJoCo::kRejects, ""},
  {"root-not-mujoco", R"(<model>
</model>)", 1, "model", "", "root element must be <mujoco>", MuJoCo::kRejects, ""},

  // ---- not MJCF: unknown elements and attributes, with suggestions -------------------------
  {"unknown-element", R"(<mujoco>
  <worldbody>
    <body name="b">
      <bodyy/>
    </body>
  </worldbody>
</mujoco>)", 4, "bodyy", "", "did you mean 'body'?", MuJoCo::kRejects, ""},
  {"unknown-attribute", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="elbow" rnage="-1 1"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
</mujoco>)", 4, "joint", "rnage", "unknown attribute 'rnage' (did you mean 'range'?)",
   MuJoCo::kRejects, ""},
  {"unknown-attribute-on-body", R"(<mujoco>
  <worldbody>
    <body name="b" class="x">
      <geom size="0.1"/>
    </body>
  </worldbody>
</mujoco>)", 3, "body", "class", "unknown attribute 'class'", MuJoCo::kRejects, ""},
  {"name-inside-default", R"(<mujoco>
  <default>
    <joint name="j"/>
  </default>
</mujoco>)", 3, "joint", "name", "not allowed on <joint> inside <default>", MuJoCo::kRejects, ""},
  {"joint-inside-default-motor", R"(<mujoco>
  <default>
    <motor joint="j"/>
  </default>
</mujoco>)", 3, "motor", "joint", "not allowed on <motor> inside <default>", MuJoCo::kRejects,
   ""},
  {"joint-in-worldbody", R"(<mujoco>
  <worldbody>
    <joint name="j"/>
  </worldbody>
</mujoco>)", 3, "joint", "", "the world body cannot move", MuJoCo::kRejects, ""},
  {"worldbody-attribute", R"(<mujoco>
  <worldbody name="w">
  </worldbody>
</mujoco>)", 2, "worldbody", "name", "takes no attributes", MuJoCo::kRejects, ""},
  {"two-inertials", R"(<mujoco>
  <worldbody>
    <body name="b">
      <inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/>
      <inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/>
    </body>
  </worldbody>
</mujoco>)", 5, "inertial", "", "only one <inertial>", MuJoCo::kRejects, ""},
  {"body-at-top-level", R"(<mujoco>
  <body name="b"/>
</mujoco>)", 2, "body", "", "it belongs in <worldbody> or <body>", MuJoCo::kRejects, ""},

  // ---- valid MJCF that lever does not support ------------------------------------------------
  {"unsupported-element", R"(<mujoco>
  <custom/>
</mujoco>)", 2, "custom", "", "valid MJCF but not supported by lever", MuJoCo::kAccepts,
   "valid MJCF outside lever's subset"},
  {"unsupported-attribute", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j" springdamper="0.1 1"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
</mujoco>)", 4, "joint", "springdamper", "valid MJCF but not supported by lever",
   MuJoCo::kAccepts, "valid MJCF outside lever's subset"},
  {"unsupported-limited-ball", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j" type="ball" limited="true" range="0 30"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
</mujoco>)", 4, "joint", "limited", "lever does not limit ball joints yet", MuJoCo::kAccepts,
   "valid MJCF outside lever's subset"},
  {"unsupported-geom-type", R"(<mujoco>
  <asset><hfield name="h" nrow="2" ncol="2" size="1 1 1 0.1"/></asset>
  <worldbody>
    <geom type="hfield" hfield="h"/>
  </worldbody>
</mujoco>)", 2, "hfield", "", "valid MJCF but not supported by lever", MuJoCo::kAccepts,
   "valid MJCF outside lever's subset"},
  {"unsupported-geom-type-hfield", R"(<mujoco>
  <default><geom type="hfield"/></default>
</mujoco>)", 2, "geom", "type", "lever has no height fields: model the ground with a plane",
   MuJoCo::kAccepts, "valid MJCF outside lever's subset"},

  // ---- contact --------------------------------------------------------------------
  {"contact-geom-condim-2", R"(<mujoco>
  <worldbody>
    <geom size="0.1" condim="2"/>
  </worldbody>
</mujoco>)", 3, "geom", "condim", "MuJoCo has no condim 2", MuJoCo::kRejects, ""},
  {"contact-pair-condim-5", R"(<mujoco>
  <worldbody>
    <geom name="a" size="0.1"/>
    <body><joint/><geom name="b" size="0.1"/></body>
  </worldbody>
  <contact>
    <pair geom1="a" geom2="b" condim="5"/>
  </contact>
</mujoco>)", 7, "pair", "condim", "MuJoCo has no condim 5", MuJoCo::kRejects, ""},
  {"contact-pair-unknown-geom", R"(<mujoco>
  <worldbody>
    <geom name="floor" type="plane" size="1 1 0.1"/>
    <body><joint/><geom name="ball" size="0.1"/></body>
  </worldbody>
  <contact>
    <pair geom1="floor"
          geom2="bal"/>
  </contact>
</mujoco>)", 8, "pair", "geom2", "unknown geom 'bal' (did you mean 'ball'?)", MuJoCo::kRejects,
   ""},
  {"contact-pair-in-default-with-geom", R"(<mujoco>
  <default><pair geom1="a"/></default>
</mujoco>)", 2, "pair", "geom1", "attribute 'geom1' is not allowed on <pair> inside <default>", MuJoCo::kRejects, ""},
  {"contact-exclude-unknown-body", R"(<mujoco>
  <worldbody>
    <body name="hand"><joint/><geom size="0.1"/></body>
  </worldbody>
  <contact>
    <exclude body1="hand" body2="hnd"/>
  </contact>
</mujoco>)", 6, "exclude", "body2", "unknown body 'hnd' (did you mean 'hand'?)",
   MuJoCo::kRejects, ""},
  {"contact-exclude-missing-body", R"(<mujoco>
  <contact>
    <exclude body1="world"/>
  </contact>
</mujoco>)", 3, "exclude", "body2", "required", MuJoCo::kRejects, ""},
  {"contact-plane-in-moving-body", R"(<mujoco>
  <worldbody>
    <body name="tray"><joint type="slide"/><geom size="0.1"/>
      <body name="lid"><geom type="plane" size="1 1 0.1"/></body>
    </body>
  </worldbody>
</mujoco>)", 4, "geom", "type", "body 'lid' moves (it or a parent has a joint): use a box",
   MuJoCo::kRejects, ""},
  {"contact-plane-no-spacing", R"(<mujoco>
  <worldbody>
    <geom type="plane" size="1 1"/>
  </worldbody>
</mujoco>)", 3, "geom", "size", "a plane needs a positive third size", MuJoCo::kRejects, ""},
  {"contact-plane-fromto", R"(<mujoco>
  <worldbody>
    <geom type="plane" size="1 1 1" fromto="0 0 0 1 0 0"/>
  </worldbody>
</mujoco>)", 3, "geom", "fromto", "not a plane", MuJoCo::kRejects, ""},
  {"contact-noslip", R"(<mujoco>
  <option noslip_iterations="3"/>
</mujoco>)", 2, "option", "noslip_iterations", "lever has no noslip solver", MuJoCo::kAccepts,
   "lever has no noslip solver"},
  {"flag-unknown-word", R"(<mujoco>
  <option>
    <flag override="on"/>
  </option>
</mujoco>)", 3, "flag", "override", "expected 'disable' or 'enable'", MuJoCo::kRejects, ""},
  {"contact-cone-unknown", R"(<mujoco>
  <option cone="eliptic"/>
</mujoco>)", 2, "option", "cone", "expected 'pyramidal' or 'elliptic' (did you mean 'elliptic'?)",
   MuJoCo::kRejects, ""},
  {"shellinertia-not-a-mesh", R"(<mujoco>
  <worldbody><body><joint/><geom type="box" size="0.1 0.1 0.1" shellinertia="true"/></body></worldbody>
</mujoco>)", 2, "geom", "shellinertia", "applies to mesh geoms only", MuJoCo::kRejects, ""},
  {"contact-mpr-iterations-negative", R"(<mujoco>
  <option mpr_iterations="-1"/>
</mujoco>)", 2, "option", "mpr_iterations", "must not be negative", MuJoCo::kAccepts,
   "a negative count of MPR iterations is a mistake"},
  {"fluid-viscosity-negative", R"(<mujoco>
  <option viscosity="-0.1"/>
</mujoco>)", 2, "option", "viscosity", "must not be negative", MuJoCo::kAccepts,
   "a negative viscosity drives the bodies instead of dragging them"},
  {"fluid-density-negative", R"(<mujoco>
  <option density="-1000"/>
</mujoco>)", 2, "option", "density", "must not be negative", MuJoCo::kAccepts,
   "a negative density drives the bodies instead of dragging them"},
  {"fluid-wind-two-numbers", R"(<mujoco>
  <option wind="1 2"/>
</mujoco>)", 2, "option", "wind", "has 2 numbers; expected 3 numbers", MuJoCo::kRejects, ""},
  {"user-not-a-number", R"(<mujoco>
  <worldbody><body><joint user="1 two"/><geom size="0.1"/></body></worldbody>
</mujoco>)", 2, "joint", "user", "'two' is not a number", MuJoCo::kRejects, ""},
  {"user-longer-than-nuser", R"(<mujoco>
  <size nuser_actuator="1"/>
  <worldbody><body><joint name="j"/><geom size="0.1"/></body></worldbody>
  <actuator><motor joint="j" user="1 2"/></actuator>
</mujoco>)", 4, "motor", "user", "more than <size nuser_actuator=\"1\">", MuJoCo::kRejects, ""},
  {"user-longer-than-nuser-tendon", R"(<mujoco>
  <size nuser_tendon="1"/>
  <worldbody><body><joint name="j"/><geom size="0.1"/></body></worldbody>
  <tendon><fixed user="1 2"><joint joint="j" coef="1"/></fixed></tendon>
</mujoco>)", 4, "fixed", "user", "more than <size nuser_tendon=\"1\">", MuJoCo::kRejects, ""},
  {"user-nuser-below-minus-one", R"(<mujoco>
  <size nuser_body="-2"/>
</mujoco>)", 2, "size", "nuser_body", "must be -1", MuJoCo::kRejects, ""},
  {"contact-impratio-zero", R"(<mujoco>
  <option impratio="0"/>
</mujoco>)", 2, "option", "impratio", "must be positive", MuJoCo::kAccepts,
   "a zero impratio divides by zero in the elliptic cone's impedance"},
  {"contact-nconmax-below-minus-one", R"(<mujoco>
  <size nconmax="-5"/>
</mujoco>)", 2, "size", "nconmax", "must be -1 (MuJoCo's default) or a count >= 0",
   MuJoCo::kAccepts, "MuJoCo reads any negative count as its default; -5 is a mistake"},
  {"option-o-solref-three-numbers", R"(<mujoco>
  <option o_solref="0.02 1 3"/>
</mujoco>)", 2, "option", "o_solref", "expected", MuJoCo::kRejects, ""},
  {"unsupported-global-coordinates", R"(<mujoco>
  <compiler coordinate="global"/>
</mujoco>)", 2, "compiler", "coordinate", "'global' is valid MJCF but not supported",
   MuJoCo::kAccepts, "valid MJCF outside lever's subset (removed in MuJoCo 2.3.4)"},
  {"nested-freejoint", R"(<mujoco>
  <worldbody>
    <body name="a">
      <joint name="hinge"/>
      <geom size="0.1"/>
      <body name="b">
        <freejoint/>
        <geom size="0.1"/>
      </body>
    </body>
  </worldbody>
</mujoco>)", 7, "freejoint", "", "can only move a body directly inside <worldbody>",
   MuJoCo::kRejects, ""},
  {"free-joint-with-another", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="hinge"/>
      <joint name="float" type="free"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
</mujoco>)", 5, "joint", "type", "must be its body's only joint", MuJoCo::kRejects, ""},
  // ---- the shortcuts with state or their own transmission: MuJoCo 2.2.2's reader's rules -----
  {"damper-without-ctrlrange", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <actuator>
    <damper joint="j" kv="1"/>
  </actuator>
</mujoco>)", 9, "damper", "ctrlrange", "missing required attribute 'ctrlrange'",
   MuJoCo::kRejects, ""},
  {"damper-negative-ctrlrange", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <actuator>
    <damper joint="j" kv="1"
            ctrlrange="-1 1"/>
  </actuator>
</mujoco>)", 10, "damper", "ctrlrange", "damper control range cannot be negative",
   MuJoCo::kRejects, ""},
  {"damper-default-without-ctrlrange", R"(<mujoco>
  <default>
    <damper kv="2"/>
  </default>
</mujoco>)", 3, "damper", "ctrlrange", "missing required attribute 'ctrlrange'",
   MuJoCo::kRejects, ""},
  {"damper-ctrllimited", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <actuator>
    <damper joint="j" ctrlrange="0 1" ctrllimited="false"/>
  </actuator>
</mujoco>)", 9, "damper", "ctrllimited", "unknown attribute 'ctrllimited'", MuJoCo::kRejects,
   ""},
  {"damper-negative-kv", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <actuator>
    <damper joint="j" ctrlrange="0 1" kv="-2"/>
  </actuator>
</mujoco>)", 9, "damper", "kv", "must not be negative", MuJoCo::kRejects, ""},
  {"intvelocity-without-actrange", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <actuator>
    <intvelocity joint="j" kp="3"/>
  </actuator>
</mujoco>)", 9, "intvelocity", "actrange",
   "with <intvelocity> (always actlimited) the actrange needs lower < upper", MuJoCo::kRejects, ""},
  {"cylinder-bias-two-numbers", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <actuator>
    <cylinder joint="j" bias="1 2"/>
  </actuator>
</mujoco>)", 9, "cylinder", "bias", "3", MuJoCo::kRejects, ""},
  {"adhesion-negative-gain", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <actuator>
    <adhesion body="b" ctrlrange="0 1" gain="-1"/>
  </actuator>
</mujoco>)", 9, "adhesion", "gain", "adhesion gain cannot be negative", MuJoCo::kRejects, ""},
  {"adhesion-negative-ctrlrange", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <actuator>
    <adhesion body="b" ctrlrange="-1 0"/>
  </actuator>
</mujoco>)", 9, "adhesion", "ctrlrange", "adhesion control range cannot be negative",
   MuJoCo::kRejects, ""},
  {"adhesion-empty-ctrlrange", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <actuator>
    <adhesion body="b" ctrlrange="0 0"/>
  </actuator>
</mujoco>)", 9, "adhesion", "ctrlrange",
   "with <adhesion> (always ctrllimited) the ctrlrange needs lower < upper", MuJoCo::kRejects, ""},
  {"adhesion-unknown-body", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <actuator>
    <adhesion body="c" ctrlrange="0 1"/>
  </actuator>
</mujoco>)", 9, "adhesion", "body", "unknown body 'c'", MuJoCo::kRejects, ""},
  {"adhesion-with-joint", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <actuator>
    <adhesion body="b" joint="j" ctrlrange="0 1"/>
  </actuator>
</mujoco>)", 9, "adhesion", "joint", "unknown attribute 'joint'", MuJoCo::kRejects, ""},
  {"general-body-and-joint", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <actuator>
    <general body="b" joint="j"/>
  </actuator>
</mujoco>)", 9, "general", "body", "names both joint and body", MuJoCo::kRejects, ""},

  // ---- number lists ------------------------------------------------------------------------
  {"too-few-numbers", R"(<mujoco>
  <worldbody>
    <geom size="0.1" pos="1 2"/>
  </worldbody>
</mujoco>)", 3, "geom", "pos", "has 2 numbers; expected 3", MuJoCo::kRejects, ""},
  {"too-many-numbers", R"(<mujoco>
  <worldbody>
    <geom size="0.1" pos="1 2 3 4"/>
  </worldbody>
</mujoco>)", 3, "geom", "pos", "has 4 numbers; expected 3", MuJoCo::kRejects, ""},
  {"too-many-sizes", R"(<mujoco>
  <worldbody>
    <geom type="box" size="0.1 0.1 0.1 0.1"/>
  </worldbody>
</mujoco>)", 3, "geom", "size", "expected 1 to 3 numbers", MuJoCo::kRejects, ""},
  {"range-one-number", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j" range="1"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
</mujoco>)", 4, "joint", "range", "has 1 number; expected 2", MuJoCo::kRejects, ""},
  {"not-a-number", R"(<mujoco>
  <worldbody>
    <geom size="0.1" pos="a b c"/>
  </worldbody>
</mujoco>)", 3, "geom", "pos", "'a' is not a number", MuJoCo::kRejects, ""},
  {"commas", R"(<mujoco>
  <worldbody>
    <geom size="0.1" pos="1,2,3"/>
  </worldbody>
</mujoco>)", 3, "geom", "pos", "'1,2,3' is not a number", MuJoCo::kRejects, ""},
  {"empty-value", R"(<mujoco>
  <worldbody>
    <geom size="0.1" pos=""/>
  </worldbody>
</mujoco>)", 3, "geom", "pos", "is empty", MuJoCo::kRejects, ""},
  {"overflow", R"(<mujoco>
  <option timestep="1e400"/>
</mujoco>)", 2, "option", "timestep", "too large", MuJoCo::kRejects, ""},
  {"nan", R"(<mujoco>
  <worldbody>
    <geom size="0.1" pos="nan 0 0"/>
  </worldbody>
</mujoco>)", 3, "geom", "pos", "'nan' is not a finite number", MuJoCo::kAccepts,
   "MuJoCo stores the NaN and only prints a warning"},
  {"infinity", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j" damping="inf"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
</mujoco>)", 4, "joint", "damping", "'inf' is not a finite number", MuJoCo::kAccepts,
   "MuJoCo stores the infinity"},
  {"trailing-blank-exact", R"(<mujoco>
  <worldbody>
    <geom size="0.1" pos="1 2 "/>
  </worldbody>
</mujoco>)", 3, "geom", "pos", "ends in a blank", MuJoCo::kAccepts,
   "MuJoCo 2.2.2 reads the last number twice and loads pos (1, 2, 2)"},
  {"trailing-blank-partial", R"(<mujoco>
  <worldbody>
    <geom type="capsule" size="0.1 "/>
  </worldbody>
</mujoco>)", 3, "geom", "size", "ends in a blank", MuJoCo::kAccepts,
   "MuJoCo 2.2.2 reads the last number twice and makes a capsule of half-length 0.1"},
  {"integer-with-fraction", R"(<mujoco>
  <worldbody>
    <geom size="0.1" group="1.7"/>
  </worldbody>
</mujoco>)", 3, "geom", "group", "'1.7' is not an integer", MuJoCo::kAccepts,
   "MuJoCo reads integers with sscanf(\"%d\") and loads group 1"},
  {"integer-not-a-number", R"(<mujoco>
  <worldbody>
    <geom size="0.1" contype="abc"/>
  </worldbody>
</mujoco>)", 3, "geom", "contype", "'abc' is not an integer", MuJoCo::kRejects, ""},

  // ---- keywords --------------------------------------------------------------------------------
  {"bad-joint-type", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j" type="hing"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
</mujoco>)", 4, "joint", "type", "invalid value 'hing' for attribute 'type'; expected 'hinge', "
   "'slide', 'ball' or 'free' (did you mean 'hinge'?)", MuJoCo::kRejects, ""},
  {"bad-boolean", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j" limited="yes" range="0 1"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
</mujoco>)", 4, "joint", "limited", "invalid value 'yes'", MuJoCo::kRejects, ""},
  {"bad-angle-unit", R"(<mujoco>
  <compiler angle="deg"/>
</mujoco>)", 2, "compiler", "angle", "did you mean 'degree'?", MuJoCo::kRejects, ""},
  {"keyword-case", R"(<mujoco>
  <option integrator="rk4"/>
</mujoco>)", 2, "option", "integrator", "did you mean 'RK4'?", MuJoCo::kRejects, ""},
  {"eulerseq-length", R"(<mujoco>
  <compiler eulerseq="xy"/>
</mujoco>)", 2, "compiler", "eulerseq", "3 letters", MuJoCo::kRejects, ""},
  {"eulerseq-letter-unused", R"(<mujoco>
  <compiler eulerseq="xya"/>
</mujoco>)", 2, "compiler", "eulerseq", "3 letters", MuJoCo::kAccepts,
   "MuJoCo checks the letters only when an euler angle is converted"},

  // ---- required attributes and references ----------------------------------------------------
  {"motor-without-joint", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <actuator>
    <motor name="m"/>
  </actuator>
</mujoco>)", 9, "motor", "joint", "the actuator names no joint or tendon", MuJoCo::kRejects, ""},
  {"motor-unknown-joint", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="elbow"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <actuator>
    <motor name="m" joint="elbw"/>
  </actuator>
</mujoco>)", 9, "motor", "joint", "unknown joint 'elbw' (did you mean 'elbow'?)",
   MuJoCo::kRejects, ""},
  {"inertial-without-mass", R"(<mujoco>
  <worldbody>
    <body name="b">
      <inertial pos="0 0 0" diaginertia="1 1 1"/>
    </body>
  </worldbody>
</mujoco>)", 4, "inertial", "mass", "missing required attribute 'mass'", MuJoCo::kRejects, ""},
  {"unknown-class", R"(<mujoco>
  <default>
    <default class="arm"/>
  </default>
  <worldbody>
    <geom class="amr" size="0.1"/>
  </worldbody>
</mujoco>)", 6, "geom", "class", "unknown default class 'amr' (did you mean 'arm'?)",
   MuJoCo::kRejects, ""},
  {"unknown-childclass", R"(<mujoco>
  <worldbody>
    <body name="b" childclass="nosuch">
      <geom size="0.1"/>
    </body>
  </worldbody>
</mujoco>)", 3, "body", "childclass", "unknown default class 'nosuch'", MuJoCo::kRejects, ""},
  {"class-defined-twice", R"(<mujoco>
  <default>
    <default class="a"/>
    <default class="a"/>
  </default>
</mujoco>)", 4, "default", "class", "defined twice", MuJoCo::kRejects, ""},
  {"nested-class-without-name", R"(<mujoco>
  <default>
    <default>
    </default>
  </default>
</mujoco>)", 3, "default", "class", "missing required attribute 'class'", MuJoCo::kRejects, ""},

  // ---- names ---------------------------------------------------------------------------------
  {"duplicate-joint-name", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <joint name="j" axis="0 1 0"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
</mujoco>)", 5, "joint", "name", "duplicate joint name 'j' (also at line 4)", MuJoCo::kRejects,
   ""},
  {"duplicate-body-name", R"(<mujoco>
  <worldbody>
    <body name="b">
      <geom size="0.1"/>
    </body>
    <body name="b">
      <geom size="0.1"/>
    </body>
  </worldbody>
</mujoco>)", 6, "body", "name", "duplicate body name 'b'", MuJoCo::kRejects, ""},
  {"body-named-world", R"(<mujoco>
  <worldbody>
    <body name="world">
      <geom size="0.1"/>
    </body>
  </worldbody>
</mujoco>)", 3, "body", "name", "it names the world body", MuJoCo::kRejects, ""},

  // ---- mass and inertia ----------------------------------------------------------------------
  {"negative-mass", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <inertial pos="0 0 0" mass="-1" diaginertia="1 1 1"/>
    </body>
  </worldbody>
</mujoco>)", 5, "inertial", "mass", "must not be negative", MuJoCo::kRejects, ""},
  {"negative-mass-static", R"(<mujoco>
  <worldbody>
    <body name="b">
      <inertial pos="0 0 0" mass="-1" diaginertia="1 1 1"/>
    </body>
  </worldbody>
</mujoco>)", 4, "inertial", "mass", "must not be negative", MuJoCo::kAccepts,
   "MuJoCo clamps the mass of a static body to 0 (boundmass) without a word"},
  {"zero-mass-moving", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <inertial pos="0 0 0" mass="0" diaginertia="1 1 1"/>
    </body>
  </worldbody>
</mujoco>)", 5, "inertial", "mass", "needs positive mass and inertia", MuJoCo::kRejects, ""},
  {"massless-moving-body", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
    </body>
  </worldbody>
</mujoco>)", 3, "body", "", "needs positive mass and inertia", MuJoCo::kRejects, ""},
  {"negative-density", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom size="0.1" density="-1"/>
    </body>
  </worldbody>
</mujoco>)", 5, "geom", "density", "must not be negative", MuJoCo::kRejects, ""},
  {"triangle-inequality", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <inertial pos="0 0 0" mass="1" diaginertia="0.1 0.1 0.5"/>
    </body>
  </worldbody>
</mujoco>)", 5, "inertial", "diaginertia", "triangle inequality", MuJoCo::kRejects, ""},
  {"fullinertia-not-positive", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <inertial pos="0 0 0" mass="1" fullinertia="1 1 1 2 0 0"/>
    </body>
  </worldbody>
</mujoco>)", 5, "inertial", "fullinertia", "not positive definite", MuJoCo::kRejects, ""},

  // ---- servos, keyframes, assets ---------------------------------------------------------------
  {"negative-kp", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <actuator>
    <position joint="j" kp="-10"/>
  </actuator>
</mujoco>)", 9, "position", "kp", "must not be negative", MuJoCo::kAccepts,
   "a negative servo gain pushes away from its target: MuJoCo 2.2.2 loads it without a word"},
  {"negative-position-kv", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <actuator>
    <position joint="j" kp="10" kv="-1"/>
  </actuator>
</mujoco>)", 9, "position", "kv", "must not be negative", MuJoCo::kRejects,
   "MuJoCo 3's kv (2.2.2 has none); MuJoCo 3 refuses a negative one too"},
  {"inheritrange-and-ctrlrange", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j" range="-1 1"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <actuator>
    <position joint="j" ctrlrange="-1 1"
              inheritrange="1"/>
  </actuator>
</mujoco>)", 10, "position", "inheritrange", "ctrlrange and inheritrange cannot both be defined",
   MuJoCo::kRejects, "MuJoCo 3's inheritrange (2.2.2 has none); MuJoCo 3 refuses it so too"},
  {"inheritrange-without-joint-range", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <actuator>
    <position joint="j" inheritrange="1"/>
  </actuator>
</mujoco>)", 9, "position", "inheritrange", "joint 'j' has none", MuJoCo::kRejects,
   "MuJoCo 3's inheritrange (2.2.2 has none); MuJoCo 3 refuses it so too"},
  {"mujoco3-dampratio", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <actuator>
    <position joint="j" dampratio="1"/>
  </actuator>
</mujoco>)", 9, "position", "dampratio", "is MuJoCo 3's: MuJoCo 2.2.2, which lever follows",
   MuJoCo::kRejects, ""},
  {"mujoco3-assetdir", R"(<mujoco>
  <compiler assetdir="assets"/>
</mujoco>)", 2, "compiler", "assetdir", "is MuJoCo 3's: MuJoCo 2.2.2, which lever follows",
   MuJoCo::kRejects, ""},
  {"mujoco3-gravcomp", R"(<mujoco>
  <worldbody>
    <body name="b" gravcomp="1">
      <joint/>
      <geom size="0.1"/>
    </body>
  </worldbody>
</mujoco>)", 3, "body", "gravcomp", "is MuJoCo 3's", MuJoCo::kRejects, ""},
  {"mujoco3-replicate", R"(<mujoco>
  <worldbody>
    <replicate count="2"/>
  </worldbody>
</mujoco>)", 3, "replicate", "", "<replicate> is MuJoCo 3's", MuJoCo::kRejects, ""},
  {"negative-kv-in-default", R"(<mujoco>
  <default>
    <velocity kv="-1"/>
  </default>
</mujoco>)", 3, "velocity", "kv", "must not be negative", MuJoCo::kAccepts,
   "a negative damping gain feeds energy in: MuJoCo 2.2.2 loads it without a word"},
  {"biasprm-too-long", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <actuator>
    <general joint="j" biastype="affine" biasprm="0 -1 -1 0 0 0 0 0 0 0 0"/>
  </actuator>
</mujoco>)", 9, "general", "biasprm", "has 11 numbers", MuJoCo::kRejects, ""},
  {"key-qpos-wrong-size", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <keyframe>
    <key name="home" qpos="0 1"/>
  </keyframe>
</mujoco>)", 9, "key", "qpos", "keyframe qpos has 2 numbers but the model has nq = 1",
   MuJoCo::kRejects, ""},
  {"key-ctrl-wrong-size", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <keyframe>
    <key ctrl="1"/>
  </keyframe>
</mujoco>)", 9, "key", "ctrl", "keyframe ctrl has 1 number but the model has nu = 0",
   MuJoCo::kRejects, ""},
  {"mesh-needed-for-mass", R"(<mujoco>
  <asset>
    <mesh name="link" file="link.stl"/>
  </asset>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom name="shell" type="mesh" mesh="link"/>
    </body>
  </worldbody>
</mujoco>)", 8, "geom", "mesh", "cannot read mesh file 'link.stl'", MuJoCo::kRejects, ""},
  {"mesh-msh-for-mass", R"(<mujoco>
  <asset>
    <mesh name="link" file="link.msh"/>
  </asset>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom name="shell" type="mesh" mesh="link"/>
    </body>
  </worldbody>
</mujoco>)", 8, "geom", "mesh", "is not binary STL or OBJ", MuJoCo::kRejects, ""},
  {"mesh-inline-for-mass", R"(<mujoco>
  <asset>
    <mesh name="tet" vertex="0 0 0  1 0 0  0 1 0  0 0 1"/>
  </asset>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom type="mesh" mesh="tet"/>
    </body>
  </worldbody>
</mujoco>)", 8, "geom", "mesh", "gives its vertices inline", MuJoCo::kAccepts,
   "MuJoCo takes the convex hull of inline vertices (qhull); lever does not compute hulls"},
  {"mesh-refquat-zero", R"(<mujoco>
  <asset>
    <mesh name="link" file="link.stl" refquat="0 0 0 0"/>
  </asset>
</mujoco>)", 3, "mesh", "refquat", "refquat is zero", MuJoCo::kRejects, ""},
  {"mesh-unknown", R"(<mujoco>
  <asset>
    <mesh name="link" file="link.stl"/>
  </asset>
  <worldbody>
    <body name="b">
      <inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/>
      <joint name="j"/>
      <geom type="mesh" mesh="lnk"/>
    </body>
  </worldbody>
</mujoco>)", 9, "geom", "mesh", "unknown mesh 'lnk' (did you mean 'link'?)", MuJoCo::kRejects, ""},
  {"material-unknown", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom size="0.1" material="steel"/>
    </body>
  </worldbody>
</mujoco>)", 5, "geom", "material", "unknown material 'steel'", MuJoCo::kRejects, ""},

  // ---- joints and motors ---------------------------------------------------------------------
  {"range-reversed", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j" range="1 -1"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
</mujoco>)", 4, "joint", "range", "needs range lower < upper", MuJoCo::kRejects, ""},
  {"limited-without-range", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j" limited="true"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
</mujoco>)", 4, "joint", "range", "needs range lower < upper", MuJoCo::kRejects, ""},
  {"range-without-limited-autolimits-off", R"(<mujoco>
  <compiler autolimits="false"/>
  <worldbody>
    <body name="b">
      <joint name="j" range="-1 1"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
</mujoco>)", 5, "joint", "range", "autolimits is false", MuJoCo::kRejects, ""},
  {"zero-axis", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j" axis="0 0 0"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
</mujoco>)", 4, "joint", "axis", "too short", MuJoCo::kRejects, ""},
  {"ctrlrange-reversed", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <actuator>
    <motor joint="j" ctrlrange="1 -1"/>
  </actuator>
</mujoco>)", 9, "motor", "ctrlrange", "needs lower < upper", MuJoCo::kRejects, ""},
  {"timestep-zero", R"(<mujoco>
  <option timestep="0"/>
</mujoco>)", 2, "option", "timestep", "must be positive", MuJoCo::kAccepts,
   "MuJoCo 2.2.2 does not check the timestep"},
  {"timestep-negative", R"(<mujoco>
  <option timestep="-0.001"/>
</mujoco>)", 2, "option", "timestep", "must be positive", MuJoCo::kAccepts,
   "MuJoCo 2.2.2 does not check the timestep"},

  // ---- geoms, sites and orientations ---------------------------------------------------------
  {"geom-without-size", R"(<mujoco>
  <worldbody>
    <geom type="sphere"/>
  </worldbody>
</mujoco>)", 3, "geom", "size", "a sphere needs a positive radius", MuJoCo::kRejects, ""},
  {"capsule-one-size", R"(<mujoco>
  <worldbody>
    <geom type="capsule" size="0.1"/>
  </worldbody>
</mujoco>)", 3, "geom", "size", "a capsule needs a positive radius and half-length",
   MuJoCo::kRejects, ""},
  {"fromto-and-pos", R"(<mujoco>
  <worldbody>
    <geom type="capsule" size="0.1" fromto="0 0 0 1 0 0" pos="1 0 0"/>
  </worldbody>
</mujoco>)", 3, "geom", "pos", "remove pos", MuJoCo::kRejects, ""},
  {"fromto-on-sphere", R"(<mujoco>
  <worldbody>
    <geom type="sphere" size="0.1" fromto="0 0 0 1 0 0"/>
  </worldbody>
</mujoco>)", 3, "geom", "fromto", "not a sphere", MuJoCo::kRejects, ""},
  {"fromto-points-coincide", R"(<mujoco>
  <worldbody>
    <geom type="capsule" size="0.1" fromto="1 0 0 1 0 0"/>
  </worldbody>
</mujoco>)", 3, "geom", "fromto", "coincide", MuJoCo::kRejects, ""},
  {"fromto-overflows", R"(<mujoco>
  <worldbody>
    <geom type="capsule" size="0.1" fromto="-1e308 0 0 1e308 0 0"/>
  </worldbody>
</mujoco>)", 3, "geom", "", "too large", MuJoCo::kAccepts,
   "MuJoCo stores an infinite half-length"},
  {"two-orientations", R"(<mujoco>
  <worldbody>
    <geom size="0.1" quat="1 0 0 0" euler="0 0 30"/>
  </worldbody>
</mujoco>)", 3, "geom", "euler", "more than one orientation", MuJoCo::kRejects, ""},
  {"zero-quaternion", R"(<mujoco>
  <worldbody>
    <body name="b" quat="0 0 0 0">
      <geom size="0.1"/>
    </body>
  </worldbody>
</mujoco>)", 3, "body", "quat", "zero length", MuJoCo::kAccepts,
   "MuJoCo stores (0,0,0,0); the body then ends up aligned with the world, not its parent"},
  {"xyaxes-parallel", R"(<mujoco>
  <worldbody>
    <geom size="0.1" xyaxes="1 0 0 2 0 0"/>
  </worldbody>
</mujoco>)", 3, "geom", "xyaxes", "parallel", MuJoCo::kRejects, ""},
  {"zaxis-zero", R"(<mujoco>
  <worldbody>
    <site zaxis="0 0 0"/>
  </worldbody>
</mujoco>)", 3, "site", "zaxis", "zero length", MuJoCo::kRejects, ""},
  {"site-zero-size", R"(<mujoco>
  <worldbody>
    <site size="0"/>
  </worldbody>
</mujoco>)", 3, "site", "size", "positive radius", MuJoCo::kRejects, ""},

  // ---- joint parameters that would make energy from nothing ---------------------------------
  {"joint-negative-damping", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j" damping="-0.1"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
</mujoco>)", 4, "joint", "damping", "must not be negative", MuJoCo::kAccepts,
   "negative damping feeds energy into the joint; MuJoCo simulates it until it blows up"},
  {"joint-negative-armature", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="j" armature="-0.01"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
</mujoco>)", 4, "joint", "armature", "must not be negative", MuJoCo::kAccepts,
   "negative rotor inertia can make M indefinite"},
  {"default-negative-stiffness", R"(<mujoco>
  <default>
    <joint stiffness="-5"/>
  </default>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
</mujoco>)", 3, "joint", "stiffness", "must not be negative", MuJoCo::kAccepts,
   "a negative spring pushes the joint away from springref, without bound"},

  // ---- numbers that overflow once compiled (set_const's check at qpos0, located) -------------
  {"body-offsets-overflow", R"(<mujoco>
  <worldbody>
    <body name="far" pos="1e308 0 0">
      <geom size="0.1"/>
      <body name="farther" pos="1e308 0 0">
        <joint name="j"/>
        <geom size="0.1"/>
      </body>
    </body>
  </worldbody>
</mujoco>)", 5, "body", "", "numbers are too large", MuJoCo::kAccepts,
   "MuJoCo places the body at infinity and every output is NaN"},
  {"gravity-out-of-scale", R"(<mujoco>
  <option gravity="0 0 -1e300"/>
  <worldbody>
    <body name="b" pos="0 0 1">
      <joint name="j" axis="0 1 0"/>
      <geom size="0.1" pos="0.5 0 0"/>
    </body>
  </worldbody>
</mujoco>)", 5, "joint", "", "more than 1e10", MuJoCo::kAccepts,
   "the acceleration at rest is beyond 1e10, so every mj_step would reset the state"},

  // ---- sensors ------------------------------------------------------------------------------
  {"sensor-unknown-type", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="hinge" axis="0 1 0"/>
      <geom size="0.1"/>
      <site name="s"/>
      <body name="c" pos="0 0 -0.5">
        <joint name="ball" type="ball"/>
        <geom size="0.1"/>
      </body>
    </body>
  </worldbody>
  <sensor>
    <toutch site="s"/>
  </sensor>
</mujoco>)", 14, "toutch", "", "did you mean 'touch'?", MuJoCo::kRejects, ""},
  {"sensor-missing-object", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="hinge" axis="0 1 0"/>
      <geom size="0.1"/>
      <site name="s"/>
      <body name="c" pos="0 0 -0.5">
        <joint name="ball" type="ball"/>
        <geom size="0.1"/>
      </body>
    </body>
  </worldbody>
  <sensor>
    <touch name="pad" site="pad"/>
  </sensor>
</mujoco>)", 14, "touch", "site", "no site of that name", MuJoCo::kRejects, ""},
  {"sensor-site-names-a-body", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="hinge" axis="0 1 0"/>
      <geom size="0.1"/>
      <site name="s"/>
    </body>
  </worldbody>
  <sensor>
    <accelerometer site="b"/>
  </sensor>
</mujoco>)", 10, "accelerometer", "site", "no site of that name ('b' is a body)",
   MuJoCo::kRejects, ""},
  {"sensor-wrong-joint-kind", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="hinge" axis="0 1 0"/>
      <geom size="0.1"/>
      <site name="s"/>
      <body name="c" pos="0 0 -0.5">
        <joint name="ball" type="ball"/>
        <geom size="0.1"/>
      </body>
    </body>
  </worldbody>
  <sensor>
    <jointpos joint="ball"/>
  </sensor>
</mujoco>)", 14, "jointpos", "joint", "reads a hinge or slide joint", MuJoCo::kRejects, ""},
  {"sensor-ball-on-hinge", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="hinge" axis="0 1 0"/>
      <geom size="0.1"/>
      <site name="s"/>
      <body name="c" pos="0 0 -0.5">
        <joint name="ball" type="ball"/>
        <geom size="0.1"/>
      </body>
    </body>
  </worldbody>
  <sensor>
    <ballquat joint="hinge"/>
  </sensor>
</mujoco>)", 14, "ballquat", "joint", "reads a ball joint", MuJoCo::kRejects, ""},
  {"sensor-limit-unlimited", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="hinge" axis="0 1 0"/>
      <geom size="0.1"/>
      <site name="s"/>
      <body name="c" pos="0 0 -0.5">
        <joint name="ball" type="ball"/>
        <geom size="0.1"/>
      </body>
    </body>
  </worldbody>
  <sensor>
    <jointlimitfrc joint="hinge"/>
  </sensor>
</mujoco>)", 14, "jointlimitfrc", "joint", "is not limited", MuJoCo::kRejects, ""},
  {"sensor-rangefinder-on-body", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="hinge" axis="0 1 0"/>
      <geom size="0.1"/>
      <site name="s"/>
      <body name="c" pos="0 0 -0.5">
        <joint name="ball" type="ball"/>
        <geom size="0.1"/>
      </body>
    </body>
  </worldbody>
  <sensor>
    <rangefinder body="b"/>
  </sensor>
</mujoco>)", 14, "rangefinder", "body", "unknown attribute 'body'", MuJoCo::kRejects, ""},
  {"sensor-negative-cutoff", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="hinge" axis="0 1 0"/>
      <geom size="0.1"/>
      <site name="s"/>
      <body name="c" pos="0 0 -0.5">
        <joint name="ball" type="ball"/>
        <geom size="0.1"/>
      </body>
    </body>
  </worldbody>
  <sensor>
    <gyro site="s" cutoff="-1"/>
  </sensor>
</mujoco>)", 14, "gyro", "cutoff", "must not be negative", MuJoCo::kRejects, ""},
  {"sensor-negative-noise", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="hinge" axis="0 1 0"/>
      <geom size="0.1"/>
      <site name="s"/>
      <body name="c" pos="0 0 -0.5">
        <joint name="ball" type="ball"/>
        <geom size="0.1"/>
      </body>
    </body>
  </worldbody>
  <sensor>
    <gyro site="s" noise="-0.1"/>
  </sensor>
</mujoco>)", 14, "gyro", "noise", "must not be negative", MuJoCo::kRejects, ""},
  {"sensor-cutoff-on-quaternion", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="hinge" axis="0 1 0"/>
      <geom size="0.1"/>
      <site name="s"/>
      <body name="c" pos="0 0 -0.5">
        <joint name="ball" type="ball"/>
        <geom size="0.1"/>
      </body>
    </body>
  </worldbody>
  <sensor>
    <framequat objtype="site" objname="s" cutoff="1"/>
  </sensor>
</mujoco>)", 14, "framequat", "cutoff", "a cutoff does not apply", MuJoCo::kRejects, ""},
  {"sensor-refname-without-reftype", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="hinge" axis="0 1 0"/>
      <geom size="0.1"/>
      <site name="s"/>
      <body name="c" pos="0 0 -0.5">
        <joint name="ball" type="ball"/>
        <geom size="0.1"/>
      </body>
    </body>
  </worldbody>
  <sensor>
    <framepos objtype="site" objname="s" refname="b"/>
  </sensor>
</mujoco>)", 14, "framepos", "refname", "reftype is missing", MuJoCo::kRejects, ""},
  {"sensor-missing-reference", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="hinge" axis="0 1 0"/>
      <geom size="0.1"/>
      <site name="s"/>
      <body name="c" pos="0 0 -0.5">
        <joint name="ball" type="ball"/>
        <geom size="0.1"/>
      </body>
    </body>
  </worldbody>
  <sensor>
    <framepos objtype="site" objname="s" reftype="body" refname="nobody"/>
  </sensor>
</mujoco>)", 14, "framepos", "refname", "no body of that name", MuJoCo::kRejects, ""},
  {"sensor-frame-of-joint", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="hinge" axis="0 1 0"/>
      <geom size="0.1"/>
      <site name="s"/>
      <body name="c" pos="0 0 -0.5">
        <joint name="ball" type="ball"/>
        <geom size="0.1"/>
      </body>
    </body>
  </worldbody>
  <sensor>
    <framepos objtype="joint" objname="hinge"/>
  </sensor>
</mujoco>)", 14, "framepos", "objtype", "'joint'", MuJoCo::kRejects, ""},
  {"sensor-frame-of-camera", R"(<mujoco>
  <worldbody>
    <camera name="eye" pos="0 0 1"/>
    <body name="b">
      <joint name="hinge" axis="0 1 0"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <sensor>
    <framepos objtype="camera" objname="eye"/>
  </sensor>
</mujoco>)", 10, "framepos", "objtype", "camera", MuJoCo::kAccepts, "lever does not place cameras"},
  {"sensor-tendon", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="hinge" axis="0 1 0"/>
      <geom size="0.1"/>
      <site name="s"/>
      <body name="c" pos="0 0 -0.5">
        <joint name="ball" type="ball"/>
        <geom size="0.1"/>
      </body>
    </body>
  </worldbody>
  <sensor>
    <tendonpos tendon="t"/>
  </sensor>
</mujoco>)", 14, "tendonpos", "tendon", "the model has no tendon of that name", MuJoCo::kRejects, ""},
  {"sensor-user", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="hinge" axis="0 1 0"/>
      <geom size="0.1"/>
      <site name="s"/>
      <body name="c" pos="0 0 -0.5">
        <joint name="ball" type="ball"/>
        <geom size="0.1"/>
      </body>
    </body>
  </worldbody>
  <sensor>
    <user objtype="site" objname="s" dim="2" needstage="pos" datatype="axis"/>
  </sensor>
</mujoco>)", 14, "user", "dim", "datatype axis has 3 numbers", MuJoCo::kRejects, ""},
  {"sensor-repeated-name", R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="hinge" axis="0 1 0"/>
      <geom size="0.1"/>
      <site name="s"/>
      <body name="c" pos="0 0 -0.5">
        <joint name="ball" type="ball"/>
        <geom size="0.1"/>
      </body>
    </body>
  </worldbody>
  <sensor>
    <gyro name="g" site="s"/>
    <touch name="g" site="s"/>
  </sensor>
</mujoco>)", 15, "touch", "name", "repeated sensor name", MuJoCo::kRejects, ""},

  // ---- structure -----------------------------------------------------------------------------
  {"text-inside-element", R"(<mujoco>
  <worldbody>
    <geom size="0.1">hello</geom>
  </worldbody>
</mujoco>)", 3, "geom", "", "unexpected text", MuJoCo::kAccepts,
   "MuJoCo ignores text inside elements; lever never drops input silently"},
};
// clang-format on

}  // namespace lever::test
