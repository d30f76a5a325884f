// Small inline models against MuJoCo 2.2.2: the lesson's visual-geom demonstration, compiler
// corner cases that the model files may not reach, and MuJoCo's verdict on the bad inputs of
// tests/mjcf.
#include <catch2/catch.hpp>
#include <lever/mjcf.hpp>

#include "bad_inputs.hpp"
#include "compile_checks.hpp"

namespace {

struct Case {
  const char* name;
  const char* xml;
};

// both compile it; every parameter and constant must agree
void compare(const std::string& name, const std::string& xml) {
  lever::test::check_compiles_as_mujoco(name, xml);
}

// the lesson's demonstration: a 1 kg colliding geom and a 2 kg non-colliding geom in group 3
std::string visual_geom_model(const char* compiler) {
  return std::string(R"(<mujoco>
  )") + compiler +
         R"(
  <worldbody>
    <body name="b" pos="0 0 1">
      <joint name="j" axis="0 1 0"/>
      <geom name="collision" type="box" size="0.05 0.05 0.05" mass="1"/>
      <geom name="visual" type="sphere" size="0.08" pos="0.1 0 0" mass="2" group="3"
            contype="0" conaffinity="0"/>
    </body>
  </worldbody>
</mujoco>)";
}

}  // namespace

TEST_CASE("a visual-only geom adds mass unless inertiagrouprange leaves its group out",
          "[compile]") {
  const std::string all = visual_geom_model(R"(<compiler angle="radian"/>)");
  const std::string narrow = visual_geom_model(R"(<compiler inertiagrouprange="0 2"/>)");
  CHECK(lever::mjcf::load_string(all).body_mass[1] == Approx(3.0).epsilon(1e-15));
  CHECK(lever::mjcf::load_string(narrow).body_mass[1] == Approx(1.0).epsilon(1e-15));
  std::string error;
  CHECK(lever::test::mujoco_compile(all, &error)->body_mass[1] == Approx(3.0).epsilon(1e-15));
  CHECK(lever::test::mujoco_compile(narrow, &error)->body_mass[1] == Approx(1.0).epsilon(1e-15));
  compare("visual-geom-all-groups", all);
  compare("visual-geom-groups-0-2", narrow);
}

TEST_CASE("the comparison itself notices a difference", "[compile]") {
  // guards against a comparison that would pass anything
  const std::string xml = visual_geom_model("");
  lever::Model ours = lever::mjcf::load_string(xml);
  std::string error;
  const lever::test::MjModelHandle theirs = lever::test::mujoco_compile(xml, &error);
  REQUIRE(lever::test::compare_parameters(ours, *theirs).empty());
  ours.body_mass[1] *= 1 + 1e-11;
  ours.geom_quat[0] *= -1;  // the same rotation: not a difference
  const std::vector<std::string> d = lever::test::compare_parameters(ours, *theirs);
  REQUIRE(d.size() == 1);
  CHECK_THAT(d[0], Catch::StartsWith("body_mass[1]"));
}

// clang-format off
const Case kCases[] = {
  {"single-capsule-frame", R"(<mujoco>
  <worldbody>
    <body name="b"><joint/><geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.025"/></body>
  </worldbody>
</mujoco>)"},
  {"fullinertia-sorted", R"(<mujoco>
  <worldbody>
    <body name="b"><joint/><inertial pos="0 0 0" mass="1" fullinertia="0.1 0.2 0.3 0 0 0"/></body>
    <body name="c"><joint/>
      <inertial pos="0.1 0 0" mass="2" fullinertia="0.3 0.25 0.2 0.01 -0.02 0.03"/></body>
  </worldbody>
</mujoco>)"},
  {"two-coaxial-geoms", R"(<mujoco>
  <worldbody>
    <body name="b"><joint/>
      <geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.025"/>
      <geom type="sphere" pos="0.5 0 0" size="0.05"/>
    </body>
  </worldbody>
</mujoco>)"},
  {"mixed-geoms-principal-axes", R"(<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="b" pos="0.1 0.2 0.3" euler="0.3 -0.2 1.1"><joint axis="1 1 0"/>
      <geom type="box" size="0.1 0.2 0.05" pos="0.1 0 0" euler="0.1 0.2 0.3" density="700"/>
      <geom type="ellipsoid" size="0.05 0.1 0.15" pos="-0.1 0.05 0" axisangle="1 2 3 0.7"/>
      <geom type="cylinder" fromto="0 0 0 0.1 0.2 0.3" size="0.03"/>
      <geom type="sphere" size="0.04" pos="0 0 0.2" mass="0.3"/>
      <geom type="capsule" size="0.02 0.1" xyaxes="0 1 0 -1 0 1" mass="0.2"/>
    </body>
  </worldbody>
</mujoco>)"},
  {"jointless-massless-body-frame", R"(<mujoco>
  <worldbody>
    <body name="a" pos="1 2 3" euler="10 20 30">
      <body name="b" pos="0.5 0 0" axisangle="0 0 1 45"><joint/><geom size="0.1"/></body>
    </body>
  </worldbody>
</mujoco>)"},
  {"massless-moving-body-carried-by-static-child", R"(<mujoco>
  <worldbody>
    <body name="a"><joint/>
      <body name="b" pos="0.2 0 0"><geom size="0.1"/></body>
    </body>
  </worldbody>
</mujoco>)"},
  {"joints-follow-the-body-tree", R"(<mujoco>
  <worldbody>
    <body name="a">
      <body name="a1" pos="0 0 -0.1"><joint name="a1"/><geom size="0.05"/></body>
      <body name="a2" pos="0 0 0.1"><joint name="a2" type="slide"/><geom size="0.05"/>
        <body name="a21"><joint name="a21a"/><joint name="a21b" axis="1 0 0"/>
          <geom size="0.05"/></body>
      </body>
      <joint name="a"/>
      <geom size="0.1"/>
    </body>
    <body name="b" pos="1 0 0"><geom size="0.1"/>
      <body name="b1"><joint name="b1" axis="0 1 0"/><geom size="0.05"/></body>
    </body>
  </worldbody>
</mujoco>)"},
  {"degrees-last-bit", R"(<mujoco>
  <worldbody>
    <body name="b" euler="13 17 77" pos="0 0 1">
      <joint name="h1" range="-13 170" ref="17" springref="77"/>
      <joint name="h2" axis="0 1 0" range="-170 13" limited="false"/>
      <joint name="s" type="slide" range="-13 17" ref="77" springref="170"/>
      <geom size="0.1" axisangle="1 1 1 77"/>
      <site name="s" axisangle="0 1 0 13"/>
      <inertial pos="0 0 0" mass="1" diaginertia="1 1 1" euler="170 13 17"/>
    </body>
  </worldbody>
</mujoco>)"},
  {"eulerseq-intrinsic-zyx", R"(<mujoco>
  <compiler eulerseq="zyx"/>
  <worldbody>
    <body name="b" euler="10 -20 30"><joint/><geom size="0.1" euler="1 2 3"/></body>
  </worldbody>
</mujoco>)"},
  {"eulerseq-mixed", R"(<mujoco>
  <compiler eulerseq="xYz" angle="radian"/>
  <worldbody>
    <body name="b" euler="0.4 -0.7 1.3"><joint/><geom size="0.1"/>
      <site euler="0.1 0.2 0.3"/></body>
  </worldbody>
</mujoco>)"},
  {"classes-and-childclass", R"(<mujoco>
  <default>
    <joint damping="0.5" axis="0 1 0"/>
    <geom type="capsule" size="0.02 0.1 0.3" rgba="1 0 0 1"/>
    <motor gear="3 0 0 0 0 1" ctrlrange="-1 1"/>
    <default class="arm">
      <joint armature="0.1" range="-30 60"/>
      <geom size="0.03" euler="0 90 0"/>
      <default class="wrist">
        <joint axis="1 0 0" solreflimit="0.05"/>
        <geom type="box" size="0.01 0.02"/>
        <site size="0.01"/>
      </default>
    </default>
    <default class="slider">
      <joint type="slide" range="-0.1 0.1" solimplimit="0.8 0.9"/>
      <motor gear="20"/>
    </default>
  </default>
  <worldbody>
    <body name="a" childclass="arm">
      <joint name="a"/>
      <geom quat="0 1 0 0"/>
      <body name="b" pos="0.2 0 0">
        <joint name="b" class="wrist"/>
        <geom class="wrist"/>
        <body name="c" childclass="slider" pos="0.1 0 0">
          <joint name="c"/>
          <geom class="main" size="0.05 0.1"/>
          <site name="tip" class="wrist"/>
        </body>
      </body>
    </body>
  </worldbody>
  <actuator>
    <motor name="a" joint="a" gear="5"/>
    <motor name="b" joint="b" class="arm"/>
    <motor name="c" joint="c" class="slider" ctrlrange="-2 2"/>
  </actuator>
</mujoco>)"},
  {"second-top-level-default-and-late-compiler", R"(<mujoco>
  <default><joint damping="1"/></default>
  <worldbody>
    <body name="b"><joint range="0 90"/><geom size="0.1"/></body>
  </worldbody>
  <default><joint armature="2"/></default>
  <compiler angle="radian"/>
  <option timestep="0.01"/>
  <option gravity="0 0 -1"/>
</mujoco>)"},
  {"inertiafromgeom-true", R"(<mujoco>
  <compiler inertiafromgeom="true" inertiagrouprange="1 2"/>
  <worldbody>
    <body name="replaced"><joint/>
      <inertial pos="0 0 0" mass="5" diaginertia="1 1 1"/>
      <geom size="0.1" group="1"/><geom size="0.1" pos="0.2 0 0" group="2"/>
    </body>
    <body name="kept" pos="1 0 0"><joint/>
      <inertial pos="0 0.1 0" mass="5" diaginertia="1 2 2"/>
      <geom size="0.1" group="0"/>
    </body>
  </worldbody>
</mujoco>)"},
  {"inertiafromgeom-false", R"(<mujoco>
  <compiler inertiafromgeom="false"/>
  <worldbody>
    <body name="static" pos="0 0 1" quat="0 1 0 0"><geom size="0.1"/></body>
    <body name="moving"><joint/><inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/>
      <geom size="0.1"/></body>
  </worldbody>
</mujoco>)"},
  {"bounds-and-total-mass", R"(<mujoco>
  <compiler boundmass="0.5" boundinertia="0.01" balanceinertia="true" settotalmass="7"/>
  <worldbody>
    <body name="light"><joint/>
      <inertial pos="0 0 0" mass="0.1" diaginertia="0.001 0.002 0.1"/></body>
    <body name="static"><inertial pos="0 0 0" mass="2" diaginertia="1 1 1"/></body>
    <body name="geoms"><joint/><geom type="box" size="0.01 0.2 0.3"/></body>
  </worldbody>
</mujoco>)"},
  {"sites-normalized-after", R"(<mujoco>
  <worldbody>
    <site name="a" quat="2 0 0 0"/>
    <site name="b" quat="1 2 3 4" size="0.1 0.2"/>
    <body name="b"><joint/><geom size="0.1"/>
      <site name="c" xyaxes="1 1 0 -1 1 0.1"/><site name="d" zaxis="0 -1 0.001"/></body>
  </worldbody>
</mujoco>)"},
  {"inertial-fullinertia-beats-diaginertia", R"(<mujoco>
  <worldbody>
    <body name="b"><joint/>
      <inertial pos="0 0 0" mass="1" diaginertia="5 5 5" fullinertia="0.2 0.3 0.4 0.01 0 0"/>
    </body>
  </worldbody>
</mujoco>)"},
  {"geom-mass-attribute", R"(<mujoco>
  <worldbody>
    <body name="b"><joint/>
      <geom size="0.1" mass="0"/>
      <geom type="box" size="0.1 0.2 0.3" mass="2" pos="0.1 0 0"/>
      <geom type="cylinder" size="0.1 0.2" density="300" quat="1 1 0 0"/>
    </body>
  </worldbody>
</mujoco>)"},
  {"fromto-every-direction", R"(<mujoco>
  <worldbody>
    <geom type="capsule" fromto="0 0 0 1 0 0" size="0.1"/>
    <geom type="capsule" fromto="0 0 0 -1 0 0" size="0.1"/>
    <geom type="cylinder" fromto="0 0 0 0 1 0" size="0.1"/>
    <geom type="cylinder" fromto="0 0 0 0 -1 0" size="0.1"/>
    <geom type="box" fromto="0 0 0 0 0 1" size="0.1"/>
    <geom type="ellipsoid" fromto="0 0 0 0 0 -1" size="0.1"/>
    <geom type="box" fromto="0.1 0.2 0.3 -0.4 0.5 0.6" size="0.1 7 7" pos="0 0 0"/>
  </worldbody>
</mujoco>)"},
  {"motors", R"(<mujoco>
  <default>
    <motor gear="2 0 0 0 0 5" forcerange="-3 3"/>
    <default class="c"><motor gear="7" ctrllimited="false" ctrlrange="1 -1"/></default>
  </default>
  <worldbody>
    <body name="b"><joint name="h"/><joint name="s" type="slide"/><geom size="0.1"/></body>
  </worldbody>
  <actuator>
    <motor joint="h" ctrlrange="-1 1"/>
    <motor joint="s" class="c" forcelimited="false"/>
    <motor name="h" joint="h" gear="-1 1" forcelimited="true"/>
  </actuator>
</mujoco>)"},
  {"joint-parameters", R"(<mujoco>
  <default><joint solreflimit="0.03 0.9" solimplimit="0.8 0.9 0.01 0.4 3"/></default>
  <worldbody>
    <body name="b" pos="0 0 1"><geom size="0.1"/>
      <joint name="a" pos="0.1 0 0" axis="1 2 3" stiffness="10" springref="30" margin="0.01"
             armature="0.2" damping="0.3" solreflimit="0.05" solimplimit="0.7 0.8"/>
      <joint name="b" type="slide" axis="0 0 -2" ref="0.1" springref="-0.2" range="-0.5 0.5"/>
    </body>
  </worldbody>
</mujoco>)"},
  {"sections-repeated", R"(<mujoco model="repeated">
  <worldbody><body name="a"><joint name="a"/><geom size="0.1"/></body></worldbody>
  <actuator><motor joint="a"/></actuator>
  <worldbody><site name="s" pos="1 0 0"/>
    <body name="b"><joint name="b"/><geom size="0.2"/></body></worldbody>
  <actuator><motor joint="b"/></actuator>
</mujoco>)"},
  // ---- contact ----------------------------------------------------------------
  {"contact-geom-parameters", R"(<mujoco>
  <default>
    <geom friction="0.7" solref="0.01" solimp="0.8 0.9" margin="0.002" priority="1"/>
    <default class="soft"><geom condim="4" solmix="3" gap="0.001" friction="0.5 0.01 0.002"/></default>
  </default>
  <worldbody>
    <geom name="floor" type="plane" size="0 0 0.1" pos="0 0 -0.5" quat="1 0.1 0 0" condim="1"/>
    <geom name="wall" type="plane" size="2 1 0.5" pos="1 0 0" zaxis="-1 0 0" mass="3"/>
    <body name="a" pos="0 0 1">
      <joint name="a" axis="0 1 0"/>
      <geom name="ball" size="0.1" class="soft"/>
      <geom name="rod" type="capsule" fromto="0 0 0 0.3 0 0.1" size="0.02" condim="6"/>
      <geom name="can" type="cylinder" size="0.05 0.1" pos="0.2 0 0" solref="-100 -10"/>
      <geom name="egg" type="ellipsoid" size="0.03 0.05 0.04" pos="0 0.2 0"/>
      <geom name="brick" type="box" size="0.1 0.2 0.3" pos="0 0 0.3" contype="2" conaffinity="4"/>
    </body>
  </worldbody>
</mujoco>)"},
  {"plane-in-static-bodies", R"(<mujoco>
  <worldbody>
    <body name="table" pos="0 0 0.4">
      <geom name="top" type="plane" size="0.5 0.5 0.05" mass="2"/>
      <body name="shelf" pos="0 0 0.2" euler="10 0 0">
        <geom type="plane" size="0 0 1" pos="0.1 0 0"/>
        <geom type="box" size="0.1 0.1 0.01"/>
      </body>
    </body>
    <body name="arm"><joint/><geom size="0.1"/></body>
  </worldbody>
</mujoco>)"},
  {"contact-pairs-and-exclusions", R"(<mujoco>
  <default>
    <pair condim="1" friction="0.3 0.4" margin="0.01"/>
    <default class="grippy"><pair condim="6" friction="2" solref="0.005 2" solimp="0.5"/></default>
  </default>
  <worldbody>
    <geom name="floor" type="plane" size="1 1 0.1" priority="3" friction="0.2 0.1 0.1"/>
    <body name="b1" pos="0 0 1"><joint/><geom name="g1" size="0.1" priority="1" margin="0.5"/>
      <body name="b2" pos="0 0 0.5"><joint/><geom name="g2" type="box" size="0.1 0.1 0.1"/>
        <body name="b3" pos="0 0 0.5"><joint/><geom name="g3" type="capsule" size="0.1 0.2"/></body>
      </body>
    </body>
  </worldbody>
  <contact>
    <pair name="p1" geom1="g3" geom2="g1" gap="0.001"/>
    <pair geom1="g2" geom2="floor" class="grippy" margin="0.02"/>
    <pair geom1="g1" geom2="floor" condim="4" solref="-500 -5"/>
    <pair geom1="floor" geom2="g3"/>
    <pair geom1="g2" geom2="g3" class="grippy"/>
    <pair geom1="g3" geom2="g2" friction="1 2 3 4 5"/>
    <exclude name="x" body1="b3" body2="b1"/>
    <exclude body1="b2" body2="world"/>
    <exclude body1="b1" body2="b2"/>
  </contact>
</mujoco>)"},
  {"contact-options-and-sizes", R"(<mujoco>
  <option cone="elliptic" impratio="10" iterations="1000" tolerance="0" solver="Newton"
          noslip_iterations="0" noslip_tolerance="1e-5">
    <flag contact="disable" override="disable"/>
  </option>
  <option iterations="50"/>
  <size nconmax="30" njmax="-1" nstack="100000"/>
  <worldbody><body name="b"><joint/><geom size="0.1"/></body></worldbody>
</mujoco>)"},
  // MuJoCo's conjugate gradients: opt.solver is mjSOL_CG (1), with its own stopping rule
  {"option-solver-cg", R"(<mujoco>
  <option solver="CG" iterations="30" tolerance="1e-6"/>
  <worldbody><body name="b"><joint/><geom size="0.1"/></body></worldbody>
</mujoco>)"},
  // MuJoCo's projected Gauss-Seidel: opt.solver is mjSOL_PGS (0)
  {"option-solver-pgs", R"(<mujoco>
  <option solver="PGS" iterations="20" tolerance="0"/>
  <worldbody><body name="b"><joint/><geom size="0.1"/></body></worldbody>
</mujoco>)"},
  // cranklength from a class: a slider-crank's rod, and kept on joint transmissions as MuJoCo
  // keeps it
  {"actuator-class-cranklength", R"(<mujoco>
  <default>
    <general cranklength="0.3"/>
    <default class="crank">
      <position kp="30" cranklength="0.08"/>
      <motor cranklength="0.05"/>
      <velocity cranklength="0.07"/>
    </default>
  </default>
  <worldbody>
    <site name="slider" pos="0 -.1 0" zaxis="1 .5 0"/>
    <body>
      <joint name="hinge" damping=".1"/>
      <geom type="capsule" size=".01" fromto="0 0 0 .2 0 0"/>
      <site name="crank" pos=".1 0 0"/>
    </body>
  </worldbody>
  <actuator>
    <position class="crank" cranksite="crank" slidersite="slider"/>
    <position class="crank" cranksite="crank" slidersite="slider" cranklength="0.09"/>
    <motor class="crank" joint="hinge"/>
    <velocity class="crank" joint="hinge"/>
    <general joint="hinge"/>
  </actuator>
</mujoco>)"},
  // every flag, the override's parameters (o_solref written in part), one <option> after another
  {"option-flags", R"(<mujoco>
  <option o_margin="0.01" o_solref="0.05" o_solimp="0.7 0.8 0.01 0.4 3">
    <flag constraint="disable" equality="disable" frictionloss="disable" limit="disable"
          contact="disable" passive="disable" gravity="disable" clampctrl="disable"/>
  </option>
  <option>
    <flag warmstart="disable" filterparent="disable" actuation="disable" refsafe="disable"
          sensor="disable" override="enable" energy="enable" fwdinv="enable"
          sensornoise="enable" multiccd="enable"/>
  </option>
  <worldbody><body name="b"><joint/><geom size="0.1"/></body></worldbody>
</mujoco>)"},
  {"option-flags-some", R"(<mujoco>
  <option><flag gravity="disable" energy="enable" contact="enable"/></option>
  <worldbody><body name="b"><joint/><geom size="0.1"/></body></worldbody>
</mujoco>)"},
  // user sensors: their own dim, datatype and stage, on objects of every kind lever has
  {"sensor-user", R"(<mujoco>
  <worldbody>
    <body name="b"><joint name="j"/><geom name="g" size="0.1"/><site name="s"/></body>
  </worldbody>
  <actuator><motor name="m" joint="j"/></actuator>
  <tendon><fixed name="t"><joint joint="j" coef="1"/></fixed></tendon>
  <sensor>
    <user objtype="site" objname="s" dim="2" needstage="pos" datatype="real" cutoff="3"/>
    <jointpos joint="j"/>
    <user name="q" objtype="body" objname="b" dim="4" needstage="acc" datatype="quaternion"
          noise="0.1" user="1 2"/>
    <user objtype="xbody" objname="b" dim="3" needstage="vel" datatype="axis"/>
    <user objtype="joint" objname="j" dim="0" needstage="none" datatype="positive"/>
    <user objtype="geom" objname="g" dim="1" needstage="pos" datatype="positive"/>
    <user objtype="actuator" objname="m" dim="1" needstage="acc" datatype="real"/>
    <user objtype="tendon" objname="t" dim="5" needstage="vel" datatype="real"/>
  </sensor>
</mujoco>)"},
  // tendons' user data: written, inherited from a class, none; the width the longest list
  {"tendon-user", R"(<mujoco>
  <default><default class="u"><tendon user="7 8"/></default></default>
  <worldbody>
    <body name="b"><joint name="j"/><geom size="0.1"/><site name="s1"/>
      <body pos="0 0 1"><joint name="k"/><geom size="0.1"/><site name="s2"/></body>
    </body>
  </worldbody>
  <tendon>
    <fixed name="own" user="1 2 3"><joint joint="j" coef="1"/></fixed>
    <spatial name="inherited" class="u"><site site="s1"/><site site="s2"/></spatial>
    <fixed name="replaced" class="u" user="4"><joint joint="k" coef="2"/></fixed>
    <fixed name="none"><joint joint="k" coef="-1"/></fixed>
  </tendon>
</mujoco>)"},
  // a written width pads every tendon's list with zeros
  {"tendon-user-sized", R"(<mujoco>
  <size nuser_tendon="4"/>
  <worldbody><body name="b"><joint name="j"/><geom size="0.1"/></body></worldbody>
  <tendon>
    <fixed user="5"><joint joint="j" coef="1"/></fixed>
    <fixed><joint joint="j" coef="3"/></fixed>
  </tendon>
</mujoco>)"},
  // MuJoCo's matrix layout, which changes none of the compiled numbers
  {"option-jacobian", R"(<mujoco>
  <option jacobian="sparse"/>
  <option jacobian="dense"/>
  <worldbody><body name="b"><joint/><geom size="0.1"/></body></worldbody>
</mujoco>)"},
};
// clang-format on

// MuJoCo 2.2.2 sorts <pair>s with std::sort by signature alone, which is not stable: with more than
// 16 pairs of one body pair their order is libstdc++'s, and lever's must be the same
std::string many_pairs_model() {
  std::string xml = "<mujoco>\n<worldbody>\n<body name=\"a\"><joint/>";
  for (int i = 0; i < 12; ++i) xml += "<geom name=\"a" + std::to_string(i) + "\" size=\"0.1\"/>";
  xml += "</body>\n<body name=\"b\"><joint/>";
  for (int i = 0; i < 12; ++i) xml += "<geom name=\"b" + std::to_string(i) + "\" size=\"0.1\"/>";
  xml += "</body>\n</worldbody>\n<contact>\n";
  for (int i = 0; i < 40; ++i) {
    // alternate the two body pairs (a-b and world-a) and the order the geoms are written in
    const std::string g1 = std::string("a").append(std::to_string(i % 12));
    const std::string g2 = std::string("b").append(std::to_string((5 * i) % 12));
    if (i % 3 == 0) {
      xml += "<pair geom1=\"" + g1 + "\" geom2=\"" + g1 + "\" condim=\"" +
             std::to_string(1 + 2 * (i % 2)) + "\"/>\n";
    } else {
      xml += "<pair geom1=\"" + (i % 2 ? g1 : g2) + "\" geom2=\"" + (i % 2 ? g2 : g1) +
             "\" margin=\"" + std::to_string(i) + "\"/>\n";
    }
  }
  return xml + "</contact>\n</mujoco>\n";
}

TEST_CASE("many pairs of the same bodies are ordered as MuJoCo 2.2.2 orders them", "[compile]") {
  compare("many-pairs", many_pairs_model());
  CHECK(lever::mjcf::load_string(many_pairs_model()).npair == 40);
}

TEST_CASE("compiler corner cases agree with MuJoCo 2.2.2", "[compile]") {
  for (const Case& c : kCases) {
    DYNAMIC_SECTION(c.name) { compare(c.name, c.xml); }
  }
}

TEST_CASE("MuJoCo 2.2.2's verdict on the bad inputs", "[compile][errors]") {
  // lever refuses every one of them; MuJoCo refuses most for the same reason, and accepts the
  // rest: valid MJCF that lever does not support, or mistakes lever refuses on purpose (the
  // table's `why` says which)
  for (const lever::test::BadInput& bad : lever::test::kBadInputs) {
    DYNAMIC_SECTION(bad.id) {
      std::string error;
      const lever::test::MjModelHandle m = lever::test::mujoco_compile(bad.xml, &error);
      INFO(bad.id << ": mujoco says: " << error);
      if (bad.mujoco == lever::test::MuJoCo::kRejects) {
        CHECK(m == nullptr);
      } else {
        INFO("lever refuses it because: " << bad.why);
        CHECK(m != nullptr);
      }
    }
  }
}
