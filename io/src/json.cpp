// The JSON writer on nlohmann-json: lever places the values, nlohmann formats them.
#include <lever/io/json.hpp>

#include <stdexcept>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace lever::json {

// ordered_json: keys stay in the order written, as mjModel's and mjData's fields are listed
using Value = nlohmann::ordered_json;

struct Writer::Document {
  std::FILE* file = nullptr;
  std::string* text = nullptr;
  // the containers being filled, outermost first, each with the key it goes under in its parent
  struct Open {
    Value value;
    std::string key;
  };
  std::vector<Open> open;
  std::string pending_key;
  bool has_key = false;

  // Put a finished value into the innermost open container, or write it when none is open.
  void place(Value v) {
    if (open.empty()) {
      emit(v);
      return;
    }
    Value& parent = open.back().value;
    if (parent.is_object()) {
      if (!has_key) throw std::logic_error("lever::json::Writer: a value in an object needs a key");
      parent[pending_key] = std::move(v);
      has_key = false;
    } else {
      parent.push_back(std::move(v));
    }
  }

  void begin(Value empty) {
    std::string key;
    if (!open.empty() && open.back().value.is_object()) {
      if (!has_key) throw std::logic_error("lever::json::Writer: a value in an object needs a key");
      key = std::move(pending_key);
      has_key = false;
    }
    open.push_back({std::move(empty), std::move(key)});
  }

  void end(bool object) {
    if (open.empty() || open.back().value.is_object() != object) {
      throw std::logic_error("lever::json::Writer: end_object/end_array without its begin");
    }
    Open done = std::move(open.back());
    open.pop_back();
    if (!open.empty() && open.back().value.is_object()) {
      pending_key = std::move(done.key);
      has_key = true;
    }
    place(std::move(done.value));
  }

  void emit(const Value& v) {
    // replace: a name read from a file in Latin-1 must not make the whole output unreadable
    put(v.dump(-1, ' ', false, Value::error_handler_t::replace));
  }

  void put(const std::string& s) {
    if (file != nullptr) {
      std::fwrite(s.data(), 1, s.size(), file);
    } else {
      text->append(s);
    }
  }
};

Writer::Writer(std::FILE* out) : doc_(std::make_unique<Document>()) { doc_->file = out; }
Writer::Writer(std::string* out) : doc_(std::make_unique<Document>()) { doc_->text = out; }
Writer::~Writer() = default;

Writer& Writer::begin_object() {
  doc_->begin(Value::object());
  return *this;
}
Writer& Writer::end_object() {
  doc_->end(true);
  return *this;
}
Writer& Writer::begin_array() {
  doc_->begin(Value::array());
  return *this;
}
Writer& Writer::end_array() {
  doc_->end(false);
  return *this;
}
Writer& Writer::key(const std::string& k) {
  doc_->pending_key = k;
  doc_->has_key = true;
  return *this;
}
Writer& Writer::value(double x) {
  doc_->place(Value(x));  // nlohmann writes a NaN or an infinity as null
  return *this;
}
Writer& Writer::value(int x) { return value(static_cast<long>(x)); }
Writer& Writer::value(long x) {
  doc_->place(Value(x));
  return *this;
}
Writer& Writer::value(bool x) {
  doc_->place(Value(x));
  return *this;
}
Writer& Writer::value(const std::string& s) {
  doc_->place(Value(s));
  return *this;
}
Writer& Writer::values(const Eigen::Ref<const Eigen::VectorXd>& v) {
  begin_array();
  for (Eigen::Index i = 0; i < v.size(); ++i) value(v[i]);
  return end_array();
}
void Writer::newline() { doc_->put("\n"); }

}  // namespace lever::json
