// The active set's check of step_derivatives on a spatial tendon's wrap: the derivatives hold
// each wrap's case (wrapping or straight, which pair of tangent points), so a step across a
// switch is reported (deriv.active_set_changes and data's kActiveSetChanges warning) as a
// contact made or lost is. tests/derivatives/wrap_switch.xml: a tendon from a fixed site round a
// fixed post to a site on an arm turning about the post's axis, stepped across the two switches
// and away from them, under Euler, RK4 and implicit.
#include <catch2/catch.hpp>

#include <lever/derivatives.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <lever/harness/models.hpp>

namespace lever::test::active_set_changes {

TEST_CASE("a spatial tendon's wrap switching within a step is an active-set change",
          "[derivatives][tendons]") {
  Model model = mjcf::load_file(model_path("tests/derivatives/wrap_switch.xml"));
  // the tendon's points at an arm angle: 2 straight (its sites), 4 wrapped (two tangent points)
  const auto points = [&](double angle) {
    Data data(model);
    data.qpos[0] = angle;
    forward(model, data);
    return data.ten_wrapnum[0];
  };
  REQUIRE(points(0.336) == 2);  // the wrap starts at pi - 2 acos(1/6) = 0.33489
  REQUIRE(points(0.334) == 4);
  struct Case {
    double angle;
    bool changes;
    const char* what;
  };
  // the arm turns by -0.002 in the step (qvel -1, the spring's torque is negligible over it)
  const Case cases[] = {{0.1, false, "wrapped on one side throughout"},
                        {0.001, true, "across straight: the other pair of tangent points"},
                        {0.336, true, "straight, then wrapped"},
                        {0.4, false, "straight throughout"}};
  for (const Integrator integrator :
       {Integrator::kEuler, Integrator::kRK4, Integrator::kImplicit}) {
    model.opt.integrator = integrator;
    for (const Case& c : cases) {
      INFO("integrator " << static_cast<int>(integrator) << ", angle " << c.angle << ": "
                         << c.what);
      Derivatives deriv(model);
      Data data(model);
      data.qpos[0] = c.angle;
      data.qvel[0] = -1.0;
      step_derivatives(model, data, deriv);
      CHECK(deriv.active_set_changes == c.changes);
      CHECK(data.warning[static_cast<int>(Warning::kActiveSetChanges)].number ==
            (c.changes ? 1 : 0));
    }
  }
}

}  // namespace lever::test::active_set_changes
