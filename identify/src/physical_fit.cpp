// The physically consistent fit (see physical_fit.hpp).
#include "physical_fit.hpp"

#include <Eigen/Cholesky>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <limits>

#include "pseudo_inertia.hpp"

namespace lever::identify::detail {

namespace {

// The data term's weight against the divergence at first: a relative misfit of 1e-4 of
// |R beta_hat| costs as much as a geodesic distance of 1. Light enough that Levenberg-Marquardt
// does not crawl along a stiff valley; raised (as augmented-Lagrangian methods do) whenever a round
// of the multipliers fails to shrink the misfit fourfold.
constexpr double kDataWeight = 1e2;
constexpr double kMaxDataWeight = 1e7;
constexpr double kReached = 1e-12;          // K pi = beta_hat to this fraction of |R beta_hat|
constexpr int kMaxTargets = 60;             // rounds of the method of multipliers
constexpr int kMaxIterations = 200;         // Levenberg-Marquardt iterations per round
constexpr double kNonnegativeStart = 1e-8;  // of the column's scale, for a prior of zero

// The unknowns x: ten log-Cholesky coordinates per free body, then the linear columns' values.
class Layout {
 public:
  Layout(const PhysicalProblem& p) : p_(p) {
    const int bodies = static_cast<int>(p.body_free.size());
    for (int b = 0; b < bodies; ++b) {
      if (!p.body_free[static_cast<std::size_t>(b)]) continue;
      free_.push_back(b);
      Matrix4 J0 = RigidInertia::from_parameters(p.prior.segment<kPerBody>(kPerBody * b))
                       .to_pseudo_inertia();
      // a prior at the edge of the rigid bodies (a thin rod: Sigma singular) is moved inside by
      // a hair, so that the distance from it is finite and it has log-Cholesky coordinates
      const double floor = 1e-9 * J0.trace();
      if (smallest_relative_eigenvalue(J0) * J0.trace() < floor) {
        J0.topLeftCorner<3, 3>() += floor * Eigen::Matrix3d::Identity();
      }
      prior_J_.push_back(J0);
      distance_.emplace_back(J0);
    }
    size_ = kPerBody * static_cast<int>(free_.size()) + static_cast<int>(p.linear.size());
  }

  int size() const { return size_; }
  int bodies() const { return static_cast<int>(free_.size()); }
  int body(int i) const { return free_[static_cast<std::size_t>(i)]; }

  Eigen::VectorXd start() const {
    Eigen::VectorXd x(size_);
    for (int i = 0; i < bodies(); ++i) {
      x.segment<kPerBody>(kPerBody * i) = log_cholesky_of(prior_J_[static_cast<std::size_t>(i)]);
    }
    for (std::size_t l = 0; l < p_.linear.size(); ++l) {
      const int column = p_.linear[l];
      // a nonnegative column starts a hair above zero: x = 0 is a stationary point of x^2
      x[kPerBody * bodies() + static_cast<int>(l)] =
          p_.linear_nonnegative[l]
              ? std::sqrt(std::max(p_.prior[column], kNonnegativeStart * p_.linear_scale[column]))
              : p_.prior[column];
    }
    return x;
  }

  // pi of x, and d pi / d x (n x size) when asked
  Eigen::VectorXd parameters(const Eigen::VectorXd& x, Eigen::MatrixXd* jacobian) const {
    Eigen::VectorXd pi = p_.prior;
    if (jacobian != nullptr) jacobian->setZero(pi.size(), size_);
    for (int i = 0; i < bodies(); ++i) {
      Jacobian10 d;
      const LogCholesky theta = x.segment<kPerBody>(kPerBody * i);
      pi.segment<kPerBody>(kPerBody * body(i)) = parameters_of(theta, jacobian ? &d : nullptr);
      if (jacobian != nullptr) {
        jacobian->block<kPerBody, kPerBody>(kPerBody * body(i), kPerBody * i) = d;
      }
    }
    for (std::size_t l = 0; l < p_.linear.size(); ++l) {
      const int at = kPerBody * bodies() + static_cast<int>(l);
      const bool square = p_.linear_nonnegative[l];
      pi[p_.linear[l]] = square ? x[at] * x[at] : x[at];
      if (jacobian != nullptr) (*jacobian)(p_.linear[l], at) = square ? 2.0 * x[at] : 1.0;
    }
    return pi;
  }

  // the divergence's residuals (10 per free body, one per linear column) and their Jacobian
  Eigen::VectorXd divergence(const Eigen::VectorXd& x, Eigen::MatrixXd* jacobian) const {
    const int rows = kPerBody * bodies() + static_cast<int>(p_.linear.size());
    Eigen::VectorXd r(rows);
    if (jacobian != nullptr) jacobian->setZero(rows, size_);
    for (int i = 0; i < bodies(); ++i) {
      Jacobian10 d;
      const LogCholesky theta = x.segment<kPerBody>(kPerBody * i);
      r.segment<kPerBody>(kPerBody * i) =
          distance_[static_cast<std::size_t>(i)](theta, jacobian ? &d : nullptr);
      if (jacobian != nullptr) {
        jacobian->block<kPerBody, kPerBody>(kPerBody * i, kPerBody * i) = d;
      }
    }
    for (std::size_t l = 0; l < p_.linear.size(); ++l) {
      const int at = kPerBody * bodies() + static_cast<int>(l);
      const int column = p_.linear[l];
      const bool square = p_.linear_nonnegative[l];
      const double value = square ? x[at] * x[at] : x[at];
      r[at] = (value - p_.prior[column]) / p_.linear_scale[column];
      if (jacobian != nullptr) {
        (*jacobian)(at, at) = (square ? 2.0 * x[at] : 1.0) / p_.linear_scale[column];
      }
    }
    return r;
  }

  double body_distance(const Eigen::VectorXd& x, int i) const {
    const LogCholesky theta = x.segment<kPerBody>(kPerBody * i);
    return distance_[static_cast<std::size_t>(i)](theta, nullptr).norm();
  }

 private:
  const PhysicalProblem& p_;
  std::vector<int> free_;
  std::vector<Matrix4> prior_J_;
  std::vector<GeodesicResidual> distance_;
  int size_ = 0;
};

}  // namespace

PhysicalFit fit_physical(const PhysicalProblem& p) {
  const Layout layout(p);
  const auto data_rows = p.R.rows();  // one per estimated base parameter
  const Eigen::MatrixXd RK = p.R * p.K;
  const double data_unit = 1.0 / std::max((p.R * p.estimate).norm(), 1e-300);
  double data_scale = kDataWeight * data_unit;

  // the stacked residual for target t, and its Jacobian
  const auto residual = [&](const Eigen::VectorXd& x, const Eigen::VectorXd& t,
                            Eigen::MatrixXd* jacobian) {
    Eigen::MatrixXd dpi, ddiv;
    const Eigen::VectorXd pi = layout.parameters(x, jacobian ? &dpi : nullptr);
    const Eigen::VectorXd div = layout.divergence(x, jacobian ? &ddiv : nullptr);
    Eigen::VectorXd r(data_rows + div.size());
    r.head(data_rows) = data_scale * (RK * pi - p.R * t);
    r.tail(div.size()) = div;
    if (jacobian != nullptr) {
      jacobian->resize(r.size(), layout.size());
      jacobian->topRows(data_rows) = data_scale * (RK * dpi);
      jacobian->bottomRows(div.size()) = ddiv;
    }
    return r;
  };

  PhysicalFit out;
  Eigen::VectorXd x = layout.start();
  const int rounds = layout.size() > 0 ? kMaxTargets : 0;  // nothing to fit: the prior
  Eigen::VectorXd target = p.estimate;
  const auto misfit_of = [&](const Eigen::VectorXd& xx) {
    return (RK * layout.parameters(xx, nullptr) - p.R * p.estimate).norm();
  };
  const double reached = kReached * (p.R * p.estimate).norm();
  double previous = std::numeric_limits<double>::infinity();
  for (int round = 0; round < rounds; ++round) {
    // Levenberg-Marquardt, damped in the scale of each unknown (the Jacobian's column norms,
    // Marquardt's); each step solves [J; sqrt(mu) D] dx = [-r; 0] by QR, the heavy data rows
    // first; mu follows Nielsen's update
    Eigen::MatrixXd J;
    Eigen::VectorXd r = residual(x, target, &J);
    double cost = r.squaredNorm();
    double mu = 1e-3;
    for (int it = 0; it < kMaxIterations; ++it) {
      ++out.iterations;
      const Eigen::VectorXd D = J.colwise().norm().transpose().cwiseMax(1e-12);
      Eigen::MatrixXd A(J.rows() + J.cols(), J.cols());
      A.topRows(J.rows()) = J;
      A.bottomRows(J.cols()) = (std::sqrt(mu) * D).asDiagonal();
      Eigen::VectorXd b = Eigen::VectorXd::Zero(A.rows());
      b.head(r.size()) = -r;
      const Eigen::VectorXd dx = A.householderQr().solve(b);
      const Eigen::VectorXd x_new = x + dx;
      Eigen::MatrixXd J_new;
      const Eigen::VectorXd r_new = residual(x_new, target, &J_new);
      const double cost_new = r_new.squaredNorm();
      const double predicted = cost - (r + J * dx).squaredNorm();
      if (std::isfinite(cost_new) && cost_new < cost) {
        const double gain = predicted > 0 ? (cost - cost_new) / predicted : 0.0;
        const double decrease = cost - cost_new;
        x = x_new;
        r = r_new;
        J = J_new;
        cost = cost_new;
        mu *= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * gain - 1.0, 3));
        if (decrease <= 1e-18 * cost || dx.norm() <= 1e-12 * (1.0 + x.norm())) break;
      } else {
        mu *= 4.0;
        if (mu > 1e20) break;  // no step lowers the cost: a minimum to rounding
      }
    }
    const double misfit = misfit_of(x);
    if (misfit <= reached) {
      out.reached = true;
      break;
    }
    // settled at the nearest physical fit: at the heaviest weight, the misfit no longer shrinks
    const bool heaviest = data_scale >= (1.0 - 1e-9) * kMaxDataWeight * data_unit;
    if (heaviest && misfit >= previous * (1.0 - 1e-3)) break;
    // the multipliers are rho^2 (t - beta_hat): t moves by what is still missing; and when a
    // round shrank the misfit less than fourfold rho grows, the offset shrinking by the same
    // factor squared so that the multipliers stay
    target += p.estimate - p.K * layout.parameters(x, nullptr);
    if (misfit > 0.25 * previous && !heaviest) {
      const double raised = std::min(3.0 * data_scale, kMaxDataWeight * data_unit);
      target = p.estimate + (target - p.estimate) * std::pow(data_scale / raised, 2);
      data_scale = raised;
    }
    previous = misfit;
  }

  out.parameters = layout.parameters(x, nullptr);
  out.base = p.K * out.parameters;
  out.misfit = (p.R * (out.base - p.estimate)).norm();
  out.reached = out.misfit <= reached;
  out.distance.assign(p.body_free.size(), 0.0);
  for (int i = 0; i < layout.bodies(); ++i) {
    out.distance[static_cast<std::size_t>(layout.body(i))] = layout.body_distance(x, i);
  }
  return out;
}

}  // namespace lever::identify::detail
