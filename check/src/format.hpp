// Number formatting for `lever check`'s text: the lesson's printed digits, numpy-like lists.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

namespace lever::check::fmt {

/// printf("%.*f"), with "-0.000" written as "0.000", inf as "inf" and NaN as "n/a".
std::string fixed(double x, int digits);

/// printf("%g").
std::string general(double x);

/// printf("%.1e"): rounding-error figures.
std::string sci(double x);

/// printf("%.4g"): four significant digits, for figures that span decades.
std::string sig4(double x);

/// Rounded to `decimals` and written without trailing zeros, as numpy prints np.round(x, d):
/// 0.0208333 -> "0.02083", 0.0001 -> "0.0001". With `keep_small`, a non-zero value that would
/// round to 0 keeps two significant digits instead (a small principal moment stays visible).
std::string rounded(double x, int decimals, bool keep_small = true);

/// "[a b c]" with each entry written by general().
std::string list(const Eigen::VectorXd& v);

/// "[a b c]" with each entry written by rounded(x, decimals).
std::string list(const Eigen::VectorXd& v, int decimals);

/// A matrix as Python prints np.round(M, 4).tolist(): [[0.486, 0.1227], [0.1227, 0.0427]].
std::string matrix(const Eigen::MatrixXd& M, int decimals);

/// Items joined by ", ", wrapped at `width` columns; continuation lines start with `indent`.
std::string wrap(const std::string& head, const std::vector<std::string>& items,
                 const std::string& indent, const std::string& tail = "", size_t width = 110);

/// The unit of a joint's force: a hinge's torque or a slide's force.
inline const char* torque_unit(bool hinge) { return hinge ? "N m" : "N"; }

}  // namespace lever::check::fmt
