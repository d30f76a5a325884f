#include <algorithm>
#include <cmath>
#include <lever/diff/twin.hpp>
#include <lever/error.hpp>
#include <lever/mjcf.hpp>
#include <stdexcept>
#include <vector>

namespace lever::diff {

namespace {

// A restart of MuJoCo's solver that moves qacc by less than this (relative to max(1, |qacc|)) has
// found the minimizer again: a tenth of the 1e-12 agreement bound.
constexpr double kRestartSettled = 1e-13;

Model lever_model(const std::string& file, Path path, const mjModel* m) {
  return path == Path::kLoader ? mjcf::load_file(file) : test::from_mujoco(m);
}

// The two compiled models must at least have the same shape for any comparison to mean anything.
void check_sizes(const Model& model, const mjModel* m) {
  const std::pair<const char*, std::pair<int, int>> sizes[] = {
      {"nq", {model.nq, m->nq}},       {"nv", {model.nv, m->nv}},
      {"nu", {model.nu, m->nu}},       {"nbody", {model.nbody, m->nbody}},
      {"njnt", {model.njnt, m->njnt}}, {"nsite", {model.nsite, m->nsite}}};
  for (const auto& [name, pair] : sizes) {
    if (pair.first != pair.second) {
      throw std::runtime_error(std::string("lever and MuJoCo compile different models: ") + name +
                               " is " + std::to_string(pair.first) + " in lever and " +
                               std::to_string(pair.second) + " in MuJoCo");
    }
  }
}

}  // namespace

const char* path_name(Path path) { return path == Path::kLoader ? "loader" : "engine"; }

const char* path_description(Path path) {
  return path == Path::kLoader
             ? "lever::mjcf::load_file compiles the file (what users get)"
             : "from_mujoco copies MuJoCo's compiled parameters (the engine alone)";
}

Twin::Twin(const std::string& file, Path path) : Twin(file, path, test::mujoco_load(file)) {}

Twin::Twin(const std::string& file, Path path, test::MjModelPtr mj)
    : model(lever_model(file, path, mj.get())),
      data(model),
      m(std::move(mj)),
      d(test::mujoco_data(m.get())),
      file_(file),
      path_(path) {
  check_sizes(model, m.get());
  m->opt.enableflags |= mjENBL_ENERGY;
  // with contacts, MuJoCo's constraint solver run to convergence: its answer is then the
  // problem's unique minimizer, the one lever's exact solve finds (with the default tolerance
  // 1e-8 MuJoCo stops ~1e-11 away from it where contacts are pyramidal). Limit rows alone it
  // solves exactly within its default iterations; equality constraints and friction loss are
  // solved by the Newton method, which a tolerance stops short of the minimizer too.
  const bool friction_loss = std::any_of(
      model.dof_frictionloss.begin(), model.dof_frictionloss.end(), [](double f) { return f > 0; });
  if (model.contacts_possible || model.neq > 0 || friction_loss) {
    m->opt.tolerance = 0;
    m->opt.iterations = std::max(m->opt.iterations, 1000);
    // and lever the same: at tolerance 0 its CG is its exact solve, its PGS runs MuJoCo's sweeps
    // (a file that asks for CG, MuJoCo's cloth, was solved by lever's CG at the file's tolerance
    // 1e-8 against MuJoCo's at 0: 3e-5 apart in qacc, relative)
    model.opt.tolerance = 0;
    model.opt.iterations = m->opt.iterations;
    // MuJoCo's CG at tolerance 0 stalls short of the minimizer, restarted or not (on the cloth
    // 2e-7 from it by MuJoCo's own gradient, 5e-10 restarted, where lever's answer is 5e-14
    // from it): the minimizer does not depend on the method, so MuJoCo's Newton finds it
    if (m->opt.solver == mjSOL_CG) {
      m->opt.solver = mjSOL_NEWTON;
      // Newton's Hessian, its factor with the cones and their sparsity (nv x nv each) live on
      // MuJoCo's stack, where CG's did not
      m->nstack += 3 * m->nv * m->nv + 8 * m->nv;
      d = test::mujoco_data(m.get());
    }
  }
  restart_mujoco_solver = mujoco_solver_stops_short();
  start_key_ = model.nkey > 0 ? 0 : -1;
}

bool Twin::mujoco_solver_stops_short() const {
  // (a restart of PGS would be another run of its sweeps from zero forces, not the same answer)
  return model.contacts_possible && model.opt.cone == Cone::kElliptic &&
         model.opt.solver != Solver::kPGS;
}

void Twin::set_integrator(Integrator integrator) {
  model.opt.integrator = integrator;
  m->opt.integrator = integrator == Integrator::kRK4        ? mjINT_RK4
                      : integrator == Integrator::kImplicit ? mjINT_IMPLICIT
                                                            : mjINT_EULER;
}

void Twin::set_cone(Cone cone, double impratio) {
  model.opt.cone = cone;
  model.opt.impratio = impratio;
  m->opt.cone = cone == Cone::kElliptic ? mjCONE_ELLIPTIC : mjCONE_PYRAMIDAL;
  m->opt.impratio = impratio;
  restart_mujoco_solver = mujoco_solver_stops_short();
}

void Twin::mujoco_forward() { mujoco_forward_converged(m.get(), d.get(), restart_mujoco_solver); }

namespace {

// mj_forward from `given`, warm-started from MuJoCo's own answer while that moves it (at most 20
// times).
void restart_from_own_answer(const mjModel* m, mjData* d, const ForwardInputs& given) {
  for (int restart = 0; restart < 20; ++restart) {
    const std::vector<double> before(d->qacc, d->qacc + m->nv);
    std::copy(before.begin(), before.end(), d->qacc_warmstart);
    given.restore(d);
    mj_forward(m, d);
    // Once at the minimizer, a restart only moves qacc in its last bits: MuJoCo's line search
    // keeps finding rounding-sized decreases of a 1e5 cost and runs all its iterations, so a
    // restart that moves qacc by less than a tenth of the comparison bound ends the loop.
    // (Measured on the elliptic scenes: the first restart moves qacc by up to 5e-10, every
    // later one by under 1e-13, all 1000 iterations each.)
    double moved = 0, scale = 1;
    for (int i = 0; i < m->nv; ++i) {
      moved = std::max(moved, std::abs(d->qacc[i] - before[i]));
      scale = std::max(scale, std::abs(before[i]));
    }
    if (moved <= kRestartSettled * scale) break;
  }
}

}  // namespace

// M^-1 times the cost's gradient, M (qacc - qacc_smooth) - J' force(J qacc - aref), by MuJoCo's
// own functions. mj_constraintUpdate writes the rows' states and forces, which are put back as
// MuJoCo's solver left them.
double mujoco_distance_to_minimizer(const mjModel* m, mjData* d) {
  const int nv = m->nv, nefc = d->nefc;
  if (nefc == 0) return 0;
  const std::vector<int> state(d->efc_state, d->efc_state + nefc);
  const std::vector<double> force(d->efc_force, d->efc_force + nefc);
  const std::vector<double> qfrc(d->qfrc_constraint, d->qfrc_constraint + nv);
  std::vector<double> jar(nefc), dacc(nv), gradient(nv), step(nv);
  mj_mulJacVec(m, d, jar.data(), d->qacc);
  for (int i = 0; i < nefc; ++i) jar[i] -= d->efc_aref[i];
  mj_constraintUpdate(m, d, jar.data(), nullptr, 0);
  for (int i = 0; i < nv; ++i) dacc[i] = d->qacc[i] - d->qacc_smooth[i];
  mj_mulM(m, d, gradient.data(), dacc.data());
  for (int i = 0; i < nv; ++i) gradient[i] -= d->qfrc_constraint[i];
  mj_solveM(m, d, step.data(), gradient.data(), 1);
  std::copy(state.begin(), state.end(), d->efc_state);
  std::copy(force.begin(), force.end(), d->efc_force);
  std::copy(qfrc.begin(), qfrc.end(), d->qfrc_constraint);
  double distance = 0, scale = 1;
  for (int i = 0; i < nv; ++i) {
    distance = std::max(distance, std::abs(step[i]));
    scale = std::max(scale, std::abs(d->qacc[i]));
  }
  return distance / scale;
}

ForwardInputs::ForwardInputs(const mjModel* m, const mjData* d)
    : qpos_(d->qpos, d->qpos + m->nq), mocap_quat_(d->mocap_quat, d->mocap_quat + 4 * m->nmocap) {}

void ForwardInputs::restore(mjData* d) const {
  std::copy(qpos_.begin(), qpos_.end(), d->qpos);
  std::copy(mocap_quat_.begin(), mocap_quat_.end(), d->mocap_quat);
}

void mujoco_forward_converged(const mjModel* m, mjData* d, bool restart_solver) {
  const ForwardInputs given(m, d);
  mj_forward(m, d);
  if (restart_solver) converge_mujoco_solver(m, d, given);
}

void converge_mujoco_solver(const mjModel* m, mjData* d, const ForwardInputs& given) {
  restart_from_own_answer(m, d, given);
  const double warm = mujoco_distance_to_minimizer(m, d);
  if (warm <= kStalled) return;
  // Stuck short of the minimizer, where MuJoCo's line search finds no decrease of its cost: on
  // tests/diff/contact_scenes/legged_elliptic.xml (implicit lockstep, step 3659) 6e-7 from it in
  // qacc, its own gradient 3e-6 there and 4e-14 at lever's answer, the two costs equal to the
  // last bit (7e-12 of 4.7e4), and every restart stays put (its first line search returns no
  // step). About 1 forward in 200 comes here, nearly all at rounding level. A cold start (from
  // qacc_smooth) reaches the minimizer along another path; the answer nearer to it by MuJoCo's
  // own gradient is kept.
  test::MjDataPtr warm_answer = test::mujoco_data(m);
  mj_copyData(warm_answer.get(), m, d);
  std::copy(d->qacc_smooth, d->qacc_smooth + m->nv, d->qacc_warmstart);
  given.restore(d);
  mj_forward(m, d);
  restart_from_own_answer(m, d, given);
  if (mujoco_distance_to_minimizer(m, d) >= warm) mj_copyData(d, m, warm_answer.get());
}

void mujoco_step_converged(const mjModel* m, mjData* d, bool restart_solver) {
  if (restart_solver) {  // mj_step's forward warm-started from the converged answer
    const ForwardInputs given(m, d);
    mujoco_forward_converged(m, d, true);
    std::copy(d->qacc, d->qacc + m->nv, d->qacc_warmstart);
    given.restore(d);
  }
  mj_step(m, d);
}

void set_mujoco_state(const mjModel* m, mjData* d, const test::State& s) {
  d->time = s.time;
  for (int i = 0; i < m->nq; ++i) d->qpos[i] = s.qpos[i];
  for (int i = 0; i < m->nv; ++i) {
    d->qvel[i] = s.qvel[i];
    d->qfrc_applied[i] = s.qfrc_applied[i];
    d->qacc_warmstart[i] = 0.0;
  }
  for (int a = 0; a < m->nu; ++a) d->ctrl[a] = s.ctrl[a];
  for (int i = 0; i < m->na && i < s.act.size(); ++i) d->act[i] = s.act[i];
}

void Twin::set_state(const test::State& s) {
  test::apply(s, data);
  data.qacc_warmstart.setZero();  // as MuJoCo's (set_mujoco_state)
  set_mujoco_state(m.get(), d.get(), s);
}

void Twin::follow_mujoco() {
  data.time = d->time;
  for (int i = 0; i < m->nq; ++i) data.qpos[i] = d->qpos[i];
  for (int i = 0; i < m->nv; ++i) {
    data.qvel[i] = d->qvel[i];
    data.qfrc_applied[i] = d->qfrc_applied[i];
    data.qacc_warmstart[i] = d->qacc_warmstart[i];  // where a warm-started PGS solve begins
  }
  for (int a = 0; a < m->nu; ++a) data.ctrl[a] = d->ctrl[a];
  for (int i = 0; i < m->na; ++i) data.act[i] = d->act[i];
}

void Twin::reset() {
  if (start_key_ >= 0) {
    reset_keyframe(model, data, start_key_);
    mj_resetDataKeyframe(m.get(), d.get(), start_key_);
    return;
  }
  lever::reset(model, data);
  mj_resetData(m.get(), d.get());
}

void Twin::start_from_key(const std::string& key) {
  const int id = model.key(key);
  if (id < 0) {
    reset_keyframe(model, data, key);  // throws the engine's message, which lists the keyframes
  }
  // lever and MuJoCo number a file's keyframes alike, in the order they are written
  if (id < 0 || id >= m->nkey) {
    throw StateError("keyframe '" + key + "' is not in MuJoCo's compiled model");
  }
  start_key_ = id;
}

std::string Twin::start_name() const {
  return start_key_ >= 0 ? "keyframe '" + model.key_name[start_key_] + "'" : "rest at qpos0";
}

}  // namespace lever::diff
