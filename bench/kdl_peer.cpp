// The Orocos KDL peer (see kdl_peer.hpp). The only file that includes KDL's headers.
//
// One KDL segment per lever link, after a fixed segment that places link 0 in the world. Segment
// i's root frame is link i's frame at zero joint displacement; its joint turns (or slides) about
// `axis` through that frame's origin; its tip is link i+1's frame at zero displacement (the site
// for the last link). KDL expresses a segment's inertia in its tip frame, about the tip's origin,
// so each link's mass, centre of mass and rotational inertia are carried into that frame here.
// Armature goes into KDL's joint inertia, which KDL 1.4+ adds to M's diagonal (JntToMass) and to
// the RNE torques, just as lever and MuJoCo add armature.
#include "kdl_peer.hpp"

#include <kdl/chain.hpp>
#include <kdl/chaindynparam.hpp>
#include <kdl/chainfdsolver_recursive_newton_euler.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <kdl/jacobian.hpp>
#include <kdl/jntarray.hpp>
#include <kdl/jntspaceinertiamatrix.hpp>

#include <stdexcept>

namespace lever::bench {

namespace {

KDL::Vector vec(const std::array<double, 3>& v) { return KDL::Vector(v[0], v[1], v[2]); }

KDL::Rotation rot(const std::array<double, 9>& r) {  // row-major
  return KDL::Rotation(r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8]);
}

KDL::Chain build_chain(const ChainSpec& spec) {
  if (spec.links.empty()) throw std::invalid_argument("KdlPeer: the chain has no links");
  KDL::Chain chain;
  // the world -> link 0 at zero displacement; nothing moves and nothing weighs
  const ChainSpec::Link& first = spec.links.front();
  chain.addSegment(KDL::Segment("base", KDL::Joint(KDL::Joint::Fixed),
                                KDL::Frame(rot(first.tree_rot), vec(first.tree_pos))));
  for (std::size_t i = 0; i < spec.links.size(); ++i) {
    const ChainSpec::Link& link = spec.links[i];
    // tip of this segment in link i's frame: the next link at zero displacement, or the site
    const KDL::Frame link_to_tip =
        i + 1 < spec.links.size()
            ? KDL::Frame(rot(spec.links[i + 1].tree_rot), vec(spec.links[i + 1].tree_pos))
            : KDL::Frame(rot(spec.tip_rot), vec(spec.tip_pos));

    const KDL::Joint joint("joint" + std::to_string(i), KDL::Vector::Zero(), vec(link.axis),
                           link.prismatic ? KDL::Joint::TransAxis : KDL::Joint::RotAxis,
                           /*scale=*/1.0, /*offset=*/-link.offset, /*inertia=*/link.armature);

    // inertia in the tip frame: c_tip = R^T (c - p), I_tip = R^T I R, about the centre of mass
    const KDL::Rotation Rt = link_to_tip.M.Inverse();
    const KDL::Vector c_tip = Rt * (vec(link.com) - link_to_tip.p);
    KDL::Rotation Ic;  // the tensor as a 3x3 array, to rotate it with KDL's products
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) Ic(r, c) = link.inertia_com[3 * r + c];
    }
    const KDL::Rotation I_tip = Rt * Ic * link_to_tip.M;
    const KDL::RotationalInertia rotational(I_tip(0, 0), I_tip(1, 1), I_tip(2, 2), I_tip(0, 1),
                                            I_tip(0, 2), I_tip(1, 2));

    // KDL's Segment takes the tip at joint coordinate 0, i.e. at displacement -offset: give it
    // the tip moved there, so that at q = offset the tip is where link_to_tip puts it
    const KDL::Frame tip_at_q0 = joint.pose(0.0) * link_to_tip;
    chain.addSegment(KDL::Segment("link" + std::to_string(i), joint, tip_at_q0,
                                  KDL::RigidBodyInertia(link.mass, c_tip, rotational)));
  }
  return chain;
}

}  // namespace

struct KdlPeer::Impl {
  explicit Impl(const ChainSpec& spec)
      : chain(build_chain(spec)),
        nj(chain.getNrOfJoints()),
        gravity_vec(vec(spec.gravity)),
        fk_solver(chain),
        jac_solver(chain),
        id_solver(chain, gravity_vec),
        dyn_param(chain, gravity_vec),
        fd_solver(chain, gravity_vec),
        q(nj),
        qdot(nj),
        qddot(nj),
        zero(nj),
        tau(nj),
        torques(nj),
        qddot_out(nj),
        H(nj),
        jac(nj),
        f_ext(chain.getNrOfSegments(), KDL::Wrench::Zero()) {}

  // the chain first: every solver keeps a reference to it
  KDL::Chain chain;
  unsigned int nj;
  KDL::Vector gravity_vec;
  KDL::ChainFkSolverPos_recursive fk_solver;
  KDL::ChainJntToJacSolver jac_solver;
  KDL::ChainIdSolver_RNE id_solver;
  KDL::ChainDynParam dyn_param;
  KDL::ChainFdSolver_RNE fd_solver;
  KDL::JntArray q, qdot, qddot, zero, tau, torques, qddot_out;
  KDL::JntSpaceInertiaMatrix H;
  KDL::Jacobian jac;
  KDL::Wrenches f_ext;
  KDL::Frame tip;
};

KdlPeer::KdlPeer(const ChainSpec& spec) : impl_(std::make_unique<Impl>(spec)) {}
KdlPeer::~KdlPeer() = default;

int KdlPeer::nj() const { return static_cast<int>(impl_->nj); }

void KdlPeer::set_state(const double* q, const double* qdot, const double* qddot,
                        const double* tau) {
  for (unsigned int i = 0; i < impl_->nj; ++i) {
    impl_->q(i) = q[i];
    impl_->qdot(i) = qdot[i];
    impl_->qddot(i) = qddot[i];
    impl_->tau(i) = tau[i];
  }
}

int KdlPeer::fk() { return impl_->fk_solver.JntToCart(impl_->q, impl_->tip); }
int KdlPeer::jacobian() { return impl_->jac_solver.JntToJac(impl_->q, impl_->jac); }
int KdlPeer::rne_bias() {
  return impl_->id_solver.CartToJnt(impl_->q, impl_->qdot, impl_->zero, impl_->f_ext,
                                    impl_->torques);
}
int KdlPeer::rne() {
  return impl_->id_solver.CartToJnt(impl_->q, impl_->qdot, impl_->qddot, impl_->f_ext,
                                    impl_->torques);
}
int KdlPeer::mass() { return impl_->dyn_param.JntToMass(impl_->q, impl_->H); }
int KdlPeer::gravity() { return impl_->dyn_param.JntToGravity(impl_->q, impl_->torques); }
int KdlPeer::forward_dynamics() {
  return impl_->fd_solver.CartToJnt(impl_->q, impl_->qdot, impl_->tau, impl_->f_ext,
                                    impl_->qddot_out);
}

std::vector<double> KdlPeer::torques() const {
  std::vector<double> out(impl_->nj);
  for (unsigned int i = 0; i < impl_->nj; ++i) out[i] = impl_->torques(i);
  return out;
}

std::vector<double> KdlPeer::mass_matrix() const {
  std::vector<double> out(impl_->nj * impl_->nj);
  for (unsigned int r = 0; r < impl_->nj; ++r) {
    for (unsigned int c = 0; c < impl_->nj; ++c) out[r * impl_->nj + c] = impl_->H(r, c);
  }
  return out;
}

std::vector<double> KdlPeer::qddot() const {
  std::vector<double> out(impl_->nj);
  for (unsigned int i = 0; i < impl_->nj; ++i) out[i] = impl_->qddot_out(i);
  return out;
}

std::array<double, 12> KdlPeer::tip_frame() const {
  std::array<double, 12> out{};
  for (int i = 0; i < 3; ++i) out[static_cast<std::size_t>(i)] = impl_->tip.p(i);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      out[3 + 3 * static_cast<std::size_t>(r) + static_cast<std::size_t>(c)] = impl_->tip.M(r, c);
  }
  return out;
}

std::vector<double> KdlPeer::jacobian_matrix() const {
  std::vector<double> out(6 * impl_->nj);
  for (unsigned int r = 0; r < 6; ++r) {
    for (unsigned int c = 0; c < impl_->nj; ++c) out[r * impl_->nj + c] = impl_->jac(r, c);
  }
  return out;
}

}  // namespace lever::bench
