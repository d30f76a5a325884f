// Identities between lever's own algorithms: RNEA against CRBA and the bias, the kinetic energy
// against the bodies' motion, and inverse dynamics against forward dynamics.
//
// The bound: 1e-12 relative to the magnitudes involved. Two ways of evaluating the same sum of n
// terms differ by at most about n * eps * (sum of |terms|), eps = 1.1e-16; with the few dozen
// terms a joint's equation holds here that is ~1e-14 of sum |terms|. So a difference beyond
// 1e-12 * max(1, sum |terms|) is a wrong term, not rounding. The scale is the sum of the terms'
// magnitudes, not the result's, because the result can cancel to near zero.
#include "property_models.hpp"

namespace lever::test {

namespace {

constexpr double kRelative = 1e-12;

bool close(double got, double expected, double magnitude) {
  return std::abs(got - expected) <= kRelative * std::max(1.0, magnitude);
}

void evaluate_random_state(const Model& model, Data& data, std::mt19937_64& rng) {
  apply(random_state(model, rng), data);
  forward(model, data);
}

}  // namespace

TEST_CASE("property: rnea(q, qd, qdd) == M qdd + qfrc_bias", "[property][rnea]") {
  for (const ModelCase& c : every_model_and_random_trees()) {
    Data data(c.model);
    std::mt19937_64 rng(c.seed);
    Eigen::VectorXd tau(c.model.nv);
    for (int k = 0; k < kStatesPerModel; ++k) {
      evaluate_random_state(c.model, data, rng);
      const Eigen::VectorXd qdd = random_qacc(c.model, rng);
      rnea(c.model, data, qdd, tau);
      const Eigen::VectorXd expected = data.M * qdd + data.qfrc_bias;
      for (int i = 0; i < c.model.nv; ++i) {
        const double magnitude =
            (data.M.row(i).cwiseAbs() * qdd.cwiseAbs()).value() + std::abs(data.qfrc_bias[i]);
        INFO(c.name << ", seed " << c.seed << ", state " << k << ", dof " << i << ": rnea "
                    << tau[i] << " vs M qdd + bias " << expected[i]);
        CHECK(close(tau[i], expected[i], magnitude));
      }
    }
  }
}

TEST_CASE("property: CRBA column j == rnea(e_j) - qfrc_bias", "[property][crba]") {
  for (const ModelCase& c : every_model_and_random_trees()) {
    Data data(c.model);
    std::mt19937_64 rng(c.seed);
    Eigen::VectorXd tau(c.model.nv);
    for (int k = 0; k < kStatesPerModel / 4; ++k) {  // nv rnea calls per state
      evaluate_random_state(c.model, data, rng);
      for (int j = 0; j < c.model.nv; ++j) {
        rnea(c.model, data, Eigen::VectorXd::Unit(c.model.nv, j), tau);
        for (int i = 0; i < c.model.nv; ++i) {
          const double column = tau[i] - data.qfrc_bias[i];
          INFO(c.name << ", seed " << c.seed << ", state " << k << ", M(" << i << ", " << j
                      << "): crba " << data.M(i, j) << " vs rnea(e_j) - bias " << column);
          CHECK(close(column, data.M(i, j), std::abs(data.M(i, j)) + std::abs(data.qfrc_bias[i])));
        }
      }
    }
  }
}

TEST_CASE("property: 1/2 qvel' M qvel is the sum of the bodies' kinetic energies",
          "[property][energy]") {
  for (const ModelCase& c : every_model_and_random_trees()) {
    const Model& model = c.model;
    Data data(model);
    std::mt19937_64 rng(c.seed);
    Eigen::MatrixXd jacp(3, model.nv), jacr(3, model.nv);
    for (int k = 0; k < kStatesPerModel; ++k) {
      evaluate_random_state(model, data, rng);
      compute_energy(model, data);
      // each body: translation of its centre of mass plus rotation about it; armature is the
      // rotors' inertia, which M carries on its diagonal
      double bodies = 0.0;
      for (int b = 1; b < model.nbody; ++b) {
        jac_point(model, data, b, data.xipos[b], jacp, jacr);
        const Eigen::Vector3d v = jacp * data.qvel, w = jacr * data.qvel;
        const Eigen::Matrix3d inertia =
            data.ximat[b] * model.body_inertia[b].asDiagonal() * data.ximat[b].transpose();
        bodies += 0.5 * model.body_mass[b] * v.squaredNorm() + 0.5 * w.dot(inertia * w);
      }
      for (int i = 0; i < model.nv; ++i)
        bodies += 0.5 * model.dof_armature[i] * data.qvel[i] * data.qvel[i];
      INFO(c.name << ", seed " << c.seed << ", state " << k << ": 1/2 v'Mv " << data.energy[1]
                  << " vs bodies " << bodies);
      // a sum of non-negative terms: no cancellation, the result itself is the scale
      CHECK(close(data.energy[1], bodies, bodies));
    }
  }
}

TEST_CASE("property: forward then inverse gives back qfrc_applied + qfrc_actuator",
          "[property][inverse]") {
  for (const ModelCase& c : every_model_and_random_trees()) {
    const Model& model = c.model;
    Data data(model);
    std::mt19937_64 rng(c.seed);
    for (int k = 0; k < kStatesPerModel; ++k) {
      evaluate_random_state(model, data, rng);
      const Eigen::VectorXd applied = data.qfrc_applied + data.qfrc_actuator;
      // the magnitudes of the terms of the equation of motion, per dof; the constraint forces
      // enter through J^T D (J qacc - aref), so a row's terms are |J| D |J qacc| and |J| D |aref|
      Eigen::VectorXd magnitude = data.M.cwiseAbs() * data.qacc.cwiseAbs() +
                                  data.qfrc_bias.cwiseAbs() + data.qfrc_passive.cwiseAbs() +
                                  data.qfrc_applied.cwiseAbs() + data.qfrc_actuator.cwiseAbs();
      for (int r = 0; r < data.nefc; ++r) {
        const double row = data.efc_D[r] * (std::abs(data.efc_J.row(r).dot(data.qacc)) +
                                            std::abs(data.efc_aref[r]));
        magnitude += data.efc_J.row(r).transpose().cwiseAbs() * row;
      }
      inverse(model, data);
      for (int i = 0; i < model.nv; ++i) {
        INFO(c.name << ", seed " << c.seed << ", state " << k << ", dof " << i << ": inverse "
                    << data.qfrc_inverse[i] << " vs applied + actuator " << applied[i]
                    << " (magnitudes " << magnitude[i] << ")");
        CHECK(close(data.qfrc_inverse[i], applied[i], magnitude[i]));
      }
    }
  }
}

}  // namespace lever::test
