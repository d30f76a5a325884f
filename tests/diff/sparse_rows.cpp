// The constraint rows of models MuJoCo 2.2.2 holds sparse against MuJoCo, bit for bit. Its
// <option jacobian> chooses efc_J's layout: "sparse", or "auto" (the default) from 60 dofs on
// (mj_isSparse). Sparse, its products with a row (J qvel, J qacc_smooth, J qacc; the PGS
// solver's A f over efc_AR's rows) add the row's stored entries one after another instead of in
// mju_dot's four running sums; lever sums them so there (constraint_room.hpp, sparse_jacobian in
// lever/model.hpp), and J^T f row after row in both layouts. Checked on the two files of MuJoCo's
// samples with 60 dofs or more (../shared/robots or $LEVER_ROBOTS_DIR), as they are and with
// jacobian="dense", and on small models with jacobian="sparse": efc_J (MuJoCo's sparse rows
// spread out), efc_vel, efc_aref, efc_b, and at MuJoCo's own qacc the forces -D (J qacc - aref)
// and J^T f that mj_inverse finds; the large files' body_invweight0, the bodies' mean inverse
// inertias at qpos0 that a contact's R is proportional to (MuJoCo's solves there skip the simple
// dofs); the small models' PGS sweeps; and that `lever diff` (tools/diff) compares a sparse
// model's efc_J too.
#include <mujoco/mujoco.h>
#include <catch2/catch.hpp>

#include <lever/diff/runs.hpp>
#include <lever/diff/twin.hpp>
#include <lever/lever.hpp>

#include <random>
#include <string>
#include <vector>

#include <lever/harness/models.hpp>
#include <lever/harness/random_state.hpp>
#include "bits.hpp"
#include "robots.hpp"

namespace lever::test {

namespace {

// MuJoCo's efc_J, row by row over nv columns: its sparse rows spread out (zero where it stores
// nothing), or its dense ones as they are.
std::vector<double> mujoco_rows(const mjModel* m, const mjData* d) {
  if (!mj_isSparse(m)) return {d->efc_J, d->efc_J + static_cast<std::ptrdiff_t>(d->nefc) * m->nv};
  std::vector<double> J(static_cast<std::size_t>(d->nefc) * m->nv, 0.0);
  for (int r = 0; r < d->nefc; ++r) {
    const int adr = d->efc_J_rowadr[r];
    for (int k = 0; k < d->efc_J_rownnz[r]; ++k) {
      J[static_cast<std::size_t>(r) * m->nv + d->efc_J_colind[adr + k]] = d->efc_J[adr + k];
    }
  }
  return J;
}

// The two files of MuJoCo 2.2.2's samples with 60 dofs or more: 22 humanoids on a floor (594
// dofs; limits and frictionless contacts between limbs, pyramids on the floor) and humanoid100.
const char* const kLargeFiles[] = {"mujoco-2.2.2/humanoid/22_humanoids.xml",
                                   "mujoco-2.2.2/humanoid100/humanoid100.xml"};

// The rows' numbers, lever's against MuJoCo's, over `count` random states of the twin: how many
// differ, of each quantity (efc_J, efc_vel, efc_aref, efc_b; at MuJoCo's qacc, efc_force and
// qfrc_constraint), and how many states, rows and pushing rows were compared.
struct RowsApart {
  int states = 0, rows = 0, pushing = 0;
  int J = 0, vel = 0, aref = 0, b = 0, force = 0, qfrc = 0;
};

RowsApart compare_rows(diff::Twin& twin, int count) {
  const mjModel* m = twin.m.get();
  mjData* d = twin.d.get();
  std::mt19937_64 rng(diff::default_seed(twin.file()));
  RowsApart apart;
  for (int k = 0; k < count; ++k) {
    const State s = random_state(twin.model, rng);
    twin.set_state(s);
    try {
      forward(twin.model, twin.data);
    } catch (const StateError&) {
      continue;  // more contacts than nconmax: lever refuses what MuJoCo drops
    }
    mj_forward(m, d);
    const int n = d->nefc, nv = m->nv;
    if (d->ncon != twin.data.ncon || n != twin.data.nefc) continue;
    ++apart.states;
    apart.rows += n;
    const std::vector<double> J = mujoco_rows(m, d);
    apart.J += numbers_apart(twin.data.efc_J.data(), J.data(), n * nv);
    apart.vel += numbers_apart(twin.data.efc_vel.data(), d->efc_vel, n);
    apart.aref += numbers_apart(twin.data.efc_aref.data(), d->efc_aref, n);
    apart.b += numbers_apart(twin.data.efc_b.data(), d->efc_b, n);
    // the forces at MuJoCo's qacc: a function of it alone
    for (int i = 0; i < nv; ++i) twin.data.qacc[i] = d->qacc[i];
    inverse(twin.model, twin.data);
    mj_inverse(m, d);
    for (int r = 0; r < n; ++r) apart.pushing += d->efc_force[r] != 0;
    apart.force += numbers_apart(twin.data.efc_force.data(), d->efc_force, n);
    apart.qfrc += numbers_apart(twin.data.qfrc_constraint.data(), d->qfrc_constraint, nv);
  }
  INFO(twin.file() << ": " << apart.states << " states, " << apart.rows << " rows, "
                   << apart.pushing << " pushing; numbers apart: efc_J " << apart.J
                   << ", efc_vel " << apart.vel << ", efc_aref " << apart.aref << ", efc_b "
                   << apart.b << ", efc_force " << apart.force << ", qfrc_constraint "
                   << apart.qfrc);
  CHECK(apart.J == 0);
  CHECK(apart.vel == 0);
  CHECK(apart.aref == 0);
  CHECK(apart.b == 0);
  CHECK(apart.force == 0);
  CHECK(apart.qfrc == 0);
  return apart;
}

}  // namespace

TEST_CASE("diff: the rows of a model MuJoCo holds sparse, their products and forces are "
          "MuJoCo's bit for bit",
          "[diff][contact][robots]") {
  REQUIRE(mj_version() == 222);
  const std::string folder = robots_dir();
  if (!robots_present(folder)) return;
  for (const char* name : kLargeFiles) {
    const std::string file = folder + "/" + name;
    diff::Twin twin(file, diff::Path::kLoader);
    const mjModel* m = twin.m.get();
    REQUIRE(m->nv >= 60);
    REQUIRE(m->opt.jacobian == mjJAC_AUTO);  // sparse by size

    // body_invweight0: computed once, at qpos0, when the file is loaded
    const int weights = 2 * m->nbody;
    const int weight_apart =
        numbers_apart(twin.model.body_invweight0.data()->data(), m->body_invweight0, weights);
    INFO(name << ": body_invweight0 " << weight_apart << " of " << weights << " numbers apart");
    CHECK(weight_apart == 0);

    const RowsApart apart = compare_rows(twin, 3);
    CHECK(apart.states >= 2);
    CHECK(apart.pushing > 20);

    // the option overrides the size: jacobian="dense", MuJoCo's dense sums on 60 dofs or more
    twin.m->opt.jacobian = mjJAC_DENSE;
    twin.model.opt.jacobian = JacobianLayout::kDense;
    CHECK(compare_rows(twin, 2).states >= 1);
  }
}

TEST_CASE("diff: option jacobian=\"sparse\" on small models: rows, products, forces and PGS "
          "sweeps are MuJoCo's bit for bit",
          "[diff][contact]") {
  REQUIRE(mj_version() == 222);
  // every kind of row, on models far below 60 dofs: pyramids (the gripper's fingers and box),
  // equality constraints, tendons' limits and friction loss, dofs' friction loss
  for (const char* file : {"models/gripper.xml", "tests/models/constraints/equality.xml",
                           "tests/models/constraints/tendons.xml",
                           "tests/models/constraints/friction_loss.xml"}) {
    diff::Twin twin(model_path(file), diff::Path::kLoader);
    REQUIRE(twin.m->opt.jacobian == mjJAC_AUTO);
    REQUIRE(twin.m->nv < 60);  // dense by size: the option alone makes it sparse
    twin.m->opt.jacobian = mjJAC_SPARSE;
    twin.model.opt.jacobian = JacobianLayout::kSparse;
    const RowsApart apart = compare_rows(twin, 10);
    CHECK(apart.states >= 5);
    CHECK(apart.rows > 0);

    // the PGS solver's sweeps, each row's residual b + (A f)_r summed over efc_AR's stored
    // entries in order: 20 sweeps from zero forces, lever's forces MuJoCo's to the bit
    twin.m->opt.solver = mjSOL_PGS;
    twin.model.opt.solver = Solver::kPGS;
    twin.m->opt.tolerance = twin.model.opt.tolerance = 0;
    twin.m->opt.iterations = twin.model.opt.iterations = 20;
    twin.m->opt.disableflags |= mjDSBL_WARMSTART;
    twin.model.opt.disableflags |= kDisableWarmstart;
    std::mt19937_64 rng(diff::default_seed(twin.file()) + 1);
    int solved = 0, forces_apart = 0;
    for (int k = 0; k < 10; ++k) {
      twin.set_state(random_state(twin.model, rng));
      try {
        forward(twin.model, twin.data);
      } catch (const StateError&) {
        continue;
      }
      mj_forward(twin.m.get(), twin.d.get());
      const int n = twin.d->nefc;
      if (n == 0 || n != twin.data.nefc) continue;
      ++solved;
      forces_apart += numbers_apart(twin.data.efc_force.data(), twin.d->efc_force, n);
    }
    INFO(file << ": PGS on " << solved << " states, " << forces_apart << " forces apart");
    CHECK(solved >= 5);
    CHECK(forces_apart == 0);
  }
}

TEST_CASE("diff: lever diff compares a sparse model's efc_J, MuJoCo's rows spread out",
          "[diff][contact]") {
  REQUIRE(mj_version() == 222);
  // tendons.xml held sparse: its equality, friction-loss and limit rows, each a row of stored
  // entries in MuJoCo (efc_J_rownnz, efc_J_rowadr, efc_J_colind), compared element by element
  diff::Twin twin(model_path("tests/models/constraints/tendons.xml"), diff::Path::kLoader);
  twin.m->opt.jacobian = mjJAC_SPARSE;
  twin.model.opt.jacobian = JacobianLayout::kSparse;
  const diff::Report report = diff::random_states(twin, 5, diff::default_seed(twin.file()));
  const diff::Extreme* J = report.find("efc_J");
  REQUIRE(J != nullptr);
  INFO("efc_J: " << J->compared << " values compared, largest difference " << J->max_abs_diff);
  CHECK(J->compared >= 5 * twin.m->nv);  // every state has rows (the tendons' couplings)
  CHECK(J->max_abs_diff == 0);
}

}  // namespace lever::test
