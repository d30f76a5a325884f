// Pinocchio's algorithms behind an interface without Eigen (pinocchio_peer.hpp says why).
#include "pinocchio_peer.hpp"

#include <pinocchio/config.hpp>
#include <pinocchio/algorithm/aba-derivatives.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/frames.hpp>
#include <pinocchio/algorithm/kinematics.hpp>
#include <pinocchio/algorithm/rnea-derivatives.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/multibody.hpp>

#include <stdexcept>

namespace lever::bench {

namespace {

std::vector<double> row_major(const Eigen::MatrixXd& m) {
  std::vector<double> out;
  out.reserve(static_cast<std::size_t>(m.size()));
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    for (Eigen::Index c = 0; c < m.cols(); ++c) out.push_back(m(r, c));
  }
  return out;
}

// Pinocchio fills the upper triangle of M only
Eigen::MatrixXd symmetric(const Eigen::MatrixXd& upper) {
  Eigen::MatrixXd m = upper;
  m.triangularView<Eigen::StrictlyLower>() = upper.transpose();
  return m;
}

Eigen::Vector3d vec(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }
Eigen::Matrix3d mat(const std::array<double, 9>& a) {
  Eigen::Matrix3d m;
  m << a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7], a[8];
  return m;
}

// A rotation whose z column is `axis` (unit): the joint frame, in its link's frame
Eigen::Matrix3d z_onto(const Eigen::Vector3d& axis) {
  return Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis).toRotationMatrix();
}

}  // namespace

std::string pinocchio_version() { return PINOCCHIO_VERSION; }

struct PinocchioPeer::Impl {
  pinocchio::Model model;
  pinocchio::Data data;
  pinocchio::FrameIndex frame = 0;
  Eigen::VectorXd offset;  // the links' qpos0
  Eigen::VectorXd q, v, a, tau;
  pinocchio::Data::Matrix6x J;

  explicit Impl(const ChainSpec& spec) {
    model.gravity.linear(vec(spec.gravity));
    offset.resize(static_cast<Eigen::Index>(spec.links.size()));
    pinocchio::JointIndex parent = 0;
    Eigen::Matrix3d parent_turn = Eigen::Matrix3d::Identity();  // the parent's joint frame in its link's
    for (std::size_t i = 0; i < spec.links.size(); ++i) {
      const ChainSpec::Link& link = spec.links[i];
      const Eigen::Matrix3d turn = z_onto(vec(link.axis).normalized());
      // the joint frame in the parent joint's frame at q = 0
      const pinocchio::SE3 placement(parent_turn.transpose() * mat(link.tree_rot) * turn,
                                     parent_turn.transpose() * vec(link.tree_pos));
      const std::string name = "joint" + std::to_string(i);
      const pinocchio::JointIndex joint =
          link.prismatic ? model.addJoint(parent, pinocchio::JointModelPZ(), placement, name)
                         : model.addJoint(parent, pinocchio::JointModelRZ(), placement, name);
      model.armature[static_cast<Eigen::Index>(i)] = link.armature;
      model.appendBodyToJoint(
          joint, pinocchio::Inertia(link.mass, turn.transpose() * vec(link.com),
                                    turn.transpose() * mat(link.inertia_com) * turn));
      offset[static_cast<Eigen::Index>(i)] = link.offset;
      parent = joint;
      parent_turn = turn;
    }
    const pinocchio::SE3 tip(parent_turn.transpose() * mat(spec.tip_rot),
                             parent_turn.transpose() * vec(spec.tip_pos));
    frame = model.addFrame(pinocchio::Frame("tip", parent, tip, pinocchio::OP_FRAME));
    data = pinocchio::Data(model);
    q.setZero(model.nq);
    v.setZero(model.nv);
    a.setZero(model.nv);
    tau.setZero(model.nv);
    J.setZero(6, model.nv);
  }
};

PinocchioPeer::PinocchioPeer(const ChainSpec& spec) : impl_(std::make_unique<Impl>(spec)) {}
PinocchioPeer::~PinocchioPeer() = default;

int PinocchioPeer::nq() const { return impl_->model.nq; }
int PinocchioPeer::nv() const { return impl_->model.nv; }

void PinocchioPeer::set_state(const double* q, const double* v, const double* a,
                              const double* tau) {
  Impl& p = *impl_;
  p.q = Eigen::Map<const Eigen::VectorXd>(q, p.model.nq) - p.offset;
  p.v = Eigen::Map<const Eigen::VectorXd>(v, p.model.nv);
  p.a = Eigen::Map<const Eigen::VectorXd>(a, p.model.nv);
  p.tau = Eigen::Map<const Eigen::VectorXd>(tau, p.model.nv);
}

void PinocchioPeer::rnea() { pinocchio::rnea(impl_->model, impl_->data, impl_->q, impl_->v, impl_->a); }
void PinocchioPeer::nonlinear_effects() {
  pinocchio::nonLinearEffects(impl_->model, impl_->data, impl_->q, impl_->v);
}
void PinocchioPeer::crba() { pinocchio::crba(impl_->model, impl_->data, impl_->q); }
void PinocchioPeer::aba() { pinocchio::aba(impl_->model, impl_->data, impl_->q, impl_->v, impl_->tau); }
void PinocchioPeer::forward_kinematics() {
  pinocchio::forwardKinematics(impl_->model, impl_->data, impl_->q);
}
void PinocchioPeer::frame_jacobian() {
  pinocchio::computeFrameJacobian(impl_->model, impl_->data, impl_->q, impl_->frame,
                                  pinocchio::LOCAL_WORLD_ALIGNED, impl_->J);
}
void PinocchioPeer::rnea_derivatives() {
  pinocchio::computeRNEADerivatives(impl_->model, impl_->data, impl_->q, impl_->v, impl_->a);
}
void PinocchioPeer::aba_derivatives() {
  pinocchio::computeABADerivatives(impl_->model, impl_->data, impl_->q, impl_->v, impl_->tau);
}

std::vector<double> PinocchioPeer::tau() const {
  return {impl_->data.tau.data(), impl_->data.tau.data() + impl_->model.nv};
}
std::vector<double> PinocchioPeer::bias() const {
  return {impl_->data.nle.data(), impl_->data.nle.data() + impl_->model.nv};
}
std::vector<double> PinocchioPeer::mass_matrix() const { return row_major(symmetric(impl_->data.M)); }
std::vector<double> PinocchioPeer::acceleration() const {
  return {impl_->data.ddq.data(), impl_->data.ddq.data() + impl_->model.nv};
}
std::vector<double> PinocchioPeer::jacobian() const { return row_major(impl_->J); }
std::array<double, 12> PinocchioPeer::frame_placement() const {
  // computeFrameJacobian places the frame's joint; the frame is placed on it here
  const pinocchio::Frame& f = impl_->model.frames[impl_->frame];
  const pinocchio::SE3 placement = impl_->data.oMi[f.parentJoint] * f.placement;
  std::array<double, 12> out{};
  for (int i = 0; i < 3; ++i) out[static_cast<std::size_t>(i)] = placement.translation()[i];
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out[static_cast<std::size_t>(3 + 3 * r + c)] = placement.rotation()(r, c);
  }
  return out;
}
std::vector<double> PinocchioPeer::dtau_dq() const { return row_major(impl_->data.dtau_dq); }
std::vector<double> PinocchioPeer::dtau_dv() const { return row_major(impl_->data.dtau_dv); }
std::vector<double> PinocchioPeer::dacc_dq() const { return row_major(impl_->data.ddq_dq); }
std::vector<double> PinocchioPeer::dacc_dv() const { return row_major(impl_->data.ddq_dv); }

}  // namespace lever::bench
