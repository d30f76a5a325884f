// <option><flag> against MuJoCo 2.2.2, flag by flag: each one switched on both sides (lever's bits
// are mjtDisableBit's and mjtEnableBit's) on a model where it changes the answer, then every
// forward output compared at random states (diff::compare_forward) and, for the flags a step
// reads (fwdinv, refsafe, warmstart), after a step. Each case also checks that the flag mattered:
// lever's answer with it differs from lever's answer without it.
#include <mujoco/mujoco.h>
#include <catch2/catch.hpp>

#include <lever/diff/compare.hpp>
#include <lever/diff/report.hpp>
#include <lever/diff/twin.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <lever/harness/models.hpp>
#include <lever/harness/random_state.hpp>
#include <lever/harness/tolerance.hpp>

#include "diff_checks.hpp"
#include "robots.hpp"

namespace lever::test {

namespace {

// A chain whose links overlap their parents: the parent filter is what keeps them apart.
std::string overlapping_chain() {
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "lever_flags_overlapping_chain.xml";
  std::ofstream(file) << R"(<mujoco>
  <worldbody>
    <geom type="plane" size="1 1 0.1"/>
    <body name="a" pos="0 0 1">
      <joint type="ball"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.05"/>
      <body name="b" pos="0.25 0 0">
        <joint axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.05"/>
        <body name="c" pos="0.25 0 0">
          <joint axis="0 0 1"/>
          <geom type="box" size="0.1 0.05 0.05" pos="0.1 0 0"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>)";
  return file.string();
}

struct FlagCase {
  std::string file;
  int disable = 0, enable = 0;  // lever's bits, which are MuJoCo's
  double timestep = 0;          // > 0: both sides take this timestep (refsafe)
  bool wild_ctrl = false;       // controls three times their range (clampctrl)
  bool step = false;            // compare a step too (fwdinv, refsafe, warmstart)
};

std::string case_name(const FlagCase& c) {
  std::string name = std::filesystem::path(c.file).filename().string() + ":";
  for (int k = 0; k < kDisableBits; ++k) {
    if (c.disable & (1 << k)) name += std::string(" ") + kDisableNames[k] + "=disable";
  }
  for (int k = 0; k < kEnableBits; ++k) {
    if (c.enable & (1 << k)) name += std::string(" ") + kEnableNames[k] + "=enable";
  }
  return name;
}

// Whether two Data of the model differ in a forward output that a flag can change: a flag that
// acts moves an output by far more than rounding (1e-9 is no agreement bound, it only tells a
// flag that acted from one that changed nothing).
bool outputs_differ(const Data& a, const Data& b) {
  const auto differ = [](const Eigen::VectorXd& x, const Eigen::VectorXd& y) {
    return x.size() != y.size() || (x.size() > 0 && (x - y).cwiseAbs().maxCoeff() > 1e-9);
  };
  return a.nefc != b.nefc || a.ncon != b.ncon || differ(a.qacc, b.qacc) ||
         differ(a.qfrc_bias, b.qfrc_bias) || differ(a.qfrc_passive, b.qfrc_passive) ||
         differ(a.qfrc_actuator, b.qfrc_actuator) || differ(a.sensordata, b.sensordata);
}

void compare_with_flags(const FlagCase& c, int states) {
  diff::Twin twin(c.file, diff::Path::kLoader);
  Model without = twin.model;
  twin.model.opt.disableflags |= c.disable;
  twin.model.opt.enableflags |= c.enable;
  twin.m->opt.disableflags |= c.disable;
  twin.m->opt.enableflags |= c.enable;
  if (c.enable & kEnableOverride) {  // parameters of its own, unlike every geom's
    twin.model.opt.o_margin = twin.m->opt.o_margin = 0.003;
    twin.model.opt.o_solref = {0.01, 0.5};
    twin.m->opt.o_solref[0] = 0.01;
    twin.m->opt.o_solref[1] = 0.5;
  }
  if (c.timestep > 0) {
    twin.model.opt.timestep = without.opt.timestep = twin.m->opt.timestep = c.timestep;
  }
  set_const(twin.model);
  set_const(without);
  twin.data = Data(twin.model);
  Data plain(without);
  // MuJoCo to convergence, so that its answer is the minimizer lever finds
  twin.m->opt.tolerance = 0;
  twin.m->opt.iterations = std::max(twin.m->opt.iterations, 1000);

  diff::Report report;
  report.set_solver_bound(twin.model.contacts_possible ? diff::kContactSolverBound : 1.0);
  std::mt19937_64 rng(seed_for(c.file) + static_cast<std::uint64_t>(c.disable + 7 * c.enable));
  int mattered = 0;
  for (int k = 0; k < states; ++k) {
    State s = random_state(twin.model, rng);
    if (c.wild_ctrl) s.ctrl *= 3.0;
    diff::compare_forward(twin, s, k, report);
    apply(s, plain);
    forward(without, plain);
    mattered += outputs_differ(twin.data, plain);
    if (c.step) {
      twin.set_state(s);
      step(twin.model, twin.data);
      mj_step(twin.m.get(), twin.d.get());
      for (int i = 0; i < twin.model.nq; ++i) {
        report.compare("qpos after one step", k, twin.data.qpos[i], twin.d->qpos[i],
                       std::to_string(i));
      }
      for (int i = 0; i < twin.model.nv; ++i) {
        report.compare("qvel after one step", k, twin.data.qvel[i], twin.d->qvel[i],
                       std::to_string(i));
      }
      if (c.enable & kEnableFwdinv) {
        mattered += twin.data.qfrc_inverse.norm() > 0;  // what the comparison leaves
        for (int i = 0; i < 2; ++i) {
          report.compare("solver_fwdinv after one step", k, twin.data.solver_fwdinv[i],
                         twin.d->solver_fwdinv[i], std::to_string(i));
        }
        for (int i = 0; i < twin.model.nv; ++i) {
          report.compare("qfrc_inverse after one step", k, twin.data.qfrc_inverse[i],
                         twin.d->qfrc_inverse[i], std::to_string(i));
        }
      }
    }
  }
  const diff::Extreme* worst = nullptr;
  for (const diff::Extreme& e : report.quantities()) {
    if (!worst || e.max_ratio > worst->max_ratio) worst = &e;
  }
  std::printf("%s: worst %.3g of 1e-12 (%s), changed the answer at %d of %d states\n",
              case_name(c).c_str(), worst ? worst->max_ratio : 0.0,
              worst ? worst->quantity.c_str() : "-", mattered, states);
  INFO(case_name(c) << ": the flag changed lever's answer at " << mattered << " of " << states
                    << " states");
  check_within_bound(report);
  if (c.enable & kEnableEnergy) {
    // forward() itself wrote the energy, as compute_energy() finds it
    Data fresh(twin.model);
    State s = random_state(twin.model, rng);
    s.qvel.setConstant(0.5);
    apply(s, fresh);
    forward(twin.model, fresh);
    const std::array<double, 2> by_forward = fresh.energy;
    compute_energy(twin.model, fresh);
    CHECK(by_forward == fresh.energy);
    CHECK(by_forward[1] > 0);
  } else if (!(c.disable & kDisableWarmstart)) {
    // warmstart changes where MuJoCo's iterations stop, never lever's answer (it has no warm
    // start)
    CHECK(mattered > 0);
  }
}

}  // namespace

TEST_CASE("diff: every option flag agrees with MuJoCo where it matters", "[diff][flags]") {
  REQUIRE(mj_version() == 222);
  const std::string sensors = model_path("tests/models/sensors.xml");
  const std::string equality = model_path("tests/models/constraints/equality.xml");
  const std::string friction = model_path("tests/models/constraints/friction_loss.xml");
  const std::string tendons = model_path("tests/models/constraints/tendons.xml");
  const std::string gripper = model_path("models/gripper.xml");
  const std::string chain = overlapping_chain();
  const FlagCase cases[] = {
      {sensors, kDisableGravity},
      {sensors, kDisablePassive, 0, 0, false, true},  // Euler still damps implicitly, as 2.2.2
      {tendons, kDisablePassive},
      {gripper, kDisablePassive, 0, 0, false, true},  // the implicit integrator's damping
      {sensors, kDisableActuation},
      {gripper, kDisableActuation, 0, 0, false, true},
      {sensors, kDisableClampctrl, 0, 0, true},
      {sensors, kDisableLimit},
      {sensors, kDisableSensor},
      {sensors, 0, kEnableEnergy},
      {sensors, kDisableGravity | kDisablePassive, kEnableEnergy},
      {equality, kDisableEquality},
      {equality, kDisableConstraint},
      {friction, kDisableFrictionloss},
      {friction, kDisableWarmstart, 0, 0, false, true},
      {friction, kDisableRefsafe, 0, 0.02, false, true},
      {tendons, kDisableLimit},
      {gripper, kDisableContact},
      {gripper, kDisableConstraint},
      {gripper, 0, kEnableOverride},
      {gripper, 0, kEnableFwdinv, 0, false, true},
      {chain, kDisableFilterparent},
  };
  for (const FlagCase& c : cases) {
    SECTION(case_name(c)) { compare_with_flags(c, 15); }
  }
  std::filesystem::remove(chain);
}

TEST_CASE("diff: the contact override's margin, solref and solimp are MuJoCo's", "[diff][flags]") {
  REQUIRE(mj_version() == 222);
  diff::Twin twin(model_path("models/gripper.xml"), diff::Path::kLoader);
  for (Options* opt : {&twin.model.opt}) {
    opt->enableflags |= kEnableOverride;
    opt->o_margin = 0.004;
    opt->o_solref = {0.01, 0.7};
    opt->o_solimp = {0.8, 0.9, 0.002, 0.4, 3};
  }
  twin.m->opt.enableflags |= mjENBL_OVERRIDE;
  twin.m->opt.o_margin = 0.004;
  twin.m->opt.o_solref[0] = 0.01;
  twin.m->opt.o_solref[1] = 0.7;
  const double solimp[5] = {0.8, 0.9, 0.002, 0.4, 3};
  for (int k = 0; k < 5; ++k) twin.m->opt.o_solimp[k] = solimp[k];
  set_const(twin.model);
  twin.data = Data(twin.model);
  diff::Report report;
  report.set_solver_bound(twin.model.contacts_possible ? diff::kContactSolverBound : 1.0);
  std::mt19937_64 rng(404);
  int contacts = 0;
  for (int k = 0; k < 20; ++k) {
    diff::compare_forward(twin, random_state(twin.model, rng), k, report);
    for (int i = 0; i < twin.data.ncon; ++i) {
      CHECK(twin.data.contact[i].solref == twin.model.opt.o_solref);
      CHECK(twin.data.contact[i].includemargin == 0.004 - 0.0);
    }
    contacts += twin.data.ncon;
  }
  CHECK(contacts > 0);
  check_within_bound(report);
}

}  // namespace lever::test

namespace lever::test {

TEST_CASE("flag.xml (a cloth flapping with the constraint stage off) loads with its flag",
          "[flags][robots]") {
  // its composite cloth is compared with MuJoCo's in composites.cpp
  const std::string file = robots_dir() + "/mujoco-2.2.2/flag/flag.xml";
  if (!robots_present(file)) return;
  const Model model = mjcf::load_file(file);
  CHECK((model.opt.disableflags & kDisableConstraint) != 0);
  // main tendons along x in the 18 rows but the origin's, and the 8 x 18 shear diagonals
  CHECK(model.ntendon == 18 * 8 + 8 * 18);
}

}  // namespace lever::test
