// Default classes (<default class=...>, nested) and how an element's attributes combine with them,
// as MuJoCo 2.2.2's reader does it: an element starts as a copy of its class's prototype and its
// own attributes are read over that copy; a partial vector (size, gear, solreflimit, ...)
// overwrites only the numbers it lists. A nested class starts as a copy of its parent as it is
// once the parent's own <joint>/<geom>/<site>/<motor> children have been read.
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "reader.hpp"
#include "schema.hpp"
#include "values.hpp"

namespace lever::mjcf::detail {

/// The attribute values of one element (or one class prototype), by attribute name.
class AttrSet {
 public:
  const Value* find(std::string_view name) const;
  bool has(std::string_view name) const { return find(name) != nullptr; }

  /// Read the attributes written on `e`, checked by `rule`, over the current values.
  void apply(const Element& e, const ElementRule& rule);

 private:
  std::map<std::string, Value, std::less<>> values_;
};

/// One default class: a prototype per element kind.
struct DefaultClass {
  std::string name;
  AttrSet joint, geom, site, motor;

  const AttrSet& prototype(std::string_view tag) const;
  AttrSet& prototype(std::string_view tag);
};

/// All default classes of a model; class 0 is the top-level ("main") class.
class DefaultClasses {
 public:
  DefaultClasses();

  /// Read one top-level <default> section: it edits (and may rename) the top-level class.
  void read_section(const Element& section);

  /// The class named by attribute `attribute` of `e`, or `fallback` if `e` has none.
  int choose(const Element& e, std::string_view attribute, int fallback) const;

  const DefaultClass& at(int id) const { return classes_[static_cast<size_t>(id)]; }

 private:
  void read(const Element& section, int id);
  int find(std::string_view name) const;

  std::vector<DefaultClass> classes_;
};

}  // namespace lever::mjcf::detail
