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

  /// Set (or remove) one value directly: what an actuator shortcut implies.
  void set(const std::string& name, Value value) { values_[name] = std::move(value); }
  void erase(const std::string& name) { values_.erase(name); }

 private:
  std::map<std::string, Value, std::less<>> values_;
};

/// Read an actuator element (<motor>, <position>, <velocity>, <general>, in a default class or
/// in <actuator>) over `set`, as MuJoCo 2.2.2's reader does: its attributes first, then what the
/// shortcut implies in <general>'s terms. A motor sets gainprm[0] = 1, gain fixed, bias none; a
/// position servo clears biasprm and sets gainprm[0] = kp (if written) and biasprm[1] = -kp, bias
/// affine; a velocity servo the same with kv and biasprm[2]. MuJoCo 3's kv and inheritrange on a
/// position servo: biasprm[2] = -kv (its own kv, else its class's); inheritrange is kept for the
/// compiler, and refused beside a ctrlrange as MuJoCo 3 refuses it. So every kind shares one
/// prototype per class, and a <general> of a class whose default is a <position> is a position
/// servo.
void apply_actuator(AttrSet& set, const Element& e, const ElementRule& rule);

/// Where a position servo's kv is held in an actuator's AttrSet (kv alone is a velocity servo's
/// gain, and a class has one actuator prototype for every kind).
inline constexpr const char* kPositionKv = "position kv";

/// One default class: a prototype per element kind (one for every actuator kind).
struct DefaultClass {
  std::string name;
  AttrSet joint, geom, site, actuator;
  AttrSet pair;         ///< <contact><pair> defaults
  AttrSet equality;     ///< <equality> defaults (active, solref, solimp)
  AttrSet tendon;       ///< <tendon> defaults
  AttrSet visual_only;  ///< mesh, material, camera, light defaults: checked, not used

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
