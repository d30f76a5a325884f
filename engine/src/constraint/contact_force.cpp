// A contact's force in its frame, from its rows' forces (lever/contact_force.hpp).
#include <lever/contact_force.hpp>
#include <lever/error.hpp>
#include <lever/fields.hpp>

#include <string>

namespace lever {

Eigen::Matrix<double, 6, 1> contact_force(const Model& model, const Data& data, int id) {
  check_fit(model, data, "lever::contact_force");
  if (id < 0 || id >= data.ncon) {
    throw StateError("lever::contact_force: contact " + std::to_string(id) +
                     " does not exist: data.ncon is " + std::to_string(data.ncon) + ".");
  }
  Eigen::Matrix<double, 6, 1> force = Eigen::Matrix<double, 6, 1>::Zero();
  const Contact& contact = data.contact[static_cast<size_t>(id)];
  const int first = contact.efc_address;
  if (first < 0) return force;  // no rows: the contact is beyond its margin and carries nothing
  const int tangents = contact.dim - 1;
  // the cone decides the row count: a pyramid has two edges per tangent, while a frictionless
  // contact or an elliptic cone has one row per component of the force
  const auto row_type = [&](int row) { return data.efc_type[static_cast<size_t>(row)]; };
  const bool pyramid = first < data.nefc && row_type(first) == ConstraintType::kContactPyramidal;
  const int rows = pyramid ? 2 * tangents : contact.dim;
  if (first + rows > data.nefc) {
    throw StateError("lever::contact_force: contact " + std::to_string(id) +
                     "'s rows run past data.nefc: the data was not computed by forward().");
  }
  const double* f = data.efc_force.data() + first;
  if (!pyramid) {
    for (int k = 0; k < contact.dim; ++k) force[k] = f[k];
    return force;
  }
  // Pyramid edges 2k and 2k + 1 push along n + mu_k t_k and n - mu_k t_k: every edge adds its
  // whole force to the normal, and the pair's difference, scaled by mu_k, is the force along t_k.
  for (int k = 0; k < 2 * tangents; ++k) force[0] += f[k];
  for (int k = 0; k < tangents; ++k) {
    force[1 + k] = (f[2 * k] - f[2 * k + 1]) * contact.friction[static_cast<size_t>(k)];
  }
  return force;
}

}  // namespace lever
