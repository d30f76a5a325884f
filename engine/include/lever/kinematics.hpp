// lever/kinematics.hpp: poses of links, bodies, centres of mass and sites, and site Jacobians.
#pragma once

#include <Eigen/Core>

#include <lever/data.hpp>
#include <lever/model.hpp>

namespace lever {

/// Forward kinematics at data.qpos (MuJoCo's mj_kinematics and mj_comPos): writes the poses
/// xpos, xquat, xmat, xipos, ximat, site_xpos, site_xmat, the joints' xanchor and xaxis, and the
/// shared spatial quantities subtree_com, cdof and cinert that crba(), rnea() and the Jacobians
/// use. Every pose is MuJoCo's to the bit (its quaternion arithmetic, in its order).
void kinematics(const Model& model, Data& data);

/// The frames alone, at data.qpos (what mj_kinematics places): each body's xpos, xquat and xmat,
/// xipos and ximat, the joints' xanchor and xaxis, geom_xpos, geom_xmat, site_xpos and site_xmat.
/// Leaves the com-frame quantities as they were; kinematics() computes them too.
void poses(const Model& model, Data& data);

/// One site's frame at data.qpos, what an inverse-kinematics loop reads: places the bodies on the
/// path from the site's body to the world (their xpos, xquat and xmat), then the site (site_xpos[site],
/// site_xmat[site]), each bit for bit what poses() writes; normalizes qpos's quaternions as
/// poses() does, and changes nothing else in Data (the other bodies' and sites' frames, the
/// joints' anchors and axes, the inertial and geom frames keep what they held). No allocation.
/// @throws StateError if site is not in 0..nsite-1.
void place_site(const Model& model, Data& data, int site);

/// Translational (jacp) and rotational (jacr) Jacobians of a site, 3 x nv each, world frame
/// (MuJoCo's mj_jacSite): site velocity = jacp qvel, angular velocity = jacr qvel.
/// @pre kinematics() was called for the current qpos.
void jac_site(const Model& model, const Data& data, int site, Eigen::Ref<Eigen::MatrixXd> jacp,
              Eigen::Ref<Eigen::MatrixXd> jacr);

/// The same for a point fixed to a body, given in world coordinates (MuJoCo's mj_jac).
void jac_point(const Model& model, const Data& data, int body, const Eigen::Vector3d& point,
               Eigen::Ref<Eigen::MatrixXd> jacp, Eigen::Ref<Eigen::MatrixXd> jacr);

}  // namespace lever
