// The step's derivatives through actuators on sites with a reference site:
// tests/derivatives/refsite_actuators.xml (position servos along and about the axes of a frame on
// another body, a <general> with affine gain and bias against a site of the world, a servo whose
// reference is moved by more dofs than its site, a muscle along one axis; a ball wrist). Under
// Euler, RK4 and implicit, against centred differences of lever's own step (eps 1e-6) and of
// MuJoCo 2.2.2's mj_step (eps 1e-6 and 1e-5; step_differences.hpp), within 1e-6 of the matrix's
// scale, computed both ways here.
// lever's model comes from its own reader (what users get; tests/compile checks that it compiles
// to MuJoCo's parameters), MuJoCo's from its compiler.
#include <catch2/catch.hpp>
#include <lever/diff/twin.hpp>

#include <lever/derivatives.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <string>

#include <lever/harness/models.hpp>
#include "step_checks.hpp"

namespace lever::test::refsite_actuator_derivatives {

using namespace lever::test::step_differences;

TEST_CASE("derivatives through site actuators with a reference site",
          "[derivatives][mujoco][actuators]") {
  diff::Twin twin(model_path("tests/derivatives/refsite_actuators.xml"), diff::Path::kLoader);
  converge(twin);
  const Model& model = twin.model;
  REQUIRE(model.nv == 5);
  REQUIRE(model.na == 1);
  State s = state_of(model);
  for (int i = 0; i < model.nv; ++i) s.qvel[i] = 0.5 * ((i * 3 % 7) - 3) / 3.0 + 0.1;
  Eigen::VectorXd dq(model.nv);
  for (int i = 0; i < model.nv; ++i) dq[i] = 0.4 * ((i * 5 % 7) - 3) / 3.0 + 0.05;
  integrate_pos(model, s.qpos, dq, 1.0);
  s.ctrl << 0.3, -0.8, 0.6, -0.4, 0.7;
  s.act << 0.4;
  {  // every length moves, no force is clamped, and the muscle pulls on its curves' inside
    Data data(model);
    apply(s, data);
    forward(model, data);
    for (int a = 0; a < model.nu; ++a) {
      INFO("actuator " << model.actuator_name[a] << " length " << data.actuator_length[a]);
      CHECK(data.actuator_length[a] != 0);
      CHECK(data.actuator_force[a] != 0);
    }
    const auto& range = model.actuator_lengthrange[4];
    const double L = 0.75 + (data.actuator_length[4] - range[0]) / ((range[1] - range[0]) / 0.3);
    INFO("muscle's normalized length " << L);
    CHECK(L > 0.8);
    CHECK(L < 1.3);
  }
  for (const Integrator integrator :
       {Integrator::kEuler, Integrator::kRK4, Integrator::kImplicit}) {
    twin.set_integrator(integrator);
    const double worst = check_step_derivatives(twin, s);
    INFO("refsite_actuators.xml, " << integrator_name(integrator) << ": worst " << worst
                                   << " of the bound");
    CHECK(worst <= 1);
    WARN("refsite_actuators.xml, " << integrator_name(integrator) << ": worst " << worst
                                   << " of the bound");
  }
}

TEST_CASE("derivatives refuse a slider-crank actuator by name", "[derivatives][actuators]") {
  const Model model = mjcf::load_string(R"(
    <mujoco>
      <worldbody>
        <site name="slider" pos="0 0 0.5"/>
        <body pos="0 0 1"><joint axis="0 1 0"/><geom size="0.1" contype="0" conaffinity="0"/>
          <site name="crank" pos="0.1 0 0"/></body>
      </worldbody>
      <actuator><motor name="crank" cranksite="crank" slidersite="slider" cranklength="0.6"/>
      </actuator>
    </mujoco>)");
  Data data(model);
  Derivatives deriv(model);
  CHECK_THROWS_WITH(step_derivatives(model, data, deriv),
                    Catch::Contains("actuator 'crank' drives a slider-crank"));
}

}  // namespace lever::test::refsite_actuator_derivatives
