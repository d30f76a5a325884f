// Least-squares identification of the base parameters and the physical model written from them
// (see lever/identify.hpp).
#include <lever/dynamics.hpp>
#include <lever/error.hpp>
#include <lever/identify.hpp>
#include <lever/kinematics.hpp>
#include <lever/spectra.hpp>

#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "names.hpp"
#include "physical_fit.hpp"

namespace lever::identify {

namespace {

using detail::kPerBody;
using detail::label_of;

}  // namespace

std::vector<int> gain_actuators_named(const Model& prior, const std::string& names) {
  const std::vector<int> fixed = gain_actuators(prior);
  if (names == "all") return fixed;
  std::vector<int> out;
  std::stringstream list(names);
  std::string name;
  while (std::getline(list, name, ',')) {
    int found = -1;
    for (int a = 0; a < prior.nu; ++a) {
      if (label_of(prior.actuator_name[a], a) == name) found = a;
    }
    if (found < 0) {
      throw Error("identify: no actuator '" + name + "' in the prior '" + prior.name + "'.");
    }
    if (std::find(fixed.begin(), fixed.end(), found) == fixed.end()) {
      throw Error("identify: actuator '" + name +
                  "' has an affine gain: only a fixed gain (gainprm[0]) is identified.");
    }
    if (std::find(out.begin(), out.end(), found) == out.end()) out.push_back(found);
  }
  if (out.empty()) throw Error("identify: no actuator named in '" + names + "'.");
  return out;
}

std::pair<int, double> known_mass_named(const Model& prior, const std::string& text) {
  const auto equals = text.find('=');
  if (equals == std::string::npos) {
    throw Error("identify: known mass '" + text + "': expected BODY=KG.");
  }
  const std::string name = text.substr(0, equals), value = text.substr(equals + 1);
  int body = -1;
  for (int b = 1; b < prior.nbody; ++b) {
    if (label_of(prior.body_name[b], b) == name) body = b;
  }
  if (body < 0) throw Error("identify: no body '" + name + "' in the prior '" + prior.name + "'.");
  char* end = nullptr;
  const double mass = std::strtod(value.c_str(), &end);
  if (value.empty() || end != value.c_str() + value.size() || !std::isfinite(mass) || !(mass > 0)) {
    throw Error("identify: known mass '" + text + "': '" + value + "' is not a mass > 0 in kg.");
  }
  if (!(prior.body_mass[body] > 0)) {
    throw Error("identify: body '" + name +
                "' has no mass in the prior, so its centre of mass and inertia per unit mass, "
                "which a known mass takes from the prior, are unknown.");
  }
  return {body, mass};
}

Result identify(const Model& prior, const Trajectory& data, const Options& options) {
  const int nv = prior.nv;
  const auto N = static_cast<int>(data.time.size());
  require_simple_actuators(prior, "identify");
  if (data.qpos.rows() != nv || data.qpos.cols() != N || data.qvel.cols() != N ||
      data.qacc.cols() != N || data.force.cols() != N || data.force.rows() != nv) {
    throw Error("identify: the trajectory's arrays do not fit the model (nv " + std::to_string(nv) +
                ", " + std::to_string(N) + " samples).");
  }
  Result r;
  r.gains = options.gains;
  if (!r.gains.empty()) {
    if (data.ctrl.rows() != prior.nu || data.ctrl.cols() != N ||
        data.actuator_force.rows() != prior.nu || data.actuator_force.cols() != N) {
      throw Error(
          "identify: estimating an actuator's gain needs the trajectory's ctrl columns "
          "(ctrl[m] for every actuator).");
    }
  }
  r.base = base_parameters_with_gains(prior, r.gains);  // throws for a gain that is not fixed
  const int rank = r.base.rank;
  r.samples = N;

  // The base regressor stacked over the samples, and the forces it must explain. An actuator
  // whose gain is estimated keeps only its force's gain-free part on the right; the rest is its
  // gain column (-gear * basis) on the left.
  const Eigen::VectorXd pi0 = model_parameters(prior);
  const int n = static_cast<int>(pi0.size());
  const int gain_column0 = n - static_cast<int>(gain_actuators(prior).size());
  const std::vector<int> fixed = gain_actuators(prior);
  std::vector<int> gain_column(r.gains.size());  // each estimated gain's column in pi
  for (std::size_t g = 0; g < r.gains.size(); ++g) {
    gain_column[g] =
        gain_column0 +
        static_cast<int>(std::find(fixed.begin(), fixed.end(), r.gains[g]) - fixed.begin());
  }
  Data work(prior);
  Eigen::MatrixXd Y(nv, n);
  Eigen::MatrixXd W_all(N * nv, rank);
  Eigen::VectorXd target_all(N * nv);
  Eigen::MatrixXd basis(static_cast<Eigen::Index>(r.gains.size()), N);  // force per unit gain
  Eigen::MatrixXd gain_free(static_cast<Eigen::Index>(r.gains.size()), N);
  for (int k = 0; k < N; ++k) {
    work.qpos = data.qpos.col(k);
    work.qvel = data.qvel.col(k);
    work.ctrl.setZero();
    for (const int a : r.gains) work.ctrl[a] = data.ctrl(a, k);
    kinematics(prior, work);
    regressor(prior, work, data.qacc.col(k), Y);
    W_all.middleRows(k * nv, nv) = r.base.base_regressor(Y);
    for (int j = 0; j < prior.njnt; ++j) {  // springs are the prior's
      const int q = prior.jnt_qposadr[j], d = prior.jnt_dofadr[j];
      target_all[k * nv + d] =
          data.force(d, k) + prior.jnt_stiffness[j] * (data.qpos(q, k) - prior.qpos_spring[q]);
    }
    for (std::size_t g = 0; g < r.gains.size(); ++g) {
      const int a = r.gains[g];
      const int j = prior.actuator_trnid[a][0];  // a hinge or slide (the regressor checked)
      const int q = prior.jnt_qposadr[j], d = prior.jnt_dofadr[j];
      const auto G = static_cast<Eigen::Index>(g);
      basis(G, k) =
          actuator_gain_basis(prior, a, data.ctrl(a, k), data.qpos(q, k), data.qvel(d, k));
      gain_free(G, k) = actuator_gain_free_force(prior, a, data.qpos(q, k), data.qvel(d, k));
      target_all[k * nv + d] +=
          prior.actuator_gear[a][0] * (gain_free(G, k) - data.actuator_force(a, k));
    }
  }

  // the full parameters closest to the prior (each scaled by its kind's size) with K pi = theta
  const int bodies = prior.nbody - 1;
  const auto kind_of = [&](int c) {
    if (c >= gain_column0) return 6;                                        // gain
    if (c >= kPerBody * bodies) return c < kPerBody * bodies + nv ? 4 : 5;  // armature, damping
    const int k = c % kPerBody;
    return k == 0 ? 0 : (k <= 3 ? 1 : 2);  // mass, first moment, inertia
  };
  double kind_size[7] = {0, 0, 0, 0, 0, 0, 0};
  for (int c = 0; c < n; ++c)
    kind_size[kind_of(c)] = std::max(kind_size[kind_of(c)], std::abs(pi0[c]));
  Eigen::VectorXd scale(n);
  for (int c = 0; c < n; ++c) {
    const double floor = kind_size[kind_of(c)] > 0 ? 1e-3 * kind_size[kind_of(c)] : 1e-6;
    scale[c] = std::max(std::abs(pi0[c]), floor);
  }
  r.prior = r.base.K * pi0;

  // Known bodies: their parameters move to the known side. A base parameter made of known
  // columns only is known outright and leaves the fit; that is what pins the scale when every
  // gain is estimated.
  Eigen::VectorXd pi_known = pi0;  // the prior with each known body's parameters
  std::vector<char> body_known(static_cast<std::size_t>(bodies), 0);
  for (const auto& [body, mass] : options.known_masses) {
    if (body < 1 || body > bodies || !(prior.body_mass[body] > 0) || !(mass > 0)) {
      throw Error("identify: a known mass needs a body with mass in the prior and a mass > 0.");
    }
    const int at = kPerBody * (body - 1);
    pi_known.segment<kPerBody>(at) = mass / prior.body_mass[body] * pi0.segment<kPerBody>(at);
    body_known[static_cast<std::size_t>(body - 1)] = 1;
  }
  const bool absolute_before = target_all.cwiseAbs().maxCoeff() > 0;
  Eigen::VectorXd known_part = Eigen::VectorXd::Zero(rank);  // K pi restricted to known columns
  std::vector<int> solved;  // the base parameters the least squares estimates
  for (int k = 0; k < rank; ++k) {
    bool unknown_column = false;
    for (int c = 0; c < n; ++c) {
      if (r.base.K(k, c) == 0.0) continue;
      const bool known =
          c < kPerBody * bodies && body_known[static_cast<std::size_t>(c / kPerBody)];
      if (known) {
        known_part[k] += r.base.K(k, c) * pi_known[c];
      } else {
        unknown_column = true;
      }
    }
    if (unknown_column) solved.push_back(k);
  }
  if (!options.known_masses.empty()) {
    target_all -= W_all * known_part;
    Eigen::MatrixXd reduced(W_all.rows(), static_cast<Eigen::Index>(solved.size()));
    // an estimated base parameter's known columns are on the known side now: the fit estimates
    // its unknown part, and known_part adds the rest back
    for (std::size_t j = 0; j < solved.size(); ++j) {
      reduced.col(static_cast<Eigen::Index>(j)) = W_all.col(solved[j]);
    }
    W_all = std::move(reduced);
    if (!r.gains.empty() && !absolute_before && static_cast<int>(solved.size()) == rank) {
      throw Error(
          "identify: the known masses fix no base parameter by themselves (each known body's "
          "parameters appear only in combinations with unknown ones), so they do not pin the "
          "scale the estimated gains and the inertia share: know a body whose own parameters "
          "the data sees (the last link, a payload).");
    }
  }
  const int unknowns = static_cast<int>(solved.size());
  const auto embed = [&](const Eigen::VectorXd& x, const Eigen::VectorXd& fill) {
    Eigen::VectorXd out = fill;
    for (int j = 0; j < unknowns; ++j) out[solved[static_cast<std::size_t>(j)]] += x[j];
    return out;
  };
  const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> KS(r.base.K * scale.asDiagonal());
  const auto closest = [&](const Eigen::VectorXd& theta) -> Eigen::VectorXd {
    return pi0 + scale.cwiseProduct(KS.solve(theta - r.prior));
  };

  // Rows where an estimated-gain actuator's force may be clamped are not linear in the gain:
  // drop them, judged at the current gains (the prior's within a factor of two first), and fit
  // again until the set of dropped rows settles.
  std::vector<char> keep(static_cast<std::size_t>(N * nv), 1);
  Eigen::MatrixXd W;
  Eigen::VectorXd target, estimate;  // of the unknown base parameters
  Eigen::VectorXd gains(static_cast<Eigen::Index>(r.gains.size()));
  for (std::size_t g = 0; g < r.gains.size(); ++g)
    gains[static_cast<Eigen::Index>(g)] = pi0[gain_column[g]];
  for (int pass = 0;; ++pass) {
    std::vector<char> next(keep.size(), 1);
    for (std::size_t g = 0; g < r.gains.size(); ++g) {
      const int a = r.gains[g];
      if (!prior.actuator_forcelimited[a]) continue;
      const auto& range = prior.actuator_forcerange[a];
      const double margin = 0.01 * (range[1] - range[0]);
      const int d = actuator_scalar_dof(prior, a);
      const auto G = static_cast<Eigen::Index>(g);
      // the first fit trusts the prior's gain to a factor of two only: a row is kept when the
      // force is inside the range for every gain in [g/2, 2g]; later fits use the estimate
      const double low = pass == 0 ? 0.5 : 1.0, high = pass == 0 ? 2.0 : 1.0;
      for (int k = 0; k < N; ++k) {
        for (const double factor : {low, high}) {
          const double force = factor * gains[G] * basis(G, k) + gain_free(G, k);
          if (force <= range[0] + margin || force >= range[1] - margin) {
            next[static_cast<std::size_t>(k * nv + d)] = 0;
          }
        }
      }
    }
    if (pass > 0 && next == keep) break;
    keep = next;
    const auto rows = static_cast<Eigen::Index>(std::count(keep.begin(), keep.end(), 1));
    r.equations = static_cast<int>(rows);
    r.dropped = N * nv - r.equations;
    if (r.equations < unknowns + 1) {
      throw Error(
          "identify: " + std::to_string(r.equations) + " equations (samples x dofs" +
          (r.dropped ? ", less " + std::to_string(r.dropped) + " where a force clamps" : "") +
          ") for " + std::to_string(unknowns) + " base parameters: too few samples.");
    }
    W.resize(rows, unknowns);
    target.resize(rows);
    for (Eigen::Index i = 0, row = 0; i < N * nv; ++i) {
      if (!keep[static_cast<std::size_t>(i)]) continue;
      W.row(row) = W_all.row(i);
      target[row++] = target_all[i];
    }
    if (!r.gains.empty() &&
        target.cwiseAbs().maxCoeff() <= 1e-12 * std::max(1.0, W.cwiseAbs().maxCoeff())) {
      throw Error(
          "identify: with the gains of every actuator estimated, nothing in the data is "
          "known in absolute terms (no spring, stop, gain-free actuator force or actuator of "
          "known gain): the gains and the inertia scale together. Estimate fewer gains.");
    }
    estimate = Eigen::ColPivHouseholderQR<Eigen::MatrixXd>(W).solve(target);
    r.estimate = embed(estimate, known_part);
    if (r.gains.empty() || pass >= 20) break;
    const Eigen::VectorXd pi = closest(r.estimate);
    for (std::size_t g = 0; g < r.gains.size(); ++g)
      gains[static_cast<Eigen::Index>(g)] = pi[gain_column[g]];
  }

  // standard errors and the directions the data does not excite
  const Eigen::VectorXd residual = target - W * estimate;
  r.residual_rms = std::sqrt(residual.squaredNorm() / r.equations);
  const double dof = r.equations - unknowns;
  const Eigen::MatrixXd inverse_information =
      (W.transpose() * W).ldlt().solve(Eigen::MatrixXd::Identity(unknowns, unknowns));
  const Eigen::VectorXd no_error = Eigen::VectorXd::Zero(rank);  // a known base parameter's
  r.ols_standard_error = embed(
      (residual.squaredNorm() / dof * inverse_information.diagonal()).cwiseMax(0.0).cwiseSqrt(),
      no_error);
  // Cluster-robust (sandwich) covariance: a sample's dofs share their errors (a qacc error e
  // enters every row as M e), and differenced qacc's errors are correlated between neighbouring
  // samples (each qvel error enters two differences); errors in separate clusters are taken as
  // independent. Clusters: one sample, or ten consecutive ones for differenced qacc.
  {
    const int per_cluster = data.qacc_differenced ? 10 : 1;
    Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(unknowns, unknowns);
    Eigen::VectorXd score = Eigen::VectorXd::Zero(unknowns);
    int clusters = 0, current = -1;
    for (Eigen::Index i = 0, row = 0; i < N * nv; ++i) {
      if (!keep[static_cast<std::size_t>(i)]) continue;
      const int cluster = static_cast<int>(i / nv) / per_cluster;
      if (cluster != current) {
        meat += score * score.transpose();
        score.setZero();
        current = cluster;
        ++clusters;
      }
      score += W.row(row).transpose() * residual[row];
      ++row;
    }
    meat += score * score.transpose();
    if (clusters > unknowns + 1) {
      const double correction =
          clusters / (clusters - 1.0) * (r.equations - 1.0) / dof;  // small-sample, as Stata's
      r.standard_error = embed((correction * inverse_information * meat * inverse_information)
                                   .diagonal()
                                   .cwiseMax(0.0)
                                   .cwiseSqrt(),
                               no_error);
    } else {
      r.standard_error = r.ols_standard_error;  // too few clusters for the sandwich
    }
  }

  Eigen::VectorXd norms = W.colwise().norm().transpose();
  for (int c = 0; c < unknowns; ++c) norms[c] = norms[c] > 0 ? norms[c] : 1.0;
  // W is tall (rows >= unknowns): its full V is the thin one
  const SingularValueDecomposition svd =
      singular_value_decomposition(W * norms.cwiseInverse().asDiagonal());
  const Eigen::VectorXd& s = svd.sigma;
  for (int c = 0; c < unknowns; ++c) {
    if (s[c] >= 1e-6 * s[0]) continue;
    int dominant = 0;
    svd.V.col(c).cwiseAbs().maxCoeff(&dominant);
    const std::string& name =
        r.base.names[static_cast<std::size_t>(solved[static_cast<std::size_t>(dominant)])];
    if (std::find(r.unexcited.begin(), r.unexcited.end(), name) == r.unexcited.end()) {
      r.unexcited.push_back(name);
    }
  }

  // The physical model that fits the data, closest to the prior (physical_fit.hpp): the data's
  // metric is |W d| = |R d| over the estimated base parameters (the known ones are fixed with
  // their bodies).
  detail::PhysicalProblem problem;
  problem.prior = pi_known;
  problem.K = r.base.K;
  problem.estimate = r.estimate;
  {
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(W);
    const Eigen::MatrixXd R_solved = qr.matrixQR().topRows(unknowns).triangularView<Eigen::Upper>();
    problem.R = Eigen::MatrixXd::Zero(unknowns, rank);
    for (int j = 0; j < unknowns; ++j) {
      problem.R.col(solved[static_cast<std::size_t>(j)]) = R_solved.col(j);
    }
  }
  problem.body_free.assign(static_cast<std::size_t>(bodies), 0);
  for (int b = 1; b <= bodies; ++b) {
    // a massless body (a frame) stays massless; a known body keeps its known parameters
    problem.body_free[static_cast<std::size_t>(b - 1)] =
        prior.body_mass[b] > 0 && !body_known[static_cast<std::size_t>(b - 1)];
  }
  for (int c = kPerBody * bodies; c < gain_column0; ++c) {  // armature, damping: >= 0
    problem.linear.push_back(c);
    problem.linear_nonnegative.push_back(1);
  }
  for (const int c : gain_column) {
    problem.linear.push_back(c);
    problem.linear_nonnegative.push_back(0);
  }
  problem.linear_scale = scale;
  const detail::PhysicalFit fit = detail::fit_physical(problem);
  r.parameters = fit.parameters;
  r.physical_estimate = fit.base;
  r.estimate_physical = fit.reached;
  r.physical_residual_rms =
      std::sqrt((residual.squaredNorm() + fit.misfit * fit.misfit) / r.equations);
  r.distance_to_prior.assign(static_cast<std::size_t>(prior.nbody), 0.0);
  for (int b = 1; b <= bodies; ++b) {
    r.distance_to_prior[static_cast<std::size_t>(b)] =
        fit.distance[static_cast<std::size_t>(b - 1)];
  }

  // armature and damping are fitted as squares: what is left of the hair they start from when
  // the prior's is zero and the data wants none is zero
  for (int c = kPerBody * bodies; c < gain_column0; ++c) {
    if (r.parameters[c] < 1e-12 * scale[c]) r.parameters[c] = 0.0;
  }

  try {
    Model check = prior;
    set_model_parameters(check, r.parameters);
  } catch (const Error& e) {
    r.not_physical = e.what();
  }
  return r;
}

Model identified_model(const Model& prior, const Result& result) {
  Model out = prior;
  set_model_parameters(out, result.parameters);
  return out;
}

}  // namespace lever::identify
