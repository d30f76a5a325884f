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

/// Each body's frame alone at data.qpos (xpos, xquat, xmat), what a controller reading its
/// links' placements needs (Pinocchio's forwardKinematics): bit for bit what poses() writes;
/// normalizes qpos's quaternions as poses() does, and changes nothing else in Data (the joints'
/// anchors and axes, the inertial, geom and site frames keep what they held). No allocation.
void body_poses(const Model& model, Data& data);

/// kinematics() without the geom and site frames: the body, inertial and joint frames and the
/// com-frame quantities (subtree_com, cdof, cinert), everything crba(), bias(), rnea() and
/// jac_point() read, bit for bit what kinematics() writes; geom_xpos, geom_xmat, site_xpos and
/// site_xmat keep what they held. No allocation.
void body_kinematics(const Model& model, Data& data);

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

/// jac_site() from data.qpos, without the rest of kinematics(): places the bodies of the site's
/// tree (their frames, joint frames and centres of mass: the tree's centre of mass is where the
/// Jacobian's moments are taken) and the site, then fills the columns of the dofs between the
/// site and the world (zeros elsewhere). jacp, jacr, site_xpos[site] and site_xmat[site] are bit
/// for bit what kinematics() then jac_site() give, and so are the tree's xpos, xquat, xmat,
/// xipos, xanchor, xaxis and subtree_com; nothing else in Data changes (ximat, cdof, cinert, the
/// other trees, geoms and sites keep what they held), but for qpos's quaternions, normalized as
/// kinematics() does. No allocation.
/// @throws StateError if site is not in 0..nsite-1 or a Jacobian is not 3 x nv.
void jac_site_from_q(const Model& model, Data& data, int site, Eigen::Ref<Eigen::MatrixXd> jacp,
                     Eigen::Ref<Eigen::MatrixXd> jacr);

/// The same for a point fixed to a body, given in world coordinates (MuJoCo's mj_jac).
void jac_point(const Model& model, const Data& data, int body, const Eigen::Vector3d& point,
               Eigen::Ref<Eigen::MatrixXd> jacp, Eigen::Ref<Eigen::MatrixXd> jacr);

}  // namespace lever
