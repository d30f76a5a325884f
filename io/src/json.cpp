#include <lever/io/json.hpp>

#include <cmath>

namespace lever::json {

std::string escape(const std::string& s) {
  std::string out;
  for (const char ch : s) {
    switch (ch) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (static_cast<unsigned char>(ch) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", ch);
          out += buf;
        } else {
          out += ch;
        }
    }
  }
  return out;
}

void Writer::put(const char* s) {
  if (file_ != nullptr) {
    std::fputs(s, file_);
  } else {
    text_->append(s);
  }
}

void Writer::put(char c) {
  if (file_ != nullptr) {
    std::fputc(c, file_);
  } else {
    text_->push_back(c);
  }
}

void Writer::separator() {
  if (after_key_) {
    after_key_ = false;
    return;
  }
  if (!first_.empty()) {
    if (!first_.back()) put(',');
    first_.back() = false;
  }
}

Writer& Writer::begin_object() {
  separator();
  put('{');
  first_.push_back(true);
  return *this;
}
Writer& Writer::end_object() {
  first_.pop_back();
  put('}');
  return *this;
}
Writer& Writer::begin_array() {
  separator();
  put('[');
  first_.push_back(true);
  return *this;
}
Writer& Writer::end_array() {
  first_.pop_back();
  put(']');
  return *this;
}
Writer& Writer::key(const std::string& k) {
  separator();
  put('"');
  put(escape(k).c_str());
  put("\":");
  after_key_ = true;
  return *this;
}
Writer& Writer::value(double x) {
  separator();
  if (std::isfinite(x)) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", x);
    put(buf);
  } else {
    put("null");
  }
  return *this;
}
Writer& Writer::value(int x) { return value(static_cast<long>(x)); }
Writer& Writer::value(long x) {
  separator();
  char buf[24];
  std::snprintf(buf, sizeof buf, "%ld", x);
  put(buf);
  return *this;
}
Writer& Writer::value(bool x) {
  separator();
  put(x ? "true" : "false");
  return *this;
}
Writer& Writer::value(const std::string& s) {
  separator();
  put('"');
  put(escape(s).c_str());
  put('"');
  return *this;
}
Writer& Writer::values(const Eigen::Ref<const Eigen::VectorXd>& v) {
  begin_array();
  for (Eigen::Index i = 0; i < v.size(); ++i) value(v[i]);
  return end_array();
}
void Writer::newline() { put('\n'); }

}  // namespace lever::json
