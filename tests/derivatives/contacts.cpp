// The step's derivatives of models that make contacts: at states without an active contact (the
// smooth derivatives, unchanged) and with contacts pushing (the rows' active set held), against
// centred differences of lever's own step and of MuJoCo 2.2.2's mj_step at tolerance 0 (qpos moved
// with mj_integratePos, the next qpos read with mj_differentiatePos), on lever's scenes (box_drop,
// gripper) and on a small random tree whose free body rests on a plane.
//
// A state is compared where the differences are smooth: MuJoCo's differences with eps = 1e-6 and
// 1e-5 are both compared with lever's A and B, and the active set (which rows push) is the same at
// every differenced state as at the state itself. The bound is 1e-6 of the matrix's scale
// (max(1, max |entry|)): the differences' truncation (eps^2 |f'''|) and rounding (1e-16 |f| / eps)
// are far below it, a missing term (of the order of the derivative) far above.
#include <catch2/catch.hpp>
#include <lever/diff/twin.hpp>

#include <lever/derivatives.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <lever/harness/models.hpp>
#include "step_checks.hpp"

namespace lever::test::contact_derivatives {

namespace {

using namespace lever::test::step_differences;

struct Case {
  std::string name;
  State state;
  int active_contact_rows = 0;  // at least this many contact rows push (0: none may)
};

int pushing_contact_rows(const Model& model, const State& s) {
  Data data(model);
  apply(s, data);
  forward(model, data);
  int n = 0;
  for (int r = 0; r < data.nefc; ++r) {
    n += data.efc_dof[r] < 0 && data.efc_state[r] == ConstraintState::kActive;
  }
  return n;
}

// Compares lever's A and B with lever's own differences and with MuJoCo's (eps 1e-6 and 1e-5);
// returns the worst ratio to the bound against MuJoCo. Where the contact's impedance is curved
// (a distance within solimp's width), the differences' truncation at eps = 1e-5, eps^2 / 6 times
// the third derivative of aref = -K imp(d) (d - margin) along the normal (6 K (dmax - d0) /
// (mid width^2), 1e9 on these scenes), is ten times the bound, and a hundred times smaller at
// 1e-6 (measured: 13.3 and 0.133 of the bound on box_drop at rest): there MuJoCo's eps = 1e-5
// differences are extrapolated (Richardson: (4 D(eps) - D(2 eps)) / 3, still centred differences
// of mj_step, with the eps^2 term taken out).
double compare(diff::Twin& twin, const Case& c, bool curved_impedance) {
  const Model& model = twin.model;
  INFO(c.name << ", " << integrator_name(model.opt.integrator));
  const int pushing = pushing_contact_rows(model, c.state);
  if (c.active_contact_rows == 0) {
    REQUIRE(pushing == 0);
  } else {
    REQUIRE(pushing >= c.active_contact_rows);
  }
  Derivatives deriv(model);
  Data data(model);
  apply(c.state, data);
  step_derivatives(model, data, deriv);
  {  // the flag says whether the set at the step's end (or an RK4 stage) is not the start's
    Data next(model);
    apply(c.state, next);
    const std::vector<int> start = active_set(model, next);
    step(model, next);
    const bool changed = active_set(model, next) != start;
    if (model.opt.integrator == Integrator::kRK4) {
      CHECK((deriv.active_set_changes || !changed));
    } else {
      CHECK(deriv.active_set_changes == changed);
    }
    CHECK(data.warning[static_cast<int>(Warning::kActiveSetChanges)].number ==
          (deriv.active_set_changes ? 1 : 0));
  }

  return check_against_differences(twin, c.state, deriv, curved_impedance);
}

void frictionless(diff::Twin& twin) {
  for (int g = 0; g < twin.model.ngeom; ++g) {
    twin.model.geom_condim[g] = 1;
    twin.m->geom_condim[g] = 1;
  }
}

// A free body (box or sphere) resting on a plane, carrying a random chain of two hinged links
// (which do not collide), written for both engines to compile.
std::string resting_tree_mjcf(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const bool box = u(rng) < 0.5;
  const double a = 0.03 + 0.04 * u(rng), b = 0.03 + 0.04 * u(rng), c = 0.02 + 0.03 * u(rng);
  std::ostringstream x;
  x << "<mujoco model=\"resting_tree\"><option timestep=\"0.002\"/><worldbody>"
    << "<geom type=\"plane\" size=\"1 1 0.1\"/>"
    << "<body pos=\"0 0 " << (box ? c : a) + 0.002 << "\"><freejoint/>";
  if (box) {
    x << "<geom type=\"box\" size=\"" << a << " " << b << " " << c << "\" mass=\"1\"/>";
  } else {
    x << "<geom type=\"sphere\" size=\"" << a << "\" mass=\"1\"/>";
  }
  double z = box ? c : a;
  for (int k = 0; k < 2; ++k) {
    const double length = 0.05 + 0.05 * u(rng);
    // a horizontal axis across the link, and armature: a light link about its own axis would
    // be too stiff for RK4's step (damping over inertia beyond 1e3 / s)
    x << "<body pos=\"0 0 " << z << "\"><joint type=\"hinge\" damping=\"0.5\" armature=\"0.01\" "
      << "axis=\"" << u(rng) << " " << u(rng) - 0.5 << " 0\"/><geom type=\"capsule\" fromto=\"0 0 0 0 0 "
      << length << "\" size=\"0.01\" mass=\"0.1\" contype=\"0\" conaffinity=\"0\"/>";
    z = length;
  }
  x << "</body></body></body></worldbody></mujoco>";
  return x.str();
}

}  // namespace

constexpr Integrator kIntegrators[] = {Integrator::kEuler, Integrator::kRK4,
                                       Integrator::kImplicit};

TEST_CASE("derivatives with contacts: contact-free states, as the smooth derivatives",
          "[derivatives][mujoco][contacts]") {
  for (const Integrator integrator : kIntegrators) {
    {  // a box in the air, turning
      diff::Twin twin(model_path("models/box_drop.xml"), diff::Path::kEngine);
      twin.set_integrator(integrator);
      converge(twin);
      State s = state_of(twin.model);
      s.qvel << 0.3, -0.2, -1.0, 2.0, -1.0, 0.5;
      const double worst = compare(twin, {"box_drop in the air", s, 0}, false);
      UNSCOPED_INFO("box_drop in the air: worst " << worst << " of the bound");
    }
    {  // the gripper open above the table, the box held up in the air beside it
      diff::Twin twin(model_path("models/gripper.xml"), diff::Path::kEngine);
      twin.set_integrator(integrator);
      converge(twin);
      State s = state_of(twin.model);
      s.qpos << -0.1, 0.01, 0.02, 0.15, 0.1, 0.12, 0.9, 0.1, 0.3, 0.2;
      s.qpos.segment<4>(6).normalize();
      s.qvel << 0.1, -0.05, 0.05, 0.2, -0.1, 0.3, 1.0, -0.5, 0.2;
      s.ctrl << -0.05, 0.02, 0.03;
      const double worst = compare(twin, {"gripper, nothing touching", s, 0}, false);
      UNSCOPED_INFO("gripper without contact: worst " << worst << " of the bound");
    }
  }
}

TEST_CASE("derivatives with contacts: pushing contacts, active set held",
          "[derivatives][mujoco][contacts]") {
  for (const Integrator integrator : kIntegrators) {
    for (const int variant : {0, 1, 2}) {
      const bool condim1 = variant == 1, elliptic = variant == 2;
      const std::string cone = condim1    ? "frictionless (condim 1)"
                               : elliptic ? "elliptic (inside the cone)"
                                          : "pyramidal";
      const auto twin_of = [&](const std::string& file) {
        auto twin = std::make_unique<diff::Twin>(file, diff::Path::kEngine);
        twin->set_integrator(integrator);
        converge(*twin);
        if (condim1) frictionless(*twin);
        if (elliptic) twin->set_cone(Cone::kElliptic, 1.0);
        return twin;
      };
      {  // box_drop at rest on a face (its corners within the impedance's width)
        auto twin = twin_of(model_path("models/box_drop.xml"));
        State s = settle(twin->model, state_of(twin->model), 600);
        s.qvel << 0.02, -0.01, 0.01, 0.1, -0.2, 0.05;
        const double worst = compare(*twin, {"box_drop at rest, " + cone, s, 4}, true);
        UNSCOPED_INFO("box_drop resting, " << cone << ": worst " << worst << " of the bound");
      }
      {  // box_drop pressed 1.5 to 2.5 mm into the table, past the impedance's width
        auto twin = twin_of(model_path("models/box_drop.xml"));
        State s = state_of(twin->model);
        s.qpos << 0.01, -0.02, 0.028, std::cos(0.005), std::sin(0.005), 0, 0;
        s.qvel << 0.05, -0.02, 0.01, 0.1, -0.2, 0.05;
        const double worst = compare(*twin, {"box_drop pressed in, " + cone, s, 4}, false);
        UNSCOPED_INFO("box_drop pressed in, " << cone << ": worst " << worst << " of the bound");
      }
      {  // the gripper holding the box (lifted off the table when there is friction)
        auto twin = twin_of(model_path("models/gripper.xml"));
        State s = state_of(twin->model);
        reset_keyframe(twin->model, twin->data, "open");
        s.qpos = twin->data.qpos;
        s.ctrl << -0.235, 0.045, 0.045;
        s = settle(twin->model, s, 400);
        if (!condim1) {
          s.ctrl[0] = -0.2;
          s = settle(twin->model, s, 200);
        }
        const double worst =
            compare(*twin, {"gripper grasping, " + cone, s, condim1 ? 4 : 8}, true);
        UNSCOPED_INFO("gripper grasping, " << cone << ": worst " << worst << " of the bound");
      }
      {  // a random tree resting on its free body
        const std::uint64_t seed = seed_for("contact_derivatives_resting_tree");
        const std::string file = (std::filesystem::temp_directory_path() /
                                  ("lever_contact_tree_" + std::to_string(seed) + ".xml"))
                                     .string();
        std::ofstream(file) << resting_tree_mjcf(seed);
        auto twin = twin_of(file);
        State s = settle(twin->model, state_of(twin->model), 500);
        s.qvel *= 0;
        // (sliding would put an elliptic cone's force on its surface, which is refused)
        if (elliptic) {
          s.qvel.head<3>() << 0, 0, 0.001;
        } else {
          s.qvel.head<3>() << 0.01, 0.02, -0.01;
        }
        const double worst = compare(*twin, {"resting tree, " + cone, s, 1}, true);
        UNSCOPED_INFO("resting tree, " << cone << ": worst " << worst << " of the bound");
      }
    }
  }
}

TEST_CASE("derivatives with contacts: a set that changes within the step is reported",
          "[derivatives][contacts]") {
  const Model model = mjcf::load_file(model_path("models/box_drop.xml"));
  Derivatives deriv(model);
  Data data(model);
  // the box level, its lowest face 0.1 mm above the table, falling at 1 m/s: touches in the step
  data.qpos << 0, 0, 0.0301, 1, 0, 0, 0;
  data.qvel << 0, 0, -1, 0, 0, 0;
  const Eigen::VectorXd qpos = data.qpos, qvel = data.qvel;
  for (const Integrator integrator : kIntegrators) {
    Model m = model;
    m.opt.integrator = integrator;
    data.warning = {};
    step_derivatives(m, data, deriv);
    CHECK(deriv.active_set_changes);
    CHECK(data.warning[static_cast<int>(Warning::kActiveSetChanges)].number == 1);
    if (integrator != Integrator::kRK4) CHECK(data.nefc == 0);  // forward() at the start
    CHECK(deriv.A.allFinite());
    CHECK(data.qpos == qpos);
    CHECK(data.qvel == qvel);
    // the same box 1 cm up: nothing changes
    data.qpos[2] = 0.04;
    step_derivatives(m, data, deriv);
    CHECK_FALSE(deriv.active_set_changes);
    data.qpos[2] = qpos[2];
  }
}

TEST_CASE("derivatives with contacts: d qacc against lever's and MuJoCo's forward differenced",
          "[derivatives][mujoco][contacts]") {
  // forward dynamics at rest on contacts: d qacc / d (qpos tangent, qvel, ctrl), centred
  // differences with eps 1e-6 of lever's forward() and of MuJoCo's mj_forward at tolerance 0
  for (const std::string name : {"models/box_drop.xml", "models/gripper.xml"}) {
    diff::Twin twin(model_path(name), diff::Path::kEngine);
    converge(twin);
    const Model& model = twin.model;
    const int nv = model.nv, nu = model.nu, nq = model.nq;
    State s = state_of(model);
    if (nu > 0) {
      reset_keyframe(model, twin.data, "open");
      s.qpos = twin.data.qpos;
      s.ctrl << -0.235, 0.045, 0.045;
    }
    s = settle(model, s, 600);
    INFO(name);
    REQUIRE(pushing_contact_rows(model, s) >= 4);
    Derivatives deriv(model);
    Data data(model);
    apply(s, data);
    forward_derivatives(model, data, deriv);
    Eigen::MatrixXd analytic(nv, 2 * nv + nu);
    analytic << deriv.dqacc_dq, deriv.dqacc_dv, deriv.dqacc_du;
    constexpr double eps = 1e-6;
    Eigen::MatrixXd own(nv, 2 * nv + nu), theirs(nv, 2 * nv + nu);
    Eigen::VectorXd plus(nv), minus(nv), mj_plus(nv), mj_minus(nv);
    const mjModel* m = twin.m.get();
    mjData* d = twin.d.get();
    for (int c = 0; c < 2 * nv + nu; ++c) {
      for (const double delta : {eps, -eps}) {
        apply(s, data);
        diff::set_mujoco_state(m, d, s);
        if (c < nv) {
          integrate_pos(model, data.qpos, Eigen::VectorXd::Unit(nv, c), delta);
          for (int i = 0; i < nq; ++i) d->qpos[i] = data.qpos[i];
        } else if (c < 2 * nv) {
          data.qvel[c - nv] += delta;
          d->qvel[c - nv] += delta;
        } else {
          data.ctrl[c - 2 * nv] += delta;
          d->ctrl[c - 2 * nv] += delta;
        }
        forward(model, data);
        mj_forward(m, d);
        (delta > 0 ? plus : minus) = data.qacc;
        Eigen::VectorXd& mj = delta > 0 ? mj_plus : mj_minus;
        for (int i = 0; i < nv; ++i) mj[i] = d->qacc[i];
      }
      own.col(c) = (plus - minus) / (2 * eps);
      theirs.col(c) = (mj_plus - mj_minus) / (2 * eps);
    }
    CHECK(ratio_to_bound(analytic, own) <= 1);
    CHECK(ratio_to_bound(analytic, theirs) <= 1);
    UNSCOPED_INFO(name << ": d qacc, worst " << ratio_to_bound(analytic, own) << " (lever), "
                       << ratio_to_bound(analytic, theirs) << " (mj_forward) of the bound");
  }
}

TEST_CASE("derivatives with contacts: a contact whose geometry has no derivative is refused",
          "[derivatives][contacts][refusal]") {
  // a free cylinder standing centred on a static box: a pushing cylinder-box contact, which MuJoCo
  // collides by MPR, whose search ends on its first segment (the origin on the line of the
  // centres), which any motion leaves
  const Model model = mjcf::load_string(R"(<mujoco><worldbody>
      <geom type="box" size="0.2 0.2 0.05"/>
      <body pos="0 0 0.079"><freejoint/><geom type="cylinder" size="0.03 0.03"/></body>
      </worldbody></mujoco>)",
                                        "cylinder_on_box");
  Data data(model);
  Derivatives deriv(model);
  forward(model, data);
  REQUIRE(data.nefc > 0);
  const Eigen::VectorXd qpos = data.qpos;
  CHECK_THROWS_WITH(step_derivatives(model, data, deriv), Catch::Contains("cylinder-box"));
  CHECK_THROWS_WITH(forward_derivatives(model, data, deriv), Catch::Contains("cylinder-box"));
}

}  // namespace lever::test::contact_derivatives
