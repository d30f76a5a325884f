// A small JSON reader for the programs that read JSON lever's tools write: the tests of
// `lever check --json` and the benchmark report (Google Benchmark's output). Objects, arrays,
// numbers, strings, true/false/null; it throws std::runtime_error on anything malformed, so
// "it parses" is a test. Header-only and standard C++ only.
#pragma once

#include <cctype>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace lever::test::json {

struct Value {
  enum class Kind { kNull, kBool, kNumber, kString, kArray, kObject } kind = Kind::kNull;
  bool boolean = false;
  double number = NAN;
  std::string string;
  std::vector<Value> array;
  // an object's members in the order written: keys[i] names members[i] (two vectors, because a
  // container of pairs of a still incomplete type is not allowed)
  std::vector<std::string> keys;
  std::vector<Value> members;

  /// The member named key, or nullptr (also when this is not an object).
  const Value* find(const std::string& key) const {
    for (std::size_t i = 0; i < keys.size(); ++i) {
      if (keys[i] == key) return &members[i];
    }
    return nullptr;
  }
  bool has(const std::string& key) const { return find(key) != nullptr; }

  /// The member named key; throws if there is none.
  const Value& operator[](const std::string& key) const {
    const Value* v = find(key);
    if (kind != Kind::kObject || v == nullptr) throw std::runtime_error("no key '" + key + "'");
    return *v;
  }
  /// Element i of an array; throws if there is none.
  const Value& operator[](std::size_t i) const {
    if (kind != Kind::kArray || i >= array.size()) throw std::runtime_error("no index");
    return array[i];
  }
  std::size_t size() const { return kind == Kind::kArray ? array.size() : members.size(); }

  /// The member named key as text (a number printed), or fallback.
  std::string str(const std::string& key, const std::string& fallback = "") const {
    const Value* v = find(key);
    if (v == nullptr) return fallback;
    if (v->kind == Kind::kString) return v->string;
    if (v->kind == Kind::kNumber) {
      std::ostringstream s;
      s << v->number;
      return s.str();
    }
    return fallback;
  }
  /// The member named key as a number, or fallback.
  double num(const std::string& key, double fallback = NAN) const {
    const Value* v = find(key);
    return v != nullptr && v->kind == Kind::kNumber ? v->number : fallback;
  }
};

class Parser {
 public:
  explicit Parser(std::string text) : s_(std::move(text)) {}

  Value document() {
    Value v = value();
    skip();
    if (i_ != s_.size()) fail("text after the value");
    return v;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error("json: " + what + " at offset " + std::to_string(i_));
  }
  void skip() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  bool take(char c) {
    skip();
    if (i_ < s_.size() && s_[i_] == c) {
      ++i_;
      return true;
    }
    return false;
  }
  void expect(char c) {
    if (!take(c)) fail(std::string("expected '") + c + "'");
  }
  bool word(const char* w) {
    const std::string ws(w);
    if (s_.compare(i_, ws.size(), ws) != 0) return false;
    i_ += ws.size();
    return true;
  }

  Value value() {
    skip();
    if (i_ >= s_.size()) fail("unexpected end");
    Value v;
    const char c = s_[i_];
    if (c == '{') {
      v.kind = Value::Kind::kObject;
      ++i_;
      if (take('}')) return v;
      do {
        skip();
        v.keys.push_back(string());
        expect(':');
        v.members.push_back(value());
      } while (take(','));
      expect('}');
    } else if (c == '[') {
      v.kind = Value::Kind::kArray;
      ++i_;
      if (take(']')) return v;
      do {
        v.array.push_back(value());
      } while (take(','));
      expect(']');
    } else if (c == '"') {
      v.kind = Value::Kind::kString;
      v.string = string();
    } else if (word("true")) {
      v.kind = Value::Kind::kBool;
      v.boolean = true;
    } else if (word("false")) {
      v.kind = Value::Kind::kBool;
    } else if (word("null")) {
      v.kind = Value::Kind::kNull;
    } else {
      v.kind = Value::Kind::kNumber;
      const char* begin = s_.c_str() + i_;
      char* end = nullptr;
      v.number = std::strtod(begin, &end);
      if (end == begin) fail("not a value");
      i_ += static_cast<std::size_t>(end - begin);
    }
    return v;
  }

  std::string string() {
    if (i_ >= s_.size() || s_[i_] != '"') fail("expected a string");
    ++i_;
    std::string out;
    while (i_ < s_.size() && s_[i_] != '"') {
      char c = s_[i_++];
      if (c == '\\') {
        if (i_ >= s_.size()) fail("bad escape");
        const char e = s_[i_++];
        switch (e) {
          case 'n': c = '\n'; break;
          case 't': c = '\t'; break;
          case 'r': c = '\r'; break;
          case 'b': c = '\b'; break;
          case 'f': c = '\f'; break;
          case 'u': {  // keep ASCII, replace anything else
            if (i_ + 4 > s_.size()) fail("bad \\u escape");
            const unsigned long code = std::strtoul(s_.substr(i_, 4).c_str(), nullptr, 16);
            i_ += 4;
            c = code < 128 ? static_cast<char>(code) : '?';
            break;
          }
          default: c = e;  // \" \\ \/
        }
      }
      out += c;
    }
    if (i_ >= s_.size()) fail("unterminated string");
    ++i_;
    return out;
  }

  std::string s_;
  std::size_t i_ = 0;
};

inline Value parse(const std::string& text) { return Parser(text).document(); }

}  // namespace lever::test::json
