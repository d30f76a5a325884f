// stub: being written
#include <lever/lever.hpp>
namespace lever {
void kinematics(const Model&, Data&) {}
void jac_site(const Model&, const Data&, int, Eigen::Ref<Eigen::MatrixXd>, Eigen::Ref<Eigen::MatrixXd>) {}
void jac_point(const Model&, const Data&, int, const Eigen::Vector3d&, Eigen::Ref<Eigen::MatrixXd>, Eigen::Ref<Eigen::MatrixXd>) {}
}
