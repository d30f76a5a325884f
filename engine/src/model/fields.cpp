// The field table expanded: locating, sizing and checking every array of Model and Data.
#include <lever/error.hpp>
#include <lever/fields.hpp>

#include "model/model_room.hpp"

#include <array>
#include <cstring>
#include <type_traits>

namespace lever {

namespace {

// ---- the table's tokens ------------------------------------------------------------------------

namespace token {
constexpr Size one = Size::kOne, nq = Size::kNq, nv = Size::kNv, nu = Size::kNu,
               nbody = Size::kNbody, njnt = Size::kNjnt, ngeom = Size::kNgeom, nsite = Size::kNsite,
               nefc = Size::kNefc, npair = Size::kNpair, nexclude = Size::kNexclude,
               nmesh = Size::kNmesh, nmeshvert = Size::kNmeshvert, nmeshgraph = Size::kNmeshgraph,
               nmeshface = Size::kNmeshface,
               nsensor = Size::kNsensor, nsensordata = Size::kNsensordata,
               neq = Size::kNeq, nmocap = Size::kNmocap, ntendon = Size::kNtendon,
               nwrap = Size::kNwrap, na = Size::kNa;
constexpr Stage state = Stage::kState, position = Stage::kPosition, velocity = Stage::kVelocity,
                acceleration = Stage::kAcceleration, inverse = Stage::kInverse,
                energy = Stage::kEnergy, step = Stage::kStep;
constexpr bool mujoco = true, own = false;
}  // namespace token

// The size that counts an array's columns when its table row gives no number: -1, its rows'
// (M, nv x nv); a counted_cols width, that width's (ten_J and actuator_moment: nv).
constexpr Size cols_size_of(int cols, Size rows) {
  switch (cols) {
    case -1: return rows;
    case counted_cols::nuser_body: return Size::kNuserBody;
    case counted_cols::nuser_jnt: return Size::kNuserJnt;
    case counted_cols::nuser_geom: return Size::kNuserGeom;
    case counted_cols::nuser_site: return Size::kNuserSite;
    case counted_cols::nuser_tendon: return Size::kNuserTendon;
    case counted_cols::nuser_actuator: return Size::kNuserActuator;
    case counted_cols::nuser_sensor: return Size::kNuserSensor;
    case counted_cols::nv: return Size::kNv;
    default: return Size::kOne;
  }
}

template <class T>
constexpr Scalar scalar_of() {
  if constexpr (std::is_same_v<T, double>) return Scalar::kDouble;
  if constexpr (std::is_same_v<T, int>) return Scalar::kInt;
  return Scalar::kByte;
}

// ---- how each kind of member is laid out -------------------------------------------------------
// elements_per_row: the numbers one entry of the container holds; element: their type.

template <class C>
struct Layout;

template <size_t N>
struct Layout<std::array<double, N>> {  // a fixed-size array of Data (energy)
  using element = double;
  static constexpr int per_entry = 1;
  static void* data(const std::array<double, N>& a) { return const_cast<double*>(a.data()); }
  static long entries(const std::array<double, N>&) { return N; }
  template <class Placer>
  static void place(Placer&, std::array<double, N>&, int, int) {}  // not in the block
};

// What one entry of an array of T holds: per_entry numbers of type element.
template <class T>
struct Entry {
  static constexpr bool kEigen = requires { T::RowsAtCompileTime; };
  static constexpr int per_entry = [] {
    if constexpr (kEigen) {
      return static_cast<int>(T::RowsAtCompileTime * T::ColsAtCompileTime);
    } else if constexpr (requires { std::tuple_size<T>::value; }) {
      return static_cast<int>(std::tuple_size<T>::value);
    } else {
      return 1;
    }
  }();
  using element = decltype([] {
    if constexpr (kEigen) {
      return typename T::Scalar{};
    } else if constexpr (requires { std::tuple_size<T>::value; }) {
      return typename T::value_type{};
    } else if constexpr (std::is_enum_v<T>) {
      return std::underlying_type_t<T>{};
    } else {
      return T{};
    }
  }());
  // an entry must be exactly its numbers, with no padding, for the array to be one block
  static_assert(sizeof(T) == per_entry * sizeof(element));
};

// Data's and Model's arrays: views into their blocks (lever/arena.hpp)
template <class T>
struct Layout<ArenaArray<T>> {
  using element = typename Entry<T>::element;
  static constexpr int per_entry = Entry<T>::per_entry;
  static void* data(const ArenaArray<T>& v) { return const_cast<T*>(v.data()); }
  static long entries(const ArenaArray<T>& v) { return static_cast<long>(v.size()) * per_entry; }
  template <class Placer>
  static void place(Placer& place, ArenaArray<T>& v, int rows, int cols) {
    place(v, static_cast<std::size_t>(rows) * cols / per_entry);
  }
};

// a vector, a square matrix (M: its storage order is moot), or a row-major one (ten_J, user data)
template <class Plain>
struct Layout<ArenaMap<Plain>> {
  using element = double;
  static constexpr int per_entry = 1;
  static void* data(const ArenaMap<Plain>& m) { return const_cast<double*>(m.data()); }
  static long entries(const ArenaMap<Plain>& m) { return m.size(); }
  template <class Placer>
  static void place(Placer& place, ArenaMap<Plain>& m, int rows, int cols) {
    if constexpr (Plain::ColsAtCompileTime == 1) {
      place(m, static_cast<Eigen::Index>(rows) * cols);
    } else {
      place(m, rows, cols);
    }
  }
};

template <class C, class Element, int cols>
constexpr bool matches() {
  using L = Layout<C>;
  if (!std::is_same_v<typename L::element, Element>) return false;
  return cols < 0 || L::per_entry == 1 || L::per_entry == cols;
}

#define LEVER_CHECK_MODEL_ROW(name, type, rows, cols, origin) \
  static_assert(matches<decltype(Model::name), type, cols>(), \
                "the field table's row for Model::" #name " does not match its member");
#define LEVER_CHECK_DATA_ROW(name, type, rows, cols, stage, origin) \
  static_assert(matches<decltype(Data::name), type, cols>(),        \
                "the field table's row for Data::" #name " does not match its member");
LEVER_MODEL_FIELDS(LEVER_CHECK_MODEL_ROW)
LEVER_DATA_FIELDS(LEVER_CHECK_DATA_ROW)
#undef LEVER_CHECK_MODEL_ROW
#undef LEVER_CHECK_DATA_ROW

// A member of Contact as numbers: its element type, how many, and where they start.
template <class M>
struct ContactMember {
  using element = M;
  static constexpr int count = 1;
  static const void* data(const M& m) { return &m; }
};
template <class T, int R, int C, int O>
struct ContactMember<Eigen::Matrix<T, R, C, O>> {
  static_assert(R == 1 || C == 1 || (O & Eigen::RowMajor), "a matrix member must be row-major");
  using element = T;
  static constexpr int count = R * C;
  static const void* data(const Eigen::Matrix<T, R, C, O>& m) { return m.data(); }
};
template <class T, size_t N>
struct ContactMember<std::array<T, N>> {
  using element = T;
  static constexpr int count = static_cast<int>(N);
  static const void* data(const std::array<T, N>& a) { return a.data(); }
};

#define LEVER_CHECK_CONTACT_ROW(name, type, count_, origin)                              \
  static_assert(std::is_same_v<ContactMember<decltype(Contact::name)>::element, type> && \
                    ContactMember<decltype(Contact::name)>::count == count_,             \
                "the contact field table's row for Contact::" #name " does not match its member");
LEVER_CONTACT_FIELDS(LEVER_CHECK_CONTACT_ROW)
#undef LEVER_CHECK_CONTACT_ROW

// An array's columns in this model: its table's number, else what cols_size_of counts.
int resolve_cols(const Model& model, int cols, Size rows) {
  return cols < 0 ? size_of(model, cols_size_of(cols, rows)) : cols;
}

// The rows an array is stored with: efc arrays hold the most rows the model can have.
int storage_rows(const Model& model, Size size) { return size_of(model, size); }

std::string shape_text(long elements) { return std::to_string(elements) + " numbers"; }

}  // namespace

// ---- the tables --------------------------------------------------------------------------------

const std::vector<FieldInfo>& model_field_table() {
  static const std::vector<FieldInfo> table = {
#define LEVER_MODEL_ROW(name, type, rows, cols, origin) \
  {#name, scalar_of<type>(), token::rows, cols, Stage::kState, token::origin, \
   cols_size_of(cols, token::rows)},
      LEVER_MODEL_FIELDS(LEVER_MODEL_ROW)
#undef LEVER_MODEL_ROW
  };
  return table;
}

const std::vector<FieldInfo>& data_field_table() {
  static const std::vector<FieldInfo> table = {
#define LEVER_DATA_ROW(name, type, rows, cols, stage, origin) \
  {#name, scalar_of<type>(), token::rows, cols, token::stage, token::origin, \
   cols_size_of(cols, token::rows)},
      LEVER_DATA_FIELDS(LEVER_DATA_ROW)
#undef LEVER_DATA_ROW
  };
  return table;
}

const std::vector<ContactField>& contact_field_table() {
  static const std::vector<ContactField> table = [] {
    const Contact c;  // offsets measured on an instance: whatever padding the compiler chose
    const auto at = [&c](const void* member) {
      return static_cast<const char*>(member) - reinterpret_cast<const char*>(&c);
    };
    return std::vector<ContactField>{
#define LEVER_CONTACT_ROW(name, type, count, origin) \
  {#name, scalar_of<type>(), count, at(ContactMember<decltype(Contact::name)>::data(c.name))},
        LEVER_CONTACT_FIELDS(LEVER_CONTACT_ROW)
#undef LEVER_CONTACT_ROW
    };
  }();
  return table;
}

int constraint_rows_max(const Model& model) {
  // an equality constraint's rows whether or not it is active (eq_active may be edited); the
  // arrays' own lengths, so that a model not sized yet is counted without reading past them
  int rows = 0;
  for (size_t e = 0; e < model.eq_type.size(); ++e) {
    rows += model.eq_type[e] == EqualityType::kConnect ? 3
            : model.eq_type[e] == EqualityType::kWeld  ? 6
                                                       : 1;
  }
  for (const double loss : model.dof_frictionloss) rows += loss > 0;
  // a tendon's friction-loss row, and its two stops (a tendon's range may be edited)
  for (const double loss : model.tendon_frictionloss) rows += loss > 0;
  rows += 2 * static_cast<int>(model.tendon_limited.size());
  // both stops of each limited joint; not of the others: a 3000-dof model of unlimited particles
  // would otherwise carry 6000 rows' room in its quadratic arrays (make_constraint refuses, by
  // name, a limit switched on after its Data was made)
  for (const auto limited : model.jnt_limited) rows += limited ? 2 : 0;
  return rows + (model.contacts_possible ? std::max(0, model.njmax) : 0);
}

int size_of(const Model& model, Size size) {
  switch (size) {
    case Size::kOne: return 1;
    case Size::kNq: return model.nq;
    case Size::kNv: return model.nv;
    case Size::kNu: return model.nu;
    case Size::kNbody: return model.nbody;
    case Size::kNjnt: return model.njnt;
    case Size::kNgeom: return model.ngeom;
    case Size::kNsite: return model.nsite;
    case Size::kNefc: return constraint_rows_max(model);
    case Size::kNpair: return model.npair;
    case Size::kNexclude: return model.nexclude;
    case Size::kNmesh: return model.nmesh;
    case Size::kNmeshvert: return model.nmeshvert;
    case Size::kNmeshgraph: return model.nmeshgraph;
    case Size::kNmeshface: return model.nmeshface;
    case Size::kNsensor: return model.nsensor;
    case Size::kNsensordata: return model.nsensordata;
    case Size::kNeq: return model.neq;
    case Size::kNmocap: return model.nmocap;
    case Size::kNuserBody: return model.nuser_body;
    case Size::kNuserJnt: return model.nuser_jnt;
    case Size::kNuserGeom: return model.nuser_geom;
    case Size::kNuserSite: return model.nuser_site;
    case Size::kNuserTendon: return model.nuser_tendon;
    case Size::kNuserActuator: return model.nuser_actuator;
    case Size::kNuserSensor: return model.nuser_sensor;
    case Size::kNtendon: return model.ntendon;
    case Size::kNwrap: return model.nwrap;
    case Size::kNa: return model.na;
  }
  return 0;
}

int size_of(const Model& model, const Data& data, Size size) {
  return size == Size::kNefc ? data.nefc : size_of(model, size);
}

const char* size_name(Size size) {
  static constexpr std::array<const char*, 29> names = {
      "1",            "nq",         "nv",          "nu",           "nbody",
      "njnt",         "ngeom",      "nsite",       "nefc",         "npair",
      "nexclude",     "nmesh",      "nmeshvert",   "nmeshgraph",   "nmeshface",
      "nsensor",      "nsensordata", "neq",        "nmocap",       "nuser_body",
      "nuser_jnt",    "nuser_geom", "nuser_site",  "nuser_tendon", "nuser_actuator",
      "nuser_sensor", "ntendon",    "nwrap",       "na"};
  return names[static_cast<size_t>(size)];
}

const char* stage_name(Stage stage) {
  static constexpr std::array<const char*, 7> names = {
      "state", "position", "velocity", "acceleration", "inverse", "energy", "step"};
  return names[static_cast<size_t>(stage)];
}

const char* scalar_name(Scalar scalar) {
  static constexpr std::array<const char*, 3> names = {"float64", "int32", "uint8"};
  return names[static_cast<size_t>(scalar)];
}

// ---- locating ----------------------------------------------------------------------------------

std::vector<FieldView> model_fields(const Model& model) {
  std::vector<FieldView> views;
  const std::vector<FieldInfo>& table = model_field_table();
  views.reserve(table.size());
  size_t k = 0;
#define LEVER_MODEL_VIEW(name, type, rows, cols, origin)                                           \
  {                                                                                                \
    const int n = size_of(model, token::rows);                                                     \
    views.push_back(                                                                               \
        {&table[k++], Layout<decltype(Model::name)>::data(model.name), n,                      \
         resolve_cols(model, cols, token::rows)});                                             \
  }
  LEVER_MODEL_FIELDS(LEVER_MODEL_VIEW)
#undef LEVER_MODEL_VIEW
  return views;
}

std::vector<FieldView> model_fields(Model& model) {
  return model_fields(static_cast<const Model&>(model));
}

std::vector<FieldView> data_fields(const Model& model, const Data& data) {
  std::vector<FieldView> views;
  const std::vector<FieldInfo>& table = data_field_table();
  views.reserve(table.size());
  size_t k = 0;
#define LEVER_DATA_VIEW(name, type, rows, cols, stage, origin)                      \
  {                                                                                 \
    const int n = size_of(model, data, token::rows);                                \
    views.push_back({&table[k++], Layout<decltype(Data::name)>::data(data.name), n, \
                     resolve_cols(model, cols, token::rows)});                     \
  }
  LEVER_DATA_FIELDS(LEVER_DATA_VIEW)
#undef LEVER_DATA_VIEW
  return views;
}

std::vector<FieldView> data_fields(const Model& model, Data& data) {
  return data_fields(model, static_cast<const Data&>(data));
}

FieldView model_field(const Model& model, std::string_view name) {
  for (const FieldView& v : model_fields(model)) {
    if (name == v.info->name) return v;
  }
  throw StateError("Model has no array called '" + std::string(name) + "'.");
}

FieldView data_field(const Model& model, const Data& data, std::string_view name) {
  for (const FieldView& v : data_fields(model, data)) {
    if (name == v.info->name) return v;
  }
  throw StateError("Data has no array called '" + std::string(name) + "'.");
}

// ---- sizing and checking -----------------------------------------------------------------------

void check_argument_size(long size, long n, const char* where, const char* what) {
  if (size != n) {
    throw StateError(std::string(where) + ": " + what + " has " + std::to_string(size) +
                     " elements; the model needs " + std::to_string(n) + ".");
  }
}

namespace {
// The rows an array of a Data holds, from the sizes it was made with (nefc: the most rows).
int data_rows(const Data& data, Size size) {
  switch (size) {
    case Size::kOne: return 1;
    case Size::kNq: return data.nq;
    case Size::kNv: return data.nv;
    case Size::kNu: return data.nu;
    case Size::kNbody: return data.nbody;
    case Size::kNjnt: return data.njnt;
    case Size::kNgeom: return data.ngeom;
    case Size::kNsite: return data.nsite;
    case Size::kNefc: return data.nefc_max;
    case Size::kNsensordata: return data.nsensordata;
    case Size::kNmocap: return data.nmocap;
    case Size::kNtendon: return data.ntendon;
    case Size::kNwrap: return data.nwrap;
    case Size::kNa: return data.na;
    default: break;
  }
  throw StateError(std::string("lever: a Data array counted in ") + size_name(size) +
                   ", a size a Data does not keep: add it to Data's sizes.");
}
}  // namespace

namespace detail {
void lay_out_model_table_arrays(Model& model, ModelArrayPlacer& place) {
#define LEVER_MODEL_PLACE(name, type, rows, cols, origin)                               \
  Layout<decltype(Model::name)>::place(place, model.name, size_of(model, token::rows), \
                                       resolve_cols(model, cols, token::rows));
  LEVER_MODEL_FIELDS(LEVER_MODEL_PLACE)
#undef LEVER_MODEL_PLACE
}

void lay_out_table_arrays(Data& data, ArrayPlacer& place) {
#define LEVER_DATA_PLACE(name, type, rows, cols, stage, origin)                      \
  {                                                                                  \
    const int n = data_rows(data, token::rows);                                      \
    const int c = cols < 0 ? data_rows(data, cols_size_of(cols, token::rows)) : cols; \
    Layout<decltype(Data::name)>::place(place, data.name, n, c);                    \
  }
  LEVER_DATA_FIELDS(LEVER_DATA_PLACE)
#undef LEVER_DATA_PLACE
}
}  // namespace detail

// every name of LEVER_MODEL_CONSTANTS is a member of Model (a misspelt one would match nothing)
#define LEVER_CHECK_CONSTANT(name) static_assert(sizeof(Model::name) > 0);
LEVER_MODEL_CONSTANTS(LEVER_CHECK_CONSTANT)
#undef LEVER_CHECK_CONSTANT

bool computed_by_set_const(std::string_view model_field) {
#define LEVER_MODEL_CONSTANT(name) \
  if (model_field == #name) return true;
  LEVER_MODEL_CONSTANTS(LEVER_MODEL_CONSTANT)
#undef LEVER_MODEL_CONSTANT
  return false;
}

void check_model_sizes(const Model& model) {
  // size_model gives every array the length its counts give it, so a difference means a count
  // was changed after the last size_model
#define LEVER_MODEL_SIZE(name, type, rows, cols, origin)                                          \
  {                                                                                               \
    const int n = size_of(model, token::rows);                                                    \
    const long expected = static_cast<long>(n) * resolve_cols(model, cols, token::rows);          \
    const long actual = Layout<decltype(Model::name)>::entries(model.name);                       \
    if (actual != expected) {                                                                     \
      throw ModelError("Model::" #name " holds " + shape_text(actual) +                           \
                       " but the model's counts give it " + shape_text(expected) + " (" +         \
                       size_name(token::rows) + " = " + std::to_string(n) +                       \
                       "): a count changed since the arrays were sized; call lever::size_model " \
                       "after setting the counts.");                                              \
    }                                                                                             \
  }
  LEVER_MODEL_FIELDS(LEVER_MODEL_SIZE)
#undef LEVER_MODEL_SIZE
}

// ---- sizing a Model -----------------------------------------------------------------

void size_model(Model& model) {
  const std::array<std::pair<const char*, int>, 28> counts = {{{"nmesh", model.nmesh},
                                                               {"nmeshvert", model.nmeshvert},
                                                               {"nmeshgraph", model.nmeshgraph},
                                                               {"nmeshface", model.nmeshface},
                                                               {"nq", model.nq},
                                                               {"nv", model.nv},
                                                               {"nu", model.nu},
                                                               {"nbody", model.nbody},
                                                               {"njnt", model.njnt},
                                                               {"ngeom", model.ngeom},
                                                               {"nsite", model.nsite},
                                                               {"nkey", model.nkey},
                                                               {"npair", model.npair},
                                                               {"nexclude", model.nexclude},
                                                               {"nsensor", model.nsensor},
                                                               {"nsensordata", model.nsensordata},
                                                               {"neq", model.neq},
                                                               {"nmocap", model.nmocap},
                                                               {"nuser_body", model.nuser_body},
                                                               {"nuser_jnt", model.nuser_jnt},
                                                               {"nuser_geom", model.nuser_geom},
                                                               {"nuser_site", model.nuser_site},
                                                               {"nuser_tendon", model.nuser_tendon},
                                                               {"nuser_actuator", model.nuser_actuator},
                                                               {"nuser_sensor", model.nuser_sensor},
                                                               {"ntendon", model.ntendon},
                                                               {"nwrap", model.nwrap},
                                                               {"na", model.na}}};
  for (const auto& [name, n] : counts) {
    if (n < 0) {
      throw ModelError(std::string("size_model: ") + name + " = " + std::to_string(n) +
                       " is negative; a model's counts are 0 or more.");
    }
  }
  if (model.nbody < 1) {
    throw ModelError("size_model: nbody = 0; a model has at least the world body (body 0).");
  }
  const size_t bodies_before = model.body_mocapid.size();
  // one new block for every array, zeroed; each array moved into it, keeping what it held within
  // its new length
  detail::ModelArrayPlacer measure(nullptr, detail::ModelArrayPlacer::Mode::kMeasure);
  detail::lay_out_model(model, measure);
  ArenaBlock block(measure.bytes());
  if (block.bytes() > 0) std::memset(block.data(), 0, block.bytes());
  detail::ModelArrayPlacer move_into(block.data(), detail::ModelArrayPlacer::Mode::kResize);
  detail::lay_out_model(model, move_into);
  model.block_ = std::move(block);  // the old block goes
  // a new body is not a mocap body until the builder says so
  for (size_t b = bodies_before; b < model.body_mocapid.size(); ++b) model.body_mocapid[b] = -1;
  // outside the block (see lever/fields.hpp): one name per object
#define LEVER_MODEL_SIZE_NAMES(name, count) model.name.resize(static_cast<size_t>(model.count));
  LEVER_MODEL_NAMES(LEVER_MODEL_SIZE_NAMES)
#undef LEVER_MODEL_SIZE_NAMES
  model.fit_tag = 0;  // its arrays may have changed: set_const again before a Data trusts it
}

void check_fit(const Model& model, const Data& data, const char* where) {
  const bool same_model = data.nq == model.nq && data.nv == model.nv && data.nu == model.nu &&
                          data.nbody == model.nbody && data.njnt == model.njnt &&
                          data.nsite == model.nsite && data.ngeom == model.ngeom;
  if (!same_model) {
    throw StateError(std::string(where) +
                     ": this Data was built for another model (sizes nq, nv, nu, nbody, njnt, "
                     "nsite, ngeom differ): build a Data from this model.");
  }
#define LEVER_DATA_FIT(name, type, rows, cols, stage, origin)                                \
  {                                                                                          \
    const int n = storage_rows(model, token::rows);                                          \
    const long expected = static_cast<long>(n) * resolve_cols(model, cols, token::rows);     \
    const long actual = Layout<decltype(Data::name)>::entries(data.name);                    \
    if (actual != expected) {                                                                \
      throw StateError(std::string(where) + ": data." #name " holds " + shape_text(actual) + \
                       " but the model gives it " + shape_text(expected) +                   \
                       ": assign it element by element or with a vector of that size.");     \
    }                                                                                        \
  }
  LEVER_DATA_FIELDS(LEVER_DATA_FIT)
#undef LEVER_DATA_FIT
}

}  // namespace lever
