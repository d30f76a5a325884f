// lever/kinematics.hpp: poses of links, bodies, centres of mass and sites, and site Jacobians.
#pragma once

#include <Eigen/Core>

#include <lever/data.hpp>
#include <lever/model.hpp>

namespace lever {

/// Forward kinematics at data.qpos (MuJoCo's mj_kinematics and mj_comPos): writes the poses
/// xpos, xquat, xmat, xipos, ximat, site_xpos, site_xmat, the joints' xanchor and xaxis, and the
/// shared spatial quantities subtree_com, cdof and cinert that crba(), rnea() and the Jacobians
/// use.
void kinematics(const Model& model, Data& data);

/// The frames alone, at data.qpos (what mj_kinematics places, without the quaternions): each
/// body's xpos and xmat, xipos and ximat, the joints' xanchor and xaxis, geom_xpos, geom_xmat,
/// site_xpos and site_xmat. Leaves xquat and the com-frame quantities as they were; kinematics()
/// computes all of them.
void poses(const Model& model, Data& data);

/// Translational (jacp) and rotational (jacr) Jacobians of a site, 3 x nv each, world frame
/// (MuJoCo's mj_jacSite): site velocity = jacp qvel, angular velocity = jacr qvel.
/// @pre kinematics() was called for the current qpos.
void jac_site(const Model& model, const Data& data, int site, Eigen::Ref<Eigen::MatrixXd> jacp,
              Eigen::Ref<Eigen::MatrixXd> jacr);

/// The same for a point fixed to a body, given in world coordinates (MuJoCo's mj_jac).
void jac_point(const Model& model, const Data& data, int body, const Eigen::Vector3d& point,
               Eigen::Ref<Eigen::MatrixXd> jacp, Eigen::Ref<Eigen::MatrixXd> jacr);

}  // namespace lever
