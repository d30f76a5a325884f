// Friction loss, equality constraints, fixed and spatial tendons compiled by mjcf_lite and by
// MuJoCo 2.2.2:
// the models of tests/models/constraints/ and small cases (class inheritance, what is left
// unwritten), field by field (dof_frictionloss, dof_solref, dof_solimp, eq_* with eq_data as
// mj_setConst completes it, tendon_* and wrap_*, tendon_length0 and tendon_invweight0); and the
// constraints lever refuses, by name.
#include <catch2/catch.hpp>
#include <lever/mjcf.hpp>

#include <filesystem>

#include <lever/harness/models.hpp>
#include "mujoco_xml.hpp"

namespace {

void compare_with_mujoco(const std::string& name, const std::string& xml) {
  INFO(name);
  const lever::Model ours = lever::mjcf::load_string(xml, name);
  std::string error;
  const lever::test::MjModelHandle theirs = lever::test::mujoco_compile(xml, &error);
  INFO("mujoco: " << error);
  REQUIRE(theirs);
  std::vector<std::string> differences = lever::test::compare_parameters(ours, *theirs);
  const std::vector<std::string> constants = lever::test::compare_constants(ours, *theirs);
  differences.insert(differences.end(), constants.begin(), constants.end());
  for (const std::string& d : differences) FAIL_CHECK(name << ": " << d);
}

std::string constraint_refusal(const std::string& xml) {
  try {
    lever::mjcf::load_string(xml, "refused.xml");
  } catch (const lever::mjcf::ParseError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("the constraint models compile to MuJoCo 2.2.2's parameters", "[compile][constraints]") {
  for (const char* name :
       {"friction_loss.xml", "equality.xml", "tendons.xml", "spatial_tendons.xml"}) {
    const std::string path =
        lever::test::model_path(std::string("tests/models/constraints/") + name);
    compare_with_mujoco(name, lever::test::read_text(path));
  }
  const lever::Model friction =
      lever::mjcf::load_file(lever::test::model_path("tests/models/constraints/friction_loss.xml"));
  CHECK(friction.dof_frictionloss[1] == 0.4);  // from class "rough"
  CHECK(friction.dof_frictionloss[3] == 0.0);  // the class's value overridden by 0
  const lever::Model eq =
      lever::mjcf::load_file(lever::test::model_path("tests/models/constraints/equality.xml"));
  REQUIRE(eq.neq == 7);
  CHECK(eq.eq_active[6] == 0);
  CHECK(eq.eq_solref[1][0] == 0.05);  // class "loose"
  const lever::Model tendons =
      lever::mjcf::load_file(lever::test::model_path("tests/models/constraints/tendons.xml"));
  REQUIRE(tendons.ntendon == 5);
  REQUIRE(tendons.nwrap == 10);
  CHECK(tendons.tendon_limited[0] == 1);       // by its range (autolimits)
  CHECK(tendons.tendon_stiffness[1] == 3.0);   // class "soft"
  CHECK(tendons.tendon_lengthspring[2] == 0.2);  // as written
  CHECK(tendons.actuator_trntype[1] == lever::TransmissionType::kTendon);
  CHECK(tendons.eq_type[0] == lever::EqualityType::kTendon);
}

TEST_CASE("tendon corner cases agree with MuJoCo 2.2.2", "[compile][tendons]") {
  // a tendon class nested in another, partial solref and solimp, limited="false" beside a range,
  // a joint named twice in one path, a coupling of one tendon, springlength at springref in degrees
  compare_with_mujoco("tendon_corners.xml", R"(<mujoco>
  <default>
    <tendon solreflimit="0.03" solimpfriction="0.7" margin="0.01"/>
    <default class="a">
      <tendon stiffness="2" range="-1 1"/>
      <default class="b">
        <tendon limited="false" damping="0.3" frictionloss="0.2"/>
      </default>
    </default>
  </default>
  <worldbody>
    <body name="a" pos="0 0 1">
      <joint name="a1" axis="1 0 0" springref="30"/>
      <geom size="0.1"/>
      <body name="b" pos="0.2 0 0">
        <joint name="b1" type="slide" axis="0 0 1" ref="0.1"/>
        <geom size="0.05"/>
      </body>
    </body>
  </worldbody>
  <tendon>
    <fixed name="t1" class="a"><joint joint="a1" coef="2"/><joint joint="b1" coef="-1"/></fixed>
    <fixed name="t2" class="b"><joint joint="b1" coef="0.5"/><joint joint="b1" coef="3"/></fixed>
    <fixed class="b" limited="true" range="0 0.5"><joint joint="a1" coef="1"/></fixed>
  </tendon>
  <equality><tendon tendon1="t2" polycoef="0.1 1 0 0 0"/></equality>
  <actuator><position tendon="t1" kp="10" gear="3"/></actuator>
</mujoco>)");
}

TEST_CASE("spatial tendon corner cases agree with MuJoCo 2.2.2", "[compile][tendons]") {
  // a spatial tendon over a class of its own (width, limits, springlength left to the length at
  // springref), a path starting at a pulley, a geom named twice, a side site on another body, a
  // cylinder and a sphere of one body, sites of the world only; a spatial tendon driven and
  // coupled to a fixed one
  compare_with_mujoco("spatial_corners.xml", R"(<mujoco>
  <default>
    <default class="rope"><tendon width="0.02" range="0.1 2" stiffness="3" margin="0.01"/></default>
  </default>
  <worldbody>
    <site name="w0" pos="0 0 1"/><site name="w1" pos="1 0 1"/>
    <body name="a" pos="0 0 0.5">
      <joint name="h" axis="0 1 0" springref="20"/>
      <geom name="drum" type="cylinder" size="0.1 0.2"/>
      <geom name="ball" type="sphere" pos="0.5 0 0" size="0.05"/>
      <site name="s" pos="-0.3 0 0.1"/><site name="side" pos="0 0.3 0"/>
      <body name="b" pos="1 0 0"><joint name="k" axis="0 1 0"/><geom size="0.05"/>
        <site name="r" pos="0.2 0 0"/></body>
    </body>
  </worldbody>
  <tendon>
    <spatial name="t1" class="rope">
      <pulley divisor="3"/><site site="w0"/><geom geom="drum" sidesite="side"/><site site="r"/>
      <geom geom="ball"/><site site="s"/>
      <pulley divisor="1.5"/><site site="w1"/><geom geom="drum"/><site site="s"/>
    </spatial>
    <spatial name="t2" limited="false"><site site="w0"/><site site="w1"/></spatial>
    <fixed name="t3"><joint joint="k" coef="2"/></fixed>
  </tendon>
  <equality><tendon tendon1="t1" tendon2="t3" polycoef="0 1 0 0 0"/></equality>
  <actuator><position tendon="t1" kp="10"/></actuator>
</mujoco>)");
}

TEST_CASE("tendons lever cannot build are refused by name", "[compile][tendons]") {
  const std::string head = R"(<mujoco><worldbody><body name="a"><joint name="j"/><geom size="1"/>
    <site name="s"/><body name="b"><joint name="ball" type="ball"/><geom size="1"/><site name="r"/>
    </body></body></worldbody>)";
  // spatial paths MuJoCo refuses too, each named
  CHECK_THAT(constraint_refusal(head + R"(<tendon><spatial><site site="s"/></spatial></tendon>
    </mujoco>)"),
             Catch::Contains("at least two"));
  CHECK_THAT(constraint_refusal(head + R"(<tendon><spatial><site site="s"/><site site="q"/>
    </spatial></tendon></mujoco>)"),
             Catch::Contains("unknown site 'q'"));
  CHECK_THAT(constraint_refusal(head + R"(<tendon><spatial><site site="s"/><site site="s"/>
    </spatial></tendon></mujoco>)"),
             Catch::Contains("follows itself"));
  CHECK_THAT(constraint_refusal(head + R"(<tendon><spatial><site site="s"/><pulley divisor="2"/>
    <site site="r"/></spatial></tendon></mujoco>)"),
             Catch::Contains("no neighbour"));
  CHECK_THAT(constraint_refusal(head + R"(<tendon><spatial><site site="s"/><site site="r"/>
    <pulley divisor="2"/></spatial></tendon></mujoco>)"),
             Catch::Contains("ends with a pulley"));
  CHECK_THAT(constraint_refusal(head + R"(<tendon><spatial><site site="s"/><site site="r"/>
    <pulley divisor="0"/><site site="s"/><site site="r"/></spatial></tendon></mujoco>)"),
             Catch::Contains("divisor must be positive"));
  CHECK_THAT(constraint_refusal(head + R"(<tendon><spatial><site site="s"/><geom geom="g"/>
    </spatial></tendon></mujoco>)"),
             Catch::Contains("unknown geom 'g'"));
  CHECK_THAT(constraint_refusal(R"(<mujoco><worldbody><body><joint/><geom name="box" type="box"
    size="1 1 1"/><site name="s"/><site name="r" pos="1 0 0"/></body></worldbody><tendon><spatial>
    <site site="s"/><geom geom="box"/><site site="r"/></spatial></tendon></mujoco>)"),
             Catch::Contains("not a sphere or a cylinder"));
  CHECK_THAT(constraint_refusal(R"(<mujoco><worldbody><body><joint/><geom name="ball" size="1"/>
    <site name="s"/><site name="r" pos="1 0 0"/></body></worldbody><tendon><spatial>
    <geom geom="ball"/><site site="s"/><site site="r"/></spatial></tendon></mujoco>)"),
             Catch::Contains("between two sites"));
  CHECK_THAT(constraint_refusal(R"(<mujoco><worldbody><body><joint/><geom name="ball" size="1"/>
    <site name="s"/><site name="r" pos="1 0 0"/></body></worldbody><tendon><spatial>
    <site site="s"/><geom geom="ball" sidesite="x"/><site site="r"/></spatial></tendon></mujoco>)"),
             Catch::Contains("unknown side site 'x'"));
  CHECK_THAT(constraint_refusal(head + R"(<tendon><spatial width="0"><site site="s"/>
    <site site="r"/></spatial></tendon></mujoco>)"),
             Catch::Contains("width must be positive"));
  CHECK_THAT(constraint_refusal(head + R"(<tendon><fixed><joint joint="ball" coef="1"/></fixed>
    </tendon></mujoco>)"),
             Catch::Contains("ball or free joint"));
  CHECK_THAT(constraint_refusal(head + R"(<tendon><fixed><joint joint="k" coef="1"/></fixed>
    </tendon></mujoco>)"),
             Catch::Contains("unknown joint 'k'"));
  CHECK_THAT(constraint_refusal(head + R"(<tendon><fixed name="t"/></tendon></mujoco>)"),
             Catch::Contains("at least one"));
  CHECK_THAT(constraint_refusal(head + R"(<tendon><fixed name="t"><joint joint="j" coef="1"/>
    </fixed></tendon><actuator><motor tendon="u"/></actuator></mujoco>)"),
             Catch::Contains("unknown tendon 'u'"));
  CHECK_THAT(constraint_refusal(head + R"(<tendon><fixed name="t" limited="true" range="1 0">
    <joint joint="j" coef="1"/></fixed></tendon></mujoco>)"),
             Catch::Contains("lower < upper"));
}

TEST_CASE("equality and friction loss corner cases agree with MuJoCo 2.2.2",
          "[compile][constraints]") {
  // a weld to the world without anchor or relpose, a coupling left at its default polycoef, a
  // connect whose second body is a child, partial solref and solimp over the main class, a
  // class's frictionloss and solimpfriction partly overridden
  compare_with_mujoco("corners.xml", R"(<mujoco>
  <default>
    <joint frictionloss="0.2" solimpfriction="0.7 0.8 0.01"/>
    <equality solref="0.03" solimp="0.8"/>
  </default>
  <worldbody>
    <body name="a" pos="0 0 1" euler="10 20 30">
      <joint name="a1" axis="1 0 0" solimpfriction="0.6"/>
      <joint name="a2" axis="0 1 0" frictionloss="1.5" solreffriction="0.05"/>
      <geom size="0.1"/>
      <body name="b" pos="0.2 0 0">
        <joint name="b1" type="slide" axis="0 0 1" frictionloss="0"/>
        <geom size="0.05"/>
      </body>
    </body>
    <body name="c" pos="1 0 1">
      <freejoint/>
      <geom type="box" size="0.1 0.2 0.3"/>
    </body>
  </worldbody>
  <equality>
    <weld body1="c"/>
    <joint joint1="a2" joint2="a1"/>
    <connect body1="a" body2="b" anchor="0.1 0.2 0.3" solimp="0.5 0.6"/>
  </equality>
</mujoco>)");
}

TEST_CASE("constraints lever cannot build are refused by name", "[compile][constraints]") {
  const std::string head = R"(<mujoco><worldbody><body name="a"><joint name="j"/><geom size="1"/>
    <body name="b"><joint name="ball" type="ball"/><geom size="1"/></body></body></worldbody>)";
  CHECK_THAT(constraint_refusal(head + R"(<equality><tendon tendon1="t"/></equality></mujoco>)"),
             Catch::Contains("unknown tendon 't'"));
  CHECK_THAT(constraint_refusal(
                 head + R"(<equality><connect body1="x" anchor="0 0 0"/></equality></mujoco>)"),
             Catch::Contains("unknown body 'x'"));
  CHECK_THAT(constraint_refusal(head + R"(<equality><joint joint1="ball"/></equality></mujoco>)"),
             Catch::Contains("joint 'ball' is a ball or free joint"));
  CHECK_THAT(
      constraint_refusal(head + R"(<equality><weld body1="a" body2="a"/></equality></mujoco>)"),
      Catch::Contains("constrained to itself"));
  CHECK_THAT(constraint_refusal(head + R"(<equality><connect body1="a"/></equality></mujoco>)"),
             Catch::Contains("anchor"));
}
