// <composite> expanded as MuJoCo 2.2.2 expands it; see composite.hpp. The generators follow
// user_composite.cc type by type (MakeParticle, MakeGrid, MakeRope with AddRopeBody, MakeCloth
// with AddClothBody, MakeBox with BoxProject), with the same arithmetic, so that the generated
// frames are MuJoCo's to the last bit.
#include "composite.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "inertia.hpp"  // geom_volume; orientation.hpp: kPi, normalize
#include "parse.hpp"
#include "schema.hpp"

namespace lever::mjcf::detail {

namespace {

constexpr double kMinSpacing = 1e-15;  // mjMINVAL: a smaller spacing is refused

enum class CompositeType { kParticle, kGrid, kRope, kLoop, kCloth, kBox, kCylinder, kEllipsoid };

// the kinds of generated joints and tendons, each with its own defaults (MuJoCo's mjtCompKind)
enum CompositeKind { kJointMain = 0, kTwist, kStretch, kTendonMain, kShear, kKinds };

CompositeType composite_type_named(const std::string& w) {
  if (w == "grid") return CompositeType::kGrid;
  if (w == "rope") return CompositeType::kRope;
  if (w == "loop") return CompositeType::kLoop;
  if (w == "cloth") return CompositeType::kCloth;
  if (w == "box") return CompositeType::kBox;
  if (w == "cylinder") return CompositeType::kCylinder;
  if (w == "ellipsoid") return CompositeType::kEllipsoid;
  return CompositeType::kParticle;
}

bool is_shell_type(CompositeType t) {
  return t == CompositeType::kBox || t == CompositeType::kCylinder ||
         t == CompositeType::kEllipsoid;
}

// MuJoCo's AdjustSoft: level 0 makes a constraint hard, level 1 soft
void adjust_softness(std::vector<double>& solref, std::vector<double>& solimp, int level) {
  solref[0] = level == 0 ? 0.01 : 0.02;
  solimp[0] = solimp[1] = level == 0 ? 0.99 : 0.9;
}

// an integer at `text[at...]` as sscanf's %d reads it (leading blanks, a sign, digits); false if
// none
bool scan_composite_int(const std::string& text, size_t& at, int& value) {
  while (at < text.size() && is_space(text[at])) ++at;
  size_t i = at;
  if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
  const size_t digits = i;
  while (i < text.size() && is_digit(text[i])) ++i;
  if (i == digits) return false;
  value = std::stoi(text.substr(at, i - at));
  at = i;
  return true;
}

std::vector<double> written_numbers(const AttrSet& set, std::string_view name) {
  return set.find(name)->numbers;
}

Value value_of_numbers(std::vector<double> numbers) { return Value{std::move(numbers), "", 0}; }
Value value_of_integer(int n) { return value_of_numbers({static_cast<double>(n)}); }

class CompositeExpander {
 public:
  CompositeExpander(const Element& e, const DefaultClass& main, const AssetSpec& assets,
                    CompositeOutput& out)
      : e_(e), main_(main), assets_(assets), out_(out) {}

  void expand(BodySpec& body) {
    read();
    check();
    switch (type_) {
      case CompositeType::kParticle: particles(body); break;
      case CompositeType::kGrid: grid(body); break;
      case CompositeType::kRope:
      case CompositeType::kLoop: rope(body); break;
      case CompositeType::kCloth: cloth(body); break;
      default: shell(body); break;
    }
  }

 private:
  // ---- reading: xml_native_reader.cc's OneComposite with mjCComposite::SetDefault ---------------

  const Element* child(std::string_view tag) const {
    for (const Element& c : e_.children) {
      if (c.tag == tag) return &c;
    }
    return nullptr;
  }

  void read() {
    const ElementRule& rule = *find_rule("body", "composite");  // the same under <worldbody>
    AttrSet own;
    own.apply(e_, rule);
    prefix_ = own.has("prefix") ? own.find("prefix")->text : "";
    type_ = composite_type_named(own.find("type")->text);
    const std::vector<double> count = written_numbers(own, "count");
    for (int i = 0; i < 3; ++i) count_[i] = static_cast<int>(count[static_cast<size_t>(i)]);
    spacing_ = own.find("spacing")->numbers[0];
    if (const Value* v = own.find("offset")) std::copy_n(v->numbers.begin(), 3, offset_);
    if (const Value* v = own.find("flatinertia")) flatinertia_ = v->numbers[0];
    skin_ = child("skin");

    // SetDefault: groups 3 (hidden behind the skin) unless the geoms are what is seen
    for (int i = 0; i < 3; ++i) dim_ += count_[i] > 1;
    const bool seen = !skin_ || type_ == CompositeType::kParticle ||
                      type_ == CompositeType::kRope || type_ == CompositeType::kLoop ||
                      (type_ == CompositeType::kGrid && dim_ == 1);
    const int group = seen ? 0 : 3;
    geom_set_.set("group", value_of_integer(group));
    site_set_.set("group", value_of_integer(3));
    std::vector<double> solref = default_numbers(attribute_rule("equality", "joint", "solref"));
    std::vector<double> solimp = default_numbers(attribute_rule("equality", "joint", "solimp"));
    std::vector<std::vector<double>> fix_ref(kKinds, solref), fix_imp(kKinds, solimp);
    std::vector<double> smooth_ref = solref, smooth_imp = solimp;
    if (type_ == CompositeType::kParticle) {
      // no friction with anything
      geom_set_.set("condim", value_of_integer(1));
      geom_set_.set("priority", value_of_integer(1));
    }
    if (type_ == CompositeType::kGrid) {
      adjust_softness(fix_ref[kTendonMain], fix_imp[kTendonMain], 0);
    }
    if (type_ == CompositeType::kLoop) adjust_softness(smooth_ref, smooth_imp, 0);
    if (is_shell_type(type_)) {
      geom_set_.set("contype", value_of_integer(0));  // no self-collision
      adjust_softness(smooth_ref, smooth_imp, 1);
      for (int k = 0; k < kKinds; ++k) adjust_softness(fix_ref[k], fix_imp[k], 1);
      adjust_softness(fix_ref[kTendonMain], fix_imp[kTendonMain], 0);
    }
    for (int k = 0; k < kKinds; ++k) {
      AttrSet& set = k < kTendonMain ? joint_set_[k] : tendon_set_[k - kTendonMain];
      set.set("group", value_of_integer(k < kTendonMain ? 3 : group));
      set.set("solreffix", value_of_numbers(fix_ref[static_cast<size_t>(k)]));
      set.set("solimpfix", value_of_numbers(fix_imp[static_cast<size_t>(k)]));
    }
    // the smoothing parameters are read over the type's
    AttrSet smooth;
    smooth.set("solrefsmooth", value_of_numbers(smooth_ref));
    smooth.set("solimpsmooth", value_of_numbers(smooth_imp));
    smooth.apply(e_, rule);
    smooth_ref_ = written_numbers(smooth, "solrefsmooth");
    smooth_imp_ = written_numbers(smooth, "solimpsmooth");

    for (const Element& c : e_.children) {
      // the element tree is checked by tag: a composite's <tendon> would pass for a section's
      if (!c.children.empty()) {
        const Element& inner = c.children.front();
        fail(inner.place(), "",
             "a composite's <" + c.tag + "> takes no child elements (found <" + inner.tag + ">)");
      }
    }
    if (const Element* g = child("geom")) geom_set_.apply(*g, *find_rule("composite", "geom"));
    if (const Element* s = child("site")) site_set_.apply(*s, *find_rule("composite", "site"));
    for (const Element& c : e_.children) {
      if (c.tag != "joint" && c.tag != "tendon" && c.tag != "pin") continue;
      AttrSet kind;
      kind.apply(c, *find_rule("composite", c.tag));
      if (c.tag == "pin") {
        const std::vector<double> at = written_numbers(kind, "coord");
        pins_.push_back({static_cast<int>(at[0]), static_cast<int>(at[1])});
        continue;
      }
      const std::string word = kind.find("kind")->text;
      const int k = c.tag == "joint"
                        ? (word == "twist" ? kTwist : word == "stretch" ? kStretch : kJointMain)
                        : (word == "shear" ? kShear : kTendonMain);
      AttrSet& set = k < kTendonMain ? joint_set_[k] : tendon_set_[k - kTendonMain];
      set.apply(c, *find_rule("composite", c.tag));
      // MuJoCo 2.2.2 looks for `limited` on the <composite>, where it cannot be: never read
      set.erase("limited");
      added_[k] = true;
      kind_element_[k] = &c;
    }
  }

  // mjCComposite::Make's checks, then each type's own
  void check() const {
    if (const Element* g = child("geom")) {
      const std::string type = geom_set_.has("type") ? geom_set_.find("type")->text : "sphere";
      if (type != "sphere" && type != "capsule" && type != "ellipsoid") {
        fail(g->place(*g->find("type")), "type",
             "a composite's geoms must be spheres, capsules or ellipsoids (found " + type + ")");
      }
    }
    const Attribute* count = e_.find("count");
    for (int i = 0; i < 3; ++i) {
      if (count_[i] < 1) {
        fail(e_.place(*count), "count",
             "a composite's counts must be positive (found " + count->value + ")");
      }
    }
    if (!(spacing_ >= kMinSpacing)) {
      fail(e_.place(*e_.find("spacing")), "spacing",
           "a composite's spacing must be positive (found " + e_.find("spacing")->value + ")");
    }
    bool singleton = false;
    for (int i = 0; i < 3; ++i) {
      if (count_[i] == 1) {
        singleton = true;
      } else {
        if (singleton) {
          fail(e_.place(*count), "count",
               "a composite's counts of 1 must come last (found " + count->value + ")");
        }
      }
    }
    if (skin_) {
      const AttrSet skin = skin_attributes();
      if (const Value* g = skin.find("group"); g && (g->numbers[0] < 0 || g->numbers[0] > 5)) {
        fail(skin_->place(*skin_->find("group")), "group",
             "a skin's group must be between 0 and 5 (found " + skin_->find("group")->value + ")");
      }
      if (const Attribute* m = skin_->find("material"); m && !m->value.empty()) {
        const bool known = std::any_of(assets_.materials.begin(), assets_.materials.end(),
                                       [&](const Place& p) { return p.name == m->value; });
        if (!known) fail(skin_->place(*m), "material", "unknown material '" + m->value + "'");
      }
      const Attribute* subgrid = skin_->find("subgrid");
      if (subgrid && std::atoi(subgrid->value.c_str()) > 0 && (count_[0] < 3 || count_[1] < 3)) {
        fail(skin_->place(*subgrid), "subgrid",
             "a skin subgrid needs a composite of at least 3 x 3 (found count " +
                 count->value + ")");
      }
    }
    const auto dimension = [&](bool ok, const std::string& what) {
      if (!ok) fail(e_.place(*count), "count", what + " (found count " + count->value + ")");
    };
    switch (type_) {
      case CompositeType::kGrid:
        dimension(dim_ <= 2, "a grid can only be 1D or 2D");
        if (added_[kShear] && dim_ != 2) {
          fail(kind_element_[kShear]->place(), "kind", "shear tendons need a 2D grid");
        }
        if (skin_ && dim_ != 2) fail(skin_->place(), "", "a skin needs a 2D grid");
        break;
      case CompositeType::kRope:
      case CompositeType::kLoop:
        dimension(dim_ == 1, "a rope or loop must be one-dimensional");
        break;
      case CompositeType::kCloth: dimension(dim_ == 2, "a cloth must be two-dimensional"); break;
      case CompositeType::kParticle: break;
      default: dimension(dim_ == 3, "a box, cylinder or ellipsoid must be three-dimensional");
    }
  }

  AttrSet skin_attributes() const {
    AttrSet s;
    s.apply(*skin_, *find_rule("composite", "skin"));
    return s;
  }

  // ---- the generated elements -------------------------------------------------------------------

  // where a generated element is reported: at the composite, by its generated name
  Place place(const char* tag, const std::string& name) const {
    Place p = e_.place();
    p.tag = tag;
    p.name = name;
    p.element = -1;  // no element of its own to write back
    return p;
  }

  std::string name(const char* letters, std::initializer_list<int> indices) const {
    std::string n = prefix_ + letters;
    bool first = true;
    for (const int i : indices) {
      if (!first) n += '_';
      n += std::to_string(i);
      first = false;
    }
    return n;
  }

  const Element& element_of(const Element* written) const { return written ? *written : e_; }

  GeomSpec geom(const std::string& named) const {
    GeomSpec g = read_geom(element_of(child("geom")), geom_set_);
    g.at = place("geom", named);
    return g;
  }

  SiteSpec site(const std::string& named) const {
    SiteSpec s = read_site(element_of(child("site")), site_set_);
    s.at = place("site", named);
    s.type = GeomType::kSphere;
    return s;
  }

  JointSpec joint(int kind, const std::string& named, JointType type, Vec3 pos, Vec3 axis) const {
    JointSpec j = read_joint(element_of(kind_element_[kind]), joint_set_[kind]);
    j.at = place("joint", named);
    j.type = type;
    j.pos = pos;
    j.axis = axis;
    return j;
  }

  TendonSpec tendon(int kind, const std::string& named) const {
    const AttrSet& set = tendon_set_[kind - kTendonMain];
    const auto value = [&](std::string_view attribute) {
      if (const Value* v = set.find(attribute)) return v->numbers;
      return default_numbers(attribute_rule("tendon", "spatial", attribute));
    };
    TendonSpec t;
    t.at = place("tendon", named);
    t.limited = Limited::kAuto;
    std::copy_n(value("range").begin(), 2, t.range.begin());
    std::copy_n(value("solreflimit").begin(), 2, t.solref_limit.begin());
    std::copy_n(value("solimplimit").begin(), 5, t.solimp_limit.begin());
    std::copy_n(value("solreffriction").begin(), 2, t.solref_friction.begin());
    std::copy_n(value("solimpfriction").begin(), 5, t.solimp_friction.begin());
    t.margin = value("margin")[0];
    t.stiffness = value("stiffness")[0];
    t.damping = value("damping")[0];
    t.frictionloss = value("frictionloss")[0];
    t.springlength = value("springlength")[0];
    t.width = value("width")[0];
    return t;
  }

  void add_site_to_path(TendonSpec& t, const std::string& site) const {
    TendonPathSpec p;
    p.at = place("site", site);
    p.type = WrapType::kSite;
    p.name = site;
    t.path.push_back(p);
  }

  // an equality constraint with a kind's defaults (solreffix, solimpfix)
  EqualitySpec equality(int kind, EqualityType type, const std::string& name1) const {
    const AttrSet& set = kind < kTendonMain ? joint_set_[kind] : tendon_set_[kind - kTendonMain];
    EqualitySpec q = bare_equality(type, name1, "");
    q.active = true;
    std::copy_n(written_numbers(set, "solreffix").begin(), 2, q.solref.begin());
    std::copy_n(written_numbers(set, "solimpfix").begin(), 5, q.solimp.begin());
    return q;
  }

  // an equality constraint over the model's main class, with the smoothing solref and solimp
  EqualitySpec smoothing(EqualityType type, const std::string& name1,
                         const std::string& name2) const {
    EqualitySpec q = bare_equality(type, name1, name2);
    const Value* active = main_.equality.find("active");
    q.active = active ? active->text == "true" : true;
    std::copy_n(smooth_ref_.begin(), 2, q.solref.begin());
    std::copy_n(smooth_imp_.begin(), 5, q.solimp.begin());
    return q;
  }

  EqualitySpec bare_equality(EqualityType type, const std::string& name1,
                             const std::string& name2) const {
    EqualitySpec q;
    q.at = place("equality", "");
    q.type = type;
    q.name1 = name1;
    q.name2 = name2;
    q.name1_at = place("equality", "");
    q.name2_at = q.name1_at;
    q.data.fill(0.0);
    q.data[1] = 1.0;   // polycoef's linear term
    q.data[10] = 1.0;  // a weld's torquescale
    return q;
  }

  BodySpec& add_body(BodySpec& parent, const std::string& named, Vec3 pos) const {
    BodySpec b;
    b.at = place("body", named);
    b.pos = pos;
    b.user.at = b.at;
    parent.children.push_back(std::move(b));
    return parent.children.back();
  }

  bool pinned(int ix, int iy) const {
    return std::any_of(pins_.begin(), pins_.end(),
                       [&](const std::array<int, 2>& p) { return p[0] == ix && p[1] == iy; });
  }

  // the origin of a rope or cloth is the body it is written in, named prefix + B<coordinates>
  std::string origin_coordinates(const BodySpec& body, const char* form) const {
    const std::string lead = prefix_ + "B";
    const std::string& named = body.at.name;
    if (named.compare(0, lead.size(), lead) != 0) {
      fail(e_.place(), "",
           "a " + std::string(type_ == CompositeType::kCloth ? "cloth" : "rope or loop") +
               " must be written in the body of its origin, named " + lead + form +
               " (found '" + named + "')");
    }
    return named.substr(lead.size());
  }

  // ---- particle: free particles, three slides each ----------------------------------------------

  void particles(BodySpec& body) const {
    for (int ix = 0; ix < count_[0]; ++ix) {
      for (int iy = 0; iy < count_[1]; ++iy) {
        for (int iz = 0; iz < count_[2]; ++iz) {
          BodySpec& b = add_body(body, "", lattice(ix, iy, iz));
          for (int i = 0; i < 3; ++i) {
            b.joints.push_back(joint(kJointMain, "", JointType::kSlide, {}, axis_unit(i)));
          }
          GeomSpec g = geom("");
          g.type = GeomType::kSphere;
          b.geoms.push_back(g);
        }
      }
    }
  }

  Vec3 lattice(int ix, int iy, int iz) const {
    return {offset_[0] + spacing_ * (ix - 0.5 * count_[0]),
            offset_[1] + spacing_ * (iy - 0.5 * count_[1]),
            offset_[2] + spacing_ * (iz - 0.5 * count_[2])};
  }

  static Vec3 axis_unit(int i) {
    Vec3 v{};
    v[static_cast<size_t>(i)] = 1;
    return v;
  }

  // ---- grid: bodies on three slides, neighbours' sites joined by held tendons -------------------

  void grid(BodySpec& body) {
    for (int ix = 0; ix < count_[0]; ++ix) {
      for (int iy = 0; iy < count_[1]; ++iy) {
        Vec3 pos = lattice(ix, iy, 0);
        pos[2] = offset_[2];
        BodySpec& b = add_body(body, name("B", {ix, iy}), pos);
        GeomSpec g = geom(name("G", {ix, iy}));
        g.type = GeomType::kSphere;
        b.geoms.push_back(g);
        b.sites.push_back(site(name("S", {ix, iy})));
        if (pinned(ix, iy)) continue;
        for (int i = 0; i < 3; ++i) {
          b.joints.push_back(
              joint(kJointMain, name("J", {i, ix, iy}), JointType::kSlide, {}, axis_unit(i)));
        }
      }
    }
    for (int i = 0; i < 2; ++i) {
      for (int ix = 0; ix < count_[0] - (i == 0); ++ix) {
        for (int iy = 0; iy < count_[1] - (i == 1); ++iy) {
          held_tendon(kTendonMain, name("T", {i, ix, iy}), name("S", {ix, iy}),
                      name("S", {ix + (i == 0), iy + (i == 1)}));
        }
      }
    }
    if (added_[kShear]) shear();
  }

  // a spatial tendon between two sites, its length held by an equality constraint
  void held_tendon(int kind, const std::string& named, const std::string& site1,
                   const std::string& site2) {
    TendonSpec t = tendon(kind, named);
    t.spatial = true;
    add_site_to_path(t, site1);
    add_site_to_path(t, site2);
    out_.tendons.push_back(std::move(t));
    out_.equalities.push_back(equality(kind, EqualityType::kTendon, named));
  }

  // MakeShear: the diagonals of a 2D grid or cloth
  void shear() {
    for (int ix = 0; ix < count_[0] - 1; ++ix) {
      for (int iy = 0; iy < count_[1] - 1; ++iy) {
        held_tendon(kShear, name("TS", {ix, iy}), name("S", {ix, iy}),
                    name("S", {ix + 1, iy + 1}));
      }
    }
  }

  // ---- rope and loop: a chain of capsules from the origin both ways -----------------------------

  void rope(BodySpec& body) {
    const std::string coordinates = origin_coordinates(body, "<x>");
    size_t at = 0;
    int ox = -1;
    if (!scan_composite_int(coordinates, at, ox)) {
      fail(e_.place(), "", "the origin body's name must give its x coordinate, as " + prefix_ +
                               "B<x> (found '" + body.at.name + "')");
    }
    if (ox < 0 || ox >= count_[0]) {
      fail(e_.place(), "", "the origin body's coordinate is out of range (found '" +
                               body.at.name + "')");
    }
    rope_body(body, ox, ox);
    BodySpec* chain = &body;
    for (int ix = ox; ix < count_[0] - 1; ++ix) chain = &rope_body(*chain, ix, ix + 1);
    chain = &body;
    for (int ix = ox; ix > 0; --ix) chain = &rope_body(*chain, ix, ix - 1);
    if (type_ == CompositeType::kLoop) {
      // close the loop: the two ends joined by a ball joint, their contact excluded
      const std::string first = name("B", {0}), last = name("B", {count_[0] - 1});
      EqualitySpec q = smoothing(EqualityType::kConnect, first, last);
      q.data[0] = -0.5 * spacing_;
      q.data[1] = 0;
      q.data[2] = 0;
      out_.equalities.push_back(q);
      ExcludeSpec x;
      x.at = place("exclude", "");
      x.body1 = first;
      x.body2 = last;
      x.body1_at = x.at;
      x.body2_at = x.at;
      out_.excludes.push_back(x);
    }
  }

  // AddRopeBody: element ix1, a child of element ix's body (the origin itself when ix == ix1)
  BodySpec& rope_body(BodySpec& parent, int ix, int ix1) {
    const bool origin = ix == ix1;
    const double dx = spacing_ * (ix1 - ix);
    BodySpec* b = &parent;
    if (!origin) {
      Vec3 pos{dx, 0, 0};
      Quat quat{1, 0, 0, 0};
      if (type_ == CompositeType::kLoop) {
        const double alpha = 2 * kPi / count_[0];
        const double r = 0.5 * spacing_ * std::sin(kPi - alpha) / std::sin(0.5 * alpha);
        const double half = ix1 > ix ? 0.5 * alpha : -0.5 * alpha;
        pos = {ix1 > ix ? r * std::cos(0.5 * alpha) : -r * std::cos(0.5 * alpha),
               r * std::sin(0.5 * alpha), 0};
        quat = {std::cos(half), 0, 0, std::sin(half)};
      }
      b = &add_body(parent, name("B", {ix1}), pos);
      b->orientation.quat = quat;
    }
    GeomSpec g = geom(name("G", {ix1}));
    g.pos = {0, 0, 0};
    g.orientation.quat = {std::sqrt(0.5), 0, std::sqrt(0.5), 0};  // along the chain
    b->geoms.push_back(g);
    if (origin) return *b;
    const Vec3 anchor{-0.5 * dx, 0, 0};
    for (int i = 0; i < 2; ++i) {
      b->joints.push_back(
          joint(kJointMain, name("J", {i, ix1}), JointType::kHinge, anchor, axis_unit(i + 1)));
    }
    if (added_[kTwist]) {
      b->joints.push_back(
          joint(kTwist, name("JT", {ix1}), JointType::kHinge, anchor, axis_unit(0)));
      out_.equalities.push_back(equality(kTwist, EqualityType::kJoint, name("JT", {ix1})));
    }
    if (added_[kStretch]) {
      b->joints.push_back(
          joint(kStretch, name("JS", {ix1}), JointType::kSlide, anchor, axis_unit(0)));
      out_.equalities.push_back(equality(kStretch, EqualityType::kJoint, name("JS", {ix1})));
    }
    return *b;
  }

  // ---- cloth: a tree of bodies from the origin, rows along x and columns along y ----------------

  void cloth(BodySpec& body) {
    const std::string coordinates = origin_coordinates(body, "<x>_<y>");
    size_t at = 0;
    int ox = -1, oy = -1;
    const bool read = scan_composite_int(coordinates, at, ox) && at < coordinates.size() &&
                      coordinates[at++] == '_' && scan_composite_int(coordinates, at, oy);
    if (!read) {
      fail(e_.place(), "", "the origin body's name must give its coordinates, as " + prefix_ +
                               "B<x>_<y> (found '" + body.at.name + "')");
    }
    if (ox < 0 || ox >= count_[0] || oy < 0 || oy >= count_[1]) {
      fail(e_.place(), "", "the origin body's coordinates are out of range (found '" +
                               body.at.name + "')");
    }
    cloth_body(body, ox, oy, ox, oy);
    cloth_columns(body, ox, oy);                            // the origin's column
    for (const int step : {1, -1}) {                        // the rows: right, then left
      BodySpec* row = &body;
      for (int ix = ox; ix + step >= 0 && ix + step < count_[0]; ix += step) {
        row = &cloth_body(*row, ix, oy, ix + step, oy);
        cloth_columns(*row, ix + step, oy);
      }
    }
    for (int iy = 0; iy < count_[1]; ++iy) {
      if (iy == oy) continue;  // the origin's row is held by its joints
      for (int ix = 0; ix < count_[0] - 1; ++ix) {
        held_tendon(kTendonMain, name("T", {ix, iy}), name("S", {ix, iy}),
                    name("S", {ix + 1, iy}));
      }
    }
    if (added_[kShear]) shear();
  }

  // the column through row element (ix, oy): up, then down
  void cloth_columns(BodySpec& row, int ix, int oy) {
    for (const int step : {1, -1}) {
      BodySpec* column = &row;
      for (int iy = oy; iy + step >= 0 && iy + step < count_[1]; iy += step) {
        column = &cloth_body(*column, ix, iy, ix, iy + step);
      }
    }
  }

  // AddClothBody: element (ix1, iy1), a child of element (ix, iy)'s body (the origin itself when
  // they are the same)
  BodySpec& cloth_body(BodySpec& parent, int ix, int iy, int ix1, int iy1) {
    const bool origin = ix == ix1 && iy == iy1;
    const double dx = spacing_ * (ix1 - ix);
    const double dy = spacing_ * (iy1 - iy);
    BodySpec* b = origin ? &parent : &add_body(parent, name("B", {ix1, iy1}), {dx, dy, 0});
    GeomSpec g = geom(name("G", {ix1, iy1}));
    g.pos = {0, 0, 0};
    // alternating orientations
    g.orientation.quat = (ix1 + iy1) % 2 ? Quat{std::sqrt(0.5), std::sqrt(0.5), 0, 0}
                                         : Quat{0.5, 0.5, 0.5, 0.5};
    if (flatinertia_ > 0) flat_inertia(*b, g);
    b->geoms.push_back(g);
    SiteSpec s = site(name("S", {ix1, iy1}));
    s.pos = {0, 0, 0};
    s.orientation.quat = {1, 0, 0, 0};
    b->sites.push_back(s);
    if (origin) return *b;
    const Vec3 anchor{-dx, -dy, 0};
    const bool along_x = ix != ix1;
    for (int i = 0; i < 2; ++i) {
      b->joints.push_back(joint(kJointMain, name("J", {i, ix1, iy1}), JointType::kHinge, anchor,
                                axis_unit(along_x ? i + 1 : 2 * i)));
    }
    if (added_[kTwist]) {
      b->joints.push_back(joint(kTwist, name("JT", {ix1, iy1}), JointType::kHinge, anchor,
                                axis_unit(along_x ? 0 : 1)));
      out_.equalities.push_back(equality(kTwist, EqualityType::kJoint, name("JT", {ix1, iy1})));
    }
    if (added_[kStretch]) {
      b->joints.push_back(joint(kStretch, name("JS", {ix1, iy1}), JointType::kSlide, anchor,
                                axis_unit(along_x ? 0 : 1)));
      out_.equalities.push_back(
          equality(kStretch, EqualityType::kJoint, name("JS", {ix1, iy1})));
    }
    return *b;
  }

  // the body's inertia that of a thin box of the geom's mass: spacing square, flatinertia thick
  void flat_inertia(BodySpec& b, const GeomSpec& g) const {
    InertialSpec in;
    in.at = place("body", b.at.name);
    in.mass = g.mass ? *g.mass : g.density * geom_volume(g.type, g.size);
    const double size[3] = {0.5 * spacing_, 0.5 * spacing_, 0.5 * spacing_ * flatinertia_};
    in.diaginertia = {in.mass * (size[1] * size[1] + size[2] * size[2]) / 3,
                      in.mass * (size[0] * size[0] + size[2] * size[2]) / 3,
                      in.mass * (size[0] * size[0] + size[1] * size[1]) / 3};
    b.inertial = in;
  }

  // ---- box, cylinder, ellipsoid: a shell of bodies on radial slides -----------------------------

  void shell(BodySpec& body) {
    // the centre geom, twice the size
    GeomSpec centre = geom(name("Gcenter", {}));
    centre.type = GeomType::kSphere;
    centre.pos = {0, 0, 0};
    centre.size = {centre.size[0] * 2, 0, 0};
    body.geoms.push_back(centre);
    // one fixed tendon over every slide, its length held
    TendonSpec all = tendon(kTendonMain, name("T", {}));
    const size_t all_at = out_.tendons.size();
    out_.tendons.push_back(all);
    const auto on_shell = [&](int ix, int iy, int iz) {
      return ix == 0 || ix == count_[0] - 1 || iy == 0 || iy == count_[1] - 1 || iz == 0 ||
             iz == count_[2] - 1;
    };
    for (int ix = 0; ix < count_[0]; ++ix) {
      for (int iy = 0; iy < count_[1]; ++iy) {
        for (int iz = 0; iz < count_[2]; ++iz) {
          if (!on_shell(ix, iy, iz)) continue;
          double pos[3] = {2.0 * ix / (count_[0] - 1) - 1, 2.0 * iy / (count_[1] - 1) - 1,
                           2.0 * iz / (count_[2] - 1) - 1};
          project(pos);
          BodySpec& b = add_body(body, name("B", {ix, iy, iz}), {pos[0], pos[1], pos[2]});
          double z[3] = {pos[0], pos[1], pos[2]};
          normalize(z, 3);
          b.orientation.zaxis = Vec3{z[0], z[1], z[2]};
          GeomSpec g = geom(name("G", {ix, iy, iz}));
          // pushed inwards by its size
          if (g.type == GeomType::kCapsule) {
            g.pos[2] = -(g.size[0] + g.size[1]);
          } else {
            g.type = GeomType::kSphere;
            g.pos[2] = -g.size[0];
          }
          b.geoms.push_back(g);
          const std::string slide = name("J", {ix, iy, iz});
          b.joints.push_back(joint(kJointMain, slide, JointType::kSlide, {}, {0, 0, 1}));
          out_.equalities.push_back(equality(kJointMain, EqualityType::kJoint, slide));
          TendonPathSpec p;
          p.at = place("joint", slide);
          p.type = WrapType::kJoint;
          p.name = slide;
          p.prm = 1;
          out_.tendons[all_at].path.push_back(p);
          // each slide follows its neighbours' along x, y and z on the shell
          for (int i = 0; i < 3; ++i) {
            const int jx = std::min(ix + (i == 0), count_[0] - 1);
            const int jy = std::min(iy + (i == 1), count_[1] - 1);
            const int jz = std::min(iz + (i == 2), count_[2] - 1);
            if (on_shell(jx, jy, jz) && (ix != jx || iy != jy || iz != jz)) {
              out_.equalities.push_back(
                  smoothing(EqualityType::kJoint, slide, name("J", {jx, jy, jz})));
            }
          }
        }
      }
    }
    out_.equalities.push_back(equality(kTendonMain, EqualityType::kTendon, name("T", {})));
  }

  // BoxProject: from the cube [-1, 1]^3 onto the shape
  void project(double* pos) const {
    const double size[3] = {0.5 * spacing_ * (count_[0] - 1), 0.5 * spacing_ * (count_[1] - 1),
                            0.5 * spacing_ * (count_[2] - 1)};
    if (type_ == CompositeType::kBox) {
      for (int i = 0; i < 3; ++i) pos[i] *= size[i];
    } else if (type_ == CompositeType::kCylinder) {
      const double l0 = std::max(std::abs(pos[0]), std::abs(pos[1]));
      normalize(pos, 2);
      pos[0] *= size[0] * l0;
      pos[1] *= size[1] * l0;
      pos[2] *= size[2];
    } else {
      normalize(pos, 3);
      for (int i = 0; i < 3; ++i) pos[i] *= size[i];
    }
  }

  const Element& e_;
  const DefaultClass& main_;
  const AssetSpec& assets_;
  CompositeOutput& out_;

  std::string prefix_;
  CompositeType type_ = CompositeType::kParticle;
  int count_[3] = {1, 1, 1};
  int dim_ = 0;
  double spacing_ = 0;
  double offset_[3] = {0, 0, 0};
  double flatinertia_ = 0;
  const Element* skin_ = nullptr;
  std::vector<double> smooth_ref_, smooth_imp_;
  std::vector<std::array<int, 2>> pins_;
  AttrSet geom_set_, site_set_;
  AttrSet joint_set_[3], tendon_set_[2];  // per kind, with solreffix and solimpfix
  bool added_[kKinds] = {};
  const Element* kind_element_[kKinds] = {};
};

}  // namespace

void expand_composite(const Element& e, BodySpec& body, const DefaultClass& main,
                      const AssetSpec& assets, CompositeOutput& out) {
  CompositeExpander(e, main, assets, out).expand(body);
}

}  // namespace lever::mjcf::detail
