#include "format.hpp"

#include <cmath>
#include <cstdio>

namespace lever::check::fmt {

namespace {
std::string printf_string(const char* format, double x, int digits = -1) {
  char buf[64];
  if (digits >= 0) {
    // cppcheck-suppress [invalidPrintfArgType_float, wrongPrintfScanfArgNum] // format has "%.*"
    std::snprintf(buf, sizeof buf, format, digits, x);
  } else {
    std::snprintf(buf, sizeof buf, format, x);
  }
  return buf;
}

bool special(double x, std::string& out) {
  if (std::isnan(x)) {
    out = "n/a";
  } else if (std::isinf(x)) {
    out = x > 0 ? "inf" : "-inf";
  } else {
    return false;
  }
  return true;
}

// "-0", "-0.00": a negative sign on a value that prints as zero
std::string drop_negative_zero(std::string s) {
  if (!s.empty() && s[0] == '-' && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);
  return s;
}
}  // namespace

std::string fixed(double x, int digits) {
  std::string out;
  if (special(x, out)) return out;
  return drop_negative_zero(printf_string("%.*f", x, digits));
}

std::string general(double x) {
  std::string out;
  if (special(x, out)) return out;
  return drop_negative_zero(printf_string("%g", x));
}

std::string sci(double x) {
  std::string out;
  if (special(x, out)) return out;
  return printf_string("%.1e", x);
}

std::string sig4(double x) {
  std::string out;
  if (special(x, out)) return out;
  return drop_negative_zero(printf_string("%.4g", x));
}

std::string rounded(double x, int decimals, bool keep_small) {
  std::string out;
  if (special(x, out)) return out;
  const double scale = std::pow(10.0, decimals);
  if (keep_small && x != 0.0 && std::round(x * scale) == 0.0) return printf_string("%.2g", x);
  out = printf_string("%.*f", std::round(x * scale) / scale, decimals);
  if (out.find('.') != std::string::npos) {
    out.erase(out.find_last_not_of('0') + 1);
    if (out.back() == '.') out.pop_back();
  }
  return drop_negative_zero(out);
}

std::string list(const Eigen::VectorXd& v) {
  std::string out = "[";
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (i) out += ' ';
    out += general(v[i]);
  }
  return out + "]";
}

std::string list(const Eigen::VectorXd& v, int decimals) {
  std::string out = "[";
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (i) out += ' ';
    out += rounded(v[i], decimals);
  }
  return out + "]";
}

std::string matrix(const Eigen::MatrixXd& M, int decimals) {
  std::string out = "[";
  for (Eigen::Index r = 0; r < M.rows(); ++r) {
    out += r ? ", [" : "[";
    for (Eigen::Index c = 0; c < M.cols(); ++c) {
      std::string x = rounded(M(r, c), decimals, false);
      if (x.find_first_of(".en") == std::string::npos) x += ".0";  // Python writes floats so
      if (c) out += ", ";
      out += x;
    }
    out += "]";
  }
  return out + "]";
}

std::string wrap(const std::string& head, const std::vector<std::string>& items,
                 const std::string& indent, const std::string& tail, size_t width) {
  std::string out = head;
  size_t line = head.size();  // length of the line being filled
  for (size_t i = 0; i < items.size(); ++i) {
    const std::string piece = items[i] + (i + 1 < items.size() ? "," : tail);
    if (i > 0 && line + 1 + piece.size() > width) {
      out += "\n" + indent + piece;
      line = indent.size() + piece.size();
    } else {
      const std::string gap = (i > 0 || (!head.empty() && head.back() != ' ')) ? " " : "";
      out += gap + piece;
      line += gap.size() + piece.size();
    }
  }
  if (items.empty()) out += tail;
  return out;
}

}  // namespace lever::check::fmt
