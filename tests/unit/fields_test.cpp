// The field table (lever/fields.hpp): its views, the Data constructor's sizes, the size checks at
// the door of every public function (check_fit, StateError), set_const's Model size check
// (ModelError), size_model's lengths (the table sizing Model as it sizes Data), and step1 + step2
// against step.
#include <catch2/catch.hpp>

#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <lever/harness/models.hpp>
#include <lever/harness/random_state.hpp>

namespace {

using lever::FieldView;
using lever::Scalar;

lever::Model load(const std::string& relative) {
  return lever::mjcf::load_file(lever::test::model_path(relative));
}

// Every model of the repository that mjcf_lite loads.
std::vector<lever::Model> all_models() {
  std::vector<lever::Model> models;
  for (const std::string& path : lever::test::all_model_files()) {
    try {
      models.push_back(lever::mjcf::load_file(path));
    } catch (const lever::Error&) {
      // a model only MuJoCo's compiler reads (tests/compile covers it)
    }
  }
  // a model with tendons: ten_J and actuator_moment of more rows than nv has columns
  models.push_back(
      lever::mjcf::load_file(lever::test::model_path("tests/models/constraints/tendons.xml")));
  return models;
}

// A value that identifies element k of view number v, exactly representable in every type.
double mark(size_t v, long k) {
  return static_cast<double>((v * 7 + static_cast<size_t>(k)) % 97 + 1);
}

void write_mark(FieldView& view, size_t v, long k) {
  const double x = mark(v, k);
  switch (view.info->scalar) {
    case Scalar::kDouble: static_cast<double*>(view.data)[k] = x; break;
    case Scalar::kInt: static_cast<int*>(view.data)[k] = static_cast<int>(x); break;
    case Scalar::kByte: static_cast<uint8_t*>(view.data)[k] = static_cast<uint8_t>(x); break;
  }
}

// The address and element count of a member, as the member itself says (independent of the
// table's Layout code).
template <class T>
std::pair<const void*, long> extent(const std::vector<T>& v, long per_entry) {
  return {v.data(), static_cast<long>(v.size()) * per_entry};
}
template <class T>
std::pair<const void*, long> extent(const lever::ArenaArray<T>& v, long per_entry) {
  return {v.data(), static_cast<long>(v.size()) * per_entry};
}
template <class Plain>
std::pair<const void*, long> extent(const lever::ArenaMap<Plain>& m) {
  return {m.data(), m.size()};
}
std::pair<const void*, long> located(const FieldView& view) { return {view.data, view.size()}; }

std::string text_of(const lever::Error& e) { return e.what(); }

// A copy of every number of a Data's table arrays, to show that a refused call changed nothing.
std::vector<double> snapshot(const lever::Model& model, const lever::Data& data) {
  std::vector<double> all;
  for (const FieldView& v : lever::data_fields(model, data)) {
    for (long k = 0; k < v.size(); ++k) {
      switch (v.info->scalar) {
        case Scalar::kDouble: all.push_back(static_cast<const double*>(v.data)[k]); break;
        case Scalar::kInt: all.push_back(static_cast<const int*>(v.data)[k]); break;
        case Scalar::kByte: all.push_back(static_cast<const uint8_t*>(v.data)[k]); break;
      }
    }
  }
  all.push_back(data.time);
  all.push_back(data.nefc);
  return all;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

bool same_bits(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return a.size() == b.size() &&
         std::memcmp(a.data(), b.data(), static_cast<size_t>(a.size()) * sizeof(double)) == 0;
}

}  // namespace

TEST_CASE("every Model view has the table's size and points into its member", "[fields]") {
  lever::Model model = load("models/arm3.xml");
  std::vector<FieldView> views = lever::model_fields(model);
  REQUIRE(views.size() == lever::model_field_table().size());
  for (size_t v = 0; v < views.size(); ++v) {
    FieldView& view = views[v];
    INFO("Model::" << view.info->name);
    CHECK(view.info == &lever::model_field_table()[v]);
    CHECK(view.rows == lever::size_of(model, view.info->rows));
    CHECK(view.cols ==
          (view.info->cols < 0 ? lever::size_of(model, view.info->cols_size) : view.info->cols));
    for (long k = 0; k < view.size(); ++k) write_mark(view, v, k);
  }
  // read back through the members themselves
  auto find = [&](const char* name) {
    for (size_t v = 0; v < views.size(); ++v) {
      if (std::string(views[v].info->name) == name) return v;
    }
    FAIL("no view " << name);
    return size_t{0};
  };
  {
    const size_t v = find("body_mass");
    for (int b = 0; b < model.nbody; ++b) CHECK(model.body_mass[b] == mark(v, b));
    CHECK(extent(model.body_mass, 1) == located(views[v]));
  }
  {
    const size_t v = find("body_pos");  // (nbody, 3): row b is body b
    for (int b = 0; b < model.nbody; ++b) {
      for (int c = 0; c < 3; ++c) CHECK(model.body_pos[b][c] == mark(v, 3 * b + c));
    }
    CHECK(extent(model.body_pos, 3) == located(views[v]));
  }
  {
    const size_t v = find("jnt_range");
    for (int j = 0; j < model.njnt; ++j) {
      for (int c = 0; c < 2; ++c) CHECK(model.jnt_range[j][c] == mark(v, 2 * j + c));
    }
  }
  {
    const size_t v = find("jnt_limited");  // flags are bytes
    for (int j = 0; j < model.njnt; ++j) CHECK(model.jnt_limited[j] == mark(v, j));
    CHECK(views[v].info->scalar == Scalar::kByte);
  }
  {
    const size_t v = find("actuator_gear");
    for (int a = 0; a < model.nu; ++a) {
      for (int c = 0; c < 6; ++c) CHECK(model.actuator_gear[a][c] == mark(v, 6 * a + c));
    }
  }
  {
    const size_t v = find("jnt_type");
    for (int j = 0; j < model.njnt; ++j) CHECK(static_cast<int>(model.jnt_type[j]) == mark(v, j));
  }
}

TEST_CASE("every Data view has the table's size and points into its member", "[fields]") {
  for (const lever::Model& model : all_models()) {
    INFO("model " << model.name);
    lever::Data data(model);
    data.nefc = data.nefc_max;  // every limit row live, so the efc views cover their storage
    std::vector<FieldView> views = lever::data_fields(model, data);
    REQUIRE(views.size() == lever::data_field_table().size());
    for (size_t v = 0; v < views.size(); ++v) {
      FieldView& view = views[v];
      INFO("Data::" << view.info->name);
      CHECK(view.rows == lever::size_of(model, data, view.info->rows));
      CHECK(view.cols == (view.info->cols < 0 ? model.nv : view.info->cols));
      for (long k = 0; k < view.size(); ++k) write_mark(view, v, k);
    }
    size_t v = 0;
    const auto next = [&](const char* name) {
      REQUIRE(std::string(views[v].info->name) == name);
      return v++;
    };
    // the table's order is fixed; read each member back in it
    size_t k = next("qpos");
    for (int i = 0; i < model.nq; ++i) CHECK(data.qpos[i] == mark(k, i));
    CHECK(extent(data.qpos) == located(views[k]));
    k = next("qvel");
    for (int i = 0; i < model.nv; ++i) CHECK(data.qvel[i] == mark(k, i));
    k = next("ctrl");
    for (int a = 0; a < model.nu; ++a) CHECK(data.ctrl[a] == mark(k, a));
    k = next("act");
    for (int i = 0; i < model.na; ++i) CHECK(data.act[i] == mark(k, i));
    k = next("qfrc_applied");
    k = next("mocap_pos");
    for (int i = 0; i < model.nmocap; ++i) {
      for (int c = 0; c < 3; ++c) CHECK(data.mocap_pos[i][c] == mark(k, 3 * i + c));
    }
    k = next("mocap_quat");
    for (int i = 0; i < model.nmocap; ++i) {
      for (int c = 0; c < 4; ++c) CHECK(data.mocap_quat[i][c] == mark(k, 4 * i + c));
    }
    k = next("qacc");
    for (int i = 0; i < model.nv; ++i) CHECK(data.qacc[i] == mark(k, i));
    k = next("qacc_warmstart");
    for (int i = 0; i < model.nv; ++i) CHECK(data.qacc_warmstart[i] == mark(k, i));
    k = next("xpos");
    for (int b = 0; b < model.nbody; ++b) {
      for (int c = 0; c < 3; ++c) CHECK(data.xpos[b][c] == mark(k, 3 * b + c));
    }
    k = next("xquat");
    for (int b = 0; b < model.nbody; ++b) {
      for (int c = 0; c < 4; ++c) CHECK(data.xquat[b][c] == mark(k, 4 * b + c));
    }
    k = next("xmat");  // row-major, as MuJoCo's: element (r, c) of body b at 9 b + 3 r + c
    for (int b = 0; b < model.nbody; ++b) {
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) CHECK(data.xmat[b](r, c) == mark(k, 9 * b + 3 * r + c));
      }
    }
    CHECK(extent(data.xmat, 9) == located(views[k]));
    k = next("xipos");
    k = next("ximat");
    for (int b = 0; b < model.nbody; ++b) {
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) CHECK(data.ximat[b](r, c) == mark(k, 9 * b + 3 * r + c));
      }
    }
    k = next("xanchor");
    k = next("xaxis");
    for (int j = 0; j < model.njnt; ++j) {
      for (int c = 0; c < 3; ++c) CHECK(data.xaxis[j][c] == mark(k, 3 * j + c));
    }
    k = next("geom_xpos");
    k = next("geom_xmat");
    for (int g = 0; g < model.ngeom; ++g) {
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) CHECK(data.geom_xmat[g](r, c) == mark(k, 9 * g + 3 * r + c));
      }
    }
    k = next("site_xpos");
    k = next("site_xmat");
    for (int s = 0; s < model.nsite; ++s) {
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) CHECK(data.site_xmat[s](r, c) == mark(k, 9 * s + 3 * r + c));
      }
    }
    k = next("subtree_com");
    k = next("cdof");  // (nv, 6): rotation then translation, as MuJoCo's
    for (int i = 0; i < model.nv; ++i) {
      for (int c = 0; c < 6; ++c) CHECK(data.cdof[i][c] == mark(k, 6 * i + c));
    }
    k = next("M");  // (nv, nv), symmetric in use; the view is its whole storage
    CHECK(extent(data.M) == located(views[k]));
    k = next("qLDiagInv");
    k = next("ten_length");
    k = next("ten_J");  // (ntendon, nv), row-major as MuJoCo's dense ten_J
    for (int t = 0; t < model.ntendon; ++t) {
      for (int c = 0; c < model.nv; ++c) CHECK(data.ten_J(t, c) == mark(k, t * model.nv + c));
    }
    k = next("ten_wrapadr");
    k = next("ten_wrapnum");
    k = next("wrap_obj");  // (nwrap, 2): two points per row, as MuJoCo's
    for (int w = 0; w < model.nwrap; ++w) {
      for (int c = 0; c < 2; ++c) CHECK(data.wrap_obj[w][c] == mark(k, 2 * w + c));
    }
    k = next("wrap_xpos");  // (nwrap, 6)
    for (int w = 0; w < model.nwrap; ++w) {
      for (int c = 0; c < 6; ++c) CHECK(data.wrap_xpos[w][c] == mark(k, 6 * w + c));
    }
    k = next("actuator_length");
    k = next("actuator_moment");  // (nu, nv), row-major
    for (int a = 0; a < model.nu; ++a) {
      for (int c = 0; c < model.nv; ++c) {
        CHECK(data.actuator_moment(a, c) == mark(k, a * model.nv + c));
      }
    }
    k = next("efc_type");
    k = next("efc_id");
    for (int r = 0; r < data.nefc; ++r) CHECK(data.efc_id[r] == mark(k, r));
    for (const FieldView& view : views) {
      // every other array: its view covers exactly its member's storage
      if (view.info->rows == lever::Size::kNefc) CHECK(view.rows == data.nefc_max);
    }
    // the remaining rows, by name, through data_field (which the bindings use)
    const FieldView force = lever::data_field(model, data, "efc_force");
    CHECK(extent(data.efc_force) == located(force));
    const FieldView state = lever::data_field(model, data, "efc_state");
    CHECK(extent(data.efc_state, 1) == located(state));
    CHECK(state.info->scalar == Scalar::kInt);
    const FieldView cvel = lever::data_field(model, data, "cvel");
    for (int b = 0; b < model.nbody; ++b) {
      for (int c = 0; c < 6; ++c) {
        CHECK(data.cvel[b][c] == static_cast<const double*>(cvel.data)[6 * b + c]);
      }
    }
    const FieldView energy = lever::data_field(model, data, "energy");
    CHECK(energy.rows == 1);
    CHECK(energy.cols == 2);
    CHECK(energy.data == static_cast<const void*>(data.energy.data()));
    CHECK_THROWS_AS(lever::data_field(model, data, "no_such_array"), lever::StateError);
    CHECK_THROWS_AS(lever::model_field(model, "no_such_array"), lever::StateError);
  }
}

TEST_CASE("Data's constructor sizes every array as the table says, zero-filled", "[fields]") {
  for (const lever::Model& model : all_models()) {
    INFO("model " << model.name);
    const lever::Data data(model);
    CHECK(data.nefc == 0);
    CHECK(data.nefc_max == lever::constraint_rows_max(model));
    CHECK(data.qpos == model.qpos0);
    // the efc arrays hold their most rows; the views count the live ones
    lever::Data full(model);
    full.nefc = full.nefc_max;
    for (const FieldView& view : lever::data_fields(model, full)) {
      INFO("Data::" << view.info->name);
      // kNefc: each equality constraint's rows, a friction-loss row per dof and tendon with
      // friction loss, two limit rows per limited joint and per tendon, and njmax contact rows
      // if the model can make contacts
      int constraint_rows = 2 * model.ntendon;
      for (int j = 0; j < model.njnt; ++j) constraint_rows += model.jnt_limited[j] ? 2 : 0;
      for (int e = 0; e < model.neq; ++e) {
        const lever::EqualityType type = model.eq_type[e];
        constraint_rows += type == lever::EqualityType::kConnect ? 3
                           : type == lever::EqualityType::kWeld  ? 6
                                                                 : 1;
      }
      for (const double loss : model.dof_frictionloss) constraint_rows += loss > 0;
      for (const double loss : model.tendon_frictionloss) constraint_rows += loss > 0;
      const int rows =
          view.info->rows == lever::Size::kNefc
              ? constraint_rows + (model.contacts_possible ? model.njmax : 0)
              : lever::size_of(model, view.info->rows);
      CHECK(view.rows == rows);
      CHECK(view.size() ==
            static_cast<long>(rows) * (view.info->cols < 0 ? model.nv : view.info->cols));
    }
    CHECK(data.qpos.size() == model.nq);
    CHECK(data.qvel.size() == model.nv);
    CHECK(data.ctrl.size() == model.nu);
    CHECK(static_cast<int>(data.xmat.size()) == model.nbody);
    CHECK(static_cast<int>(data.site_xmat.size()) == model.nsite);
    CHECK(static_cast<int>(data.xaxis.size()) == model.njnt);
    CHECK(static_cast<int>(data.cdof.size()) == model.nv);
    CHECK(data.M.rows() == model.nv);
    CHECK(data.M.cols() == model.nv);
    CHECK(static_cast<int>(data.efc_state.size()) == data.nefc_max);
    CHECK(data.efc_force.size() == data.nefc_max);
    // and check_fit accepts it
    CHECK_NOTHROW(lever::check_fit(model, data, "test"));
    // zero-filled, but for the values that mean "nothing yet": qpos0, identity rotations,
    // no joint (-1) in the limit rows, the mocap bodies where the model puts them
    for (const FieldView& view : lever::data_fields(model, full)) {
      const std::string name = view.info->name;
      if (name == "qpos" || name == "xquat" || name == "xmat" || name == "ximat" ||
          name == "geom_xmat" || name == "site_xmat" || name == "efc_id" || name == "efc_dof" ||
          name == "mocap_pos" || name == "mocap_quat") {
        continue;
      }
      INFO("Data::" << name);
      for (long k = 0; k < view.size(); ++k) {
        double x = 0.0;
        if (view.info->scalar == Scalar::kDouble) x = static_cast<const double*>(view.data)[k];
        if (view.info->scalar == Scalar::kInt) x = static_cast<const int*>(view.data)[k];
        if (view.info->scalar == Scalar::kByte) x = static_cast<const uint8_t*>(view.data)[k];
        CHECK(x == 0.0);
      }
    }
    for (int b = 0; b < model.nbody; ++b) {
      CHECK(data.xquat[b] == Eigen::Vector4d(1, 0, 0, 0));
      CHECK(data.xmat[b] == lever::Mat3::Identity());
    }
    for (int r = 0; r < data.nefc_max; ++r) CHECK(data.efc_id[r] == -1);
  }
}


TEST_CASE("a limit switched on after its Data was made is refused by name, and a new Data has room",
          "[fields]") {
  // a Data holds limit rows for the joints limited when it was made, not for every joint
  lever::Model model = lever::mjcf::load_string(R"(<mujoco>
  <worldbody>
    <body><joint name="free_swing" type="hinge" axis="0 1 0"/><geom size=".1" mass="1"/></body>
  </worldbody>
</mujoco>)");
  lever::Data data(model);
  CHECK(data.nefc_max == 0);
  model.jnt_limited[0] = 1;
  model.jnt_range[0] = {0.5, 1.0};  // qpos 0 is past the lower stop: one row
  try {
    lever::forward(model, data);
    FAIL("forward made a limit row with no room for it");
  } catch (const lever::StateError& e) {
    CHECK_THAT(e.what(), Catch::Contains("joint 0's limit was switched on after this Data was made"));
  }
  lever::Data fresh(model);
  CHECK(fresh.nefc_max == 2);
  lever::forward(model, fresh);
  CHECK(fresh.nefc == 1);
}
TEST_CASE("a Data of another model is refused by name, and nothing is written", "[fields]") {
  const lever::Model arm2 = load("models/arm2.xml");
  const lever::Model arm3 = load("models/arm3.xml");
  lever::Data data(arm3);
  lever::forward(arm3, data);
  const std::vector<double> before = snapshot(arm3, data);
  const auto refuses = [&](const char* name, auto&& call) {
    INFO(name);
    try {
      call();
      FAIL("no StateError");
    } catch (const lever::StateError& e) {
      CHECK_THAT(text_of(e), Catch::Contains(name));
      CHECK_THAT(text_of(e), Catch::Contains("another model"));
    }
    CHECK(same_bits(snapshot(arm3, data), before));
  };
  refuses("lever::forward", [&] { lever::forward(arm2, data); });
  refuses("lever::step", [&] { lever::step(arm2, data); });
  refuses("lever::step1", [&] { lever::step1(arm2, data); });
  refuses("lever::step2", [&] { lever::step2(arm2, data); });
  refuses("lever::inverse", [&] { lever::inverse(arm2, data); });
  refuses("lever::kinematics", [&] { lever::kinematics(arm2, data); });
  refuses("lever::crba", [&] { lever::crba(arm2, data); });
  refuses("lever::compute_energy", [&] { lever::compute_energy(arm2, data); });
  refuses("lever::reset", [&] { lever::reset(arm2, data); });
  Eigen::MatrixXd jacp(3, arm2.nv), jacr(3, arm2.nv);
  refuses("lever::jac_site", [&] { lever::jac_site(arm2, data, 0, jacp, jacr); });
  Eigen::VectorXd x = Eigen::VectorXd::Ones(arm2.nv), tau(arm2.nv);
  refuses("lever::solve_mass", [&] { lever::solve_mass(arm2, data, x); });
  refuses("lever::rnea", [&] { lever::rnea(arm2, data, x, tau); });
  CHECK_THROWS_AS(lever::check_fit(arm2, data, "here"), lever::StateError);
}

TEST_CASE("an array of Data keeps its size: assigning one of another size throws", "[fields]") {
  const lever::Model model = load("models/arm3.xml");
  lever::Data data(model);
  lever::forward(model, data);
  const Eigen::VectorXd qpos = data.qpos;
  CHECK_THROWS_WITH(data.qpos = Eigen::VectorXd::Ones(model.nq + 1),
                    Catch::Contains("keep the sizes"));
  CHECK(data.qpos.size() == model.nq);
  CHECK(Eigen::VectorXd(data.qpos) == qpos);  // untouched
  CHECK_THROWS_AS(data.ctrl = Eigen::VectorXd::Zero(0), lever::StateError);
  CHECK_THROWS_AS(data.M = Eigen::MatrixXd::Zero(model.nv + 1, model.nv), lever::StateError);
  CHECK_THROWS_AS(data.xpos = std::vector<Eigen::Vector3d>(1), lever::StateError);
  data.qpos = Eigen::VectorXd::Ones(model.nq);  // of its size, it is assigned
  CHECK(data.qpos[0] == 1.0);
  CHECK_NOTHROW(lever::forward(model, data));
}

TEST_CASE("a Data's arrays live in one cache-aligned block, copies and moves keep them apart",
          "[fields]") {
  const lever::Model model = load("models/arm3.xml");
  lever::Data data(model);
  lever::forward(model, data);
  const auto* begin = data.block().data();
  const auto* end = begin + data.block().bytes();
  CHECK(reinterpret_cast<std::uintptr_t>(&data) % lever::kCacheLine == 0);
  CHECK(reinterpret_cast<std::uintptr_t>(begin) % lever::kCacheLine == 0);
  CHECK(data.block().bytes() % lever::kCacheLine == 0);
  for (const lever::FieldView& v : lever::data_fields(model, data)) {
    // members of Data (fixed-size arrays), outside the block
    if (std::string(v.info->name) == "energy" || std::string(v.info->name) == "solver_fwdinv") continue;
    const auto* at = static_cast<const unsigned char*>(v.data);
    CHECK(reinterpret_cast<std::uintptr_t>(at) % lever::kCacheLine == 0);
    CHECK((at >= begin && at <= end));
  }
  lever::Data copy = data;  // a new block with the same numbers
  CHECK(copy.block().data() != data.block().data());
  CHECK(copy.qpos.data() != data.qpos.data());
  CHECK(Eigen::MatrixXd(copy.M) == Eigen::MatrixXd(data.M));
  CHECK(copy.xpos[model.nbody - 1] == data.xpos[model.nbody - 1]);
  copy.qpos[0] += 1.0;
  CHECK(copy.qpos[0] != data.qpos[0]);
  const double* qpos_at = copy.qpos.data();
  lever::Data moved = std::move(copy);  // the block changes hands: the views stay where they were
  CHECK(moved.qpos.data() == qpos_at);
  CHECK(copy.qpos.size() == 0);  // NOLINT(bugprone-use-after-move): the moved-from Data is empty
  lever::Data other(load("models/arm2.xml"));
  other = data;  // assigned a Data of another model: its sizes and numbers become data's
  CHECK(other.nv == data.nv);
  CHECK(Eigen::VectorXd(other.qacc) == Eigen::VectorXd(data.qacc));
  CHECK_NOTHROW(lever::forward(model, other));
}

TEST_CASE("a copied Model owns its arrays, an assigned one takes the other's sizes, a moved one "
          "keeps them where they were", "[fields]") {
  const lever::Model model = load("models/panda7.xml");
  lever::Data data(model);
  lever::forward(model, data);

  // every array of the table in the model's one block, each on a cache line of its own
  const auto* block_begin = model.block().data();
  for (const lever::FieldView& v : lever::model_fields(model)) {
    if (v.size() == 0) continue;
    INFO(v.info->name);
    const auto* at = static_cast<const unsigned char*>(v.data);
    CHECK(reinterpret_cast<std::uintptr_t>(at) % lever::kCacheLine == 0);
    CHECK((at >= block_begin && at < block_begin + model.block().bytes()));
  }

  lever::Model copy = model;  // every array copied, none shared
  const std::vector<lever::FieldView> original_fields = lever::model_fields(model);
  const std::vector<lever::FieldView> copied_fields = lever::model_fields(copy);
  REQUIRE(copied_fields.size() == original_fields.size());
  for (std::size_t k = 0; k < original_fields.size(); ++k) {
    const lever::FieldView& v = original_fields[k];
    const lever::FieldView& w = copied_fields[k];
    INFO(v.info->name);
    CHECK(w.info == v.info);
    CHECK(w.size() == v.size());
    if (v.size() > 0) CHECK(w.data != v.data);
  }
  copy.body_mass[2] *= 2.0;
  copy.key_qpos(0, 0) += 1.0;
  CHECK(copy.body_mass[2] != model.body_mass[2]);
  CHECK(copy.key_qpos(0, 0) != model.key_qpos(0, 0));
  lever::set_const(copy);  // the original's constants stay its own
  CHECK(copy.body_subtreemass[0] != model.body_subtreemass[0]);

  lever::Model twin = model;
  lever::Data twin_data(twin);
  lever::forward(twin, twin_data);  // the same numbers give the same bits
  CHECK(Eigen::VectorXd(twin_data.qacc) == Eigen::VectorXd(data.qacc));

  const double* mass_at = twin.body_mass.data();
  lever::Model moved = std::move(twin);  // the arrays change hands without a copy
  CHECK(moved.body_mass.data() == mass_at);
  lever::forward(moved, twin_data);
  CHECK(Eigen::VectorXd(twin_data.qacc) == Eigen::VectorXd(data.qacc));

  lever::Model other = load("models/arm2.xml");
  other = model;  // assigned a model of other sizes: its counts and arrays become model's
  CHECK(other.nv == model.nv);
  CHECK(other.body_mass.size() == model.body_mass.size());
  CHECK(other.body_mass.data() != model.body_mass.data());
  lever::Data other_data(other);
  lever::forward(other, other_data);
  CHECK(Eigen::VectorXd(other_data.qacc) == Eigen::VectorXd(data.qacc));
}

TEST_CASE("a Data checked once against a model edition is not checked again", "[fields]") {
  const lever::Model model = load("models/arm3.xml");
  lever::Data data(model);
  CHECK(model.fit_tag != 0);
  CHECK(data.model_tag == model.fit_tag);  // sized from it
  lever::Model heavier = model;
  heavier.body_mass[2] *= 2.0;
  lever::set_const(heavier);
  CHECK(heavier.fit_tag != model.fit_tag);
  lever::forward(heavier, data);  // same sizes: checked once, then remembered
  CHECK(data.model_tag == heavier.fit_tag);
  lever::forward(model, data);
  CHECK(data.model_tag == model.fit_tag);
  const lever::Model other = load("models/arm2.xml");
  CHECK_THROWS_AS(lever::forward(other, data), lever::StateError);
  CHECK(data.model_tag == model.fit_tag);  // a refusal changes nothing
}

TEST_CASE("rnea, solve_mass and jac_site refuse arguments of the wrong size or index", "[fields]") {
  const lever::Model model = load("models/arm3.xml");
  lever::Data data(model);
  std::mt19937_64 rng(lever::test::seed_for("fields_test"));
  lever::test::apply(lever::test::random_state(model, rng), data);
  lever::forward(model, data);
  const std::vector<double> before = snapshot(model, data);
  const auto refuses = [&](const char* name, const char* what, auto&& call) {
    INFO(name << " " << what);
    try {
      call();
      FAIL("no StateError");
    } catch (const lever::StateError& e) {
      CHECK_THAT(text_of(e), Catch::Contains(name));
      CHECK_THAT(text_of(e), Catch::Contains(what));
    }
    CHECK(same_bits(snapshot(model, data), before));
  };
  const int nv = model.nv;
  Eigen::VectorXd good(nv), tau(nv), short_vec(nv - 1), long_vec(nv + 1);
  good.setOnes();
  tau.setConstant(7.0);
  const Eigen::VectorXd tau_before = tau;
  refuses("lever::rnea", "qacc", [&] { lever::rnea(model, data, short_vec, tau); });
  CHECK(same_bits(tau, tau_before));
  refuses("lever::rnea", "tau", [&] { lever::rnea(model, data, good, long_vec); });
  Eigen::VectorXd x = long_vec;
  x.setConstant(3.0);
  const Eigen::VectorXd x_before = x;
  refuses("lever::solve_mass", "x", [&] { lever::solve_mass(model, data, x); });
  CHECK(same_bits(x, x_before));

  Eigen::MatrixXd jacp(3, nv), jacr(3, nv), wide(3, nv + 1), tall(4, nv);
  jacp.setConstant(5.0);
  jacr.setConstant(5.0);
  const Eigen::MatrixXd jac_before = jacp;
  refuses("lever::jac_site", "site -1", [&] { lever::jac_site(model, data, -1, jacp, jacr); });
  refuses("lever::jac_site", "is not in",
          [&] { lever::jac_site(model, data, model.nsite, jacp, jacr); });
  CHECK(jacp == jac_before);
  CHECK(jacr == jac_before);
  refuses("lever::jac_site", "3 x", [&] { lever::jac_site(model, data, 0, wide, jacr); });
  refuses("lever::jac_site", "3 x", [&] { lever::jac_site(model, data, 0, jacp, tall); });
  CHECK(jacp == jac_before);
  refuses("lever::jac_point", "body",
          [&] { lever::jac_point(model, data, model.nbody, Eigen::Vector3d::Zero(), jacp, jacr); });
  CHECK(jacp == jac_before);
  // the right sizes are accepted
  CHECK_NOTHROW(lever::rnea(model, data, good, tau));
  CHECK_NOTHROW(lever::jac_site(model, data, model.nsite - 1, jacp, jacr));
}

TEST_CASE("set_const refuses a Model whose counts changed since size_model, naming an array",
          "[fields]") {
  const lever::Model base = load("models/arm3.xml");
  const auto refuses = [](lever::Model model, const char* name) {
    INFO(name);
    try {
      lever::set_const(model);
      FAIL("no ModelError");
    } catch (const lever::ModelError& e) {
      CHECK_THAT(text_of(e), Catch::Contains(name));
      CHECK_THAT(text_of(e), Catch::Contains("size_model"));
    }
  };
  {
    lever::Model m = base;
    m.nsite += 1;
    refuses(m, "site_name");
  }
  {
    lever::Model m = base;
    m.nuser_body = 2;
    refuses(m, "body_user");
  }
  {
    lever::Model m = base;
    m.nmeshvert = 3;
    refuses(m, "mesh_vert");
  }
  {
    lever::Model m = base;
    m.nu -= 1;
    refuses(m, "actuator_name");
  }
  lever::Model m = base;
  CHECK_NOTHROW(lever::set_const(m));
  m.nuser_body = 2;  // sized again: accepted, the old numbers kept and the new column zero
  lever::size_model(m);
  CHECK(m.body_user.cols() == 2);
  CHECK(m.body_mass == base.body_mass);
  CHECK_NOTHROW(lever::set_const(m));
}

TEST_CASE("step1 + step2 equals step bit for bit with Euler, at random states", "[fields]") {
  for (const lever::Model& base : all_models()) {
    lever::Model model = base;
    model.opt.integrator = lever::Integrator::kEuler;
    INFO("model " << model.name);
    std::mt19937_64 rng(lever::test::seed_for(model.name + "/step1"));
    for (int trial = 0; trial < 20; ++trial) {
      const lever::test::State s = lever::test::random_state(model, rng);
      lever::Data whole(model), split(model);
      lever::test::apply(s, whole);
      lever::test::apply(s, split);
      for (int k = 0; k < 3; ++k) {
        lever::step(model, whole);
        lever::step1(model, split);
        lever::step2(model, split);
      }
      // step() leaves out what nothing in a step reads (lever/forward.hpp: the geom frames
      // where nothing collides), which step1() computes; tests/property/lean_step.cpp holds the
      // lean step to the whole one on everything else
      if (!model.contacts_possible) {
        split.geom_xpos = whole.geom_xpos;
        split.geom_xmat = whole.geom_xmat;
      }
      INFO("trial " << trial);
      CHECK(whole.time == split.time);
      CHECK(same_bits(whole.qpos, split.qpos));
      CHECK(same_bits(whole.qvel, split.qvel));
      CHECK(same_bits(snapshot(model, whole), snapshot(model, split)));
    }
  }
}

TEST_CASE("step1 + step2 of an RK4 model is an Euler step", "[fields]") {
  for (const lever::Model& base : all_models()) {
    lever::Model rk4 = base, euler = base;
    rk4.opt.integrator = lever::Integrator::kRK4;
    euler.opt.integrator = lever::Integrator::kEuler;
    INFO("model " << base.name);
    std::mt19937_64 rng(lever::test::seed_for(base.name + "/rk4"));
    for (int trial = 0; trial < 10; ++trial) {
      const lever::test::State s = lever::test::random_state(base, rng);
      lever::Data split(rk4), stepped(euler), rk_step(rk4);
      lever::test::apply(s, split);
      lever::test::apply(s, stepped);
      lever::test::apply(s, rk_step);
      lever::step1(rk4, split);
      lever::step2(rk4, split);
      lever::step(euler, stepped);
      lever::step(rk4, rk_step);
      INFO("trial " << trial);
      CHECK(same_bits(split.qpos, stepped.qpos));
      CHECK(same_bits(split.qvel, stepped.qvel));
      CHECK(split.time == stepped.time);
      // and the test could fail: RK4's own step differs from Euler's when anything moves
      if (s.qvel.norm() > 0) CHECK(!same_bits(rk_step.qpos, stepped.qpos));
    }
  }
}

TEST_CASE("between step1 and step2 a controller sees the forces and its control is used",
          "[fields]") {
  const lever::Model model = load("models/arm2.xml");
  lever::Data data(model), reference(model);
  data.qpos << 0.4, -0.3;
  reference.qpos = data.qpos;
  lever::step1(model, data);
  // gravity compensation from what step1 computed
  data.qfrc_applied = data.qfrc_bias;
  lever::step2(model, data);
  reference.qfrc_applied = data.qfrc_applied;
  lever::step(model, reference);
  CHECK(same_bits(data.qpos, reference.qpos));
  CHECK(same_bits(data.qvel, reference.qvel));
  // qfrc_applied cancels qfrc_bias exactly up to rounding through M^-1: a loose sanity bound on
  // what the test is about (the split equals step bit for bit, above), not an agreement claim
  CHECK(data.qacc.norm() < 1e-9);
}

// ---- size_model
// -----------------------------------------------------------------------

namespace {

// How many numbers of type Element a member holds, as the member itself says (independent of the
// table's Layout code): a vector of entries of sizeof(T) bytes each, or an Eigen vector.
template <class Element, class T>
long numbers_in(const lever::ArenaArray<T>& v) {
  static_assert(sizeof(T) % sizeof(Element) == 0);
  return static_cast<long>(v.size() * (sizeof(T) / sizeof(Element)));
}
template <class Element>
long numbers_in(const lever::ArenaVector& v) {
  return v.size();
}
template <class Element>
long numbers_in(const lever::ArenaRowMatrix& m) {  // user data, keyframes: rows x cols
  return m.size();
}

struct Stored {
  std::string name;
  const void* data;
  long numbers;
};

// Every array of the table, as its member holds it.
std::vector<Stored> stored_arrays(const lever::Model& model) {
  std::vector<Stored> all;
#define LEVER_TEST_STORED(name, type, rows, cols, origin) \
  all.push_back({#name, model.name.data(), numbers_in<type>(model.name)});
  LEVER_MODEL_FIELDS(LEVER_TEST_STORED)
#undef LEVER_TEST_STORED
  return all;
}

// The length the table gives an array in this model.
long promised(const lever::Model& model, const lever::FieldInfo& info) {
  const long rows = lever::size_of(model, info.rows);
  return rows * (info.cols < 0 ? lever::size_of(model, info.cols_size) : info.cols);
}

// Every number of the table's arrays, as doubles, with every name and keyframe number.
std::vector<double> numbers_of(const lever::Model& model) {
  std::vector<double> all;
  for (const FieldView& v : lever::model_fields(model)) {
    for (long k = 0; k < v.size(); ++k) {
      switch (v.info->scalar) {
        case Scalar::kDouble: all.push_back(static_cast<const double*>(v.data)[k]); break;
        case Scalar::kInt: all.push_back(static_cast<const int*>(v.data)[k]); break;
        case Scalar::kByte: all.push_back(static_cast<const uint8_t*>(v.data)[k]); break;
      }
    }
  }
  for (const auto* matrix : {&model.key_qpos, &model.key_qvel, &model.key_ctrl}) {
    all.insert(all.end(), matrix->data(), matrix->data() + matrix->size());
  }
  all.insert(all.end(), model.key_time.begin(), model.key_time.end());
  return all;
}

std::vector<std::string> names_of(const lever::Model& model) {
  std::vector<std::string> all;
#define LEVER_TEST_NAMES(name, count) all.insert(all.end(), model.name.begin(), model.name.end());
  LEVER_MODEL_NAMES(LEVER_TEST_NAMES)
#undef LEVER_TEST_NAMES
  return all;
}

}  // namespace

TEST_CASE("size_model gives every array the length the field table promises", "[fields]") {
  lever::Model model;  // the world body alone: every body array has its one row
  model.body_mass[0] = 2.5;
  model.body_quat[0] = Eigen::Vector4d(0.5, 0.5, 0.5, 0.5);
  model.body_name[0] = "ground";
  model.fit_tag = 7;
  // counts that need not make a consistent model: sizing reads each one alone
  model.nbody = 4;
  model.njnt = 3;
  model.nq = 9;
  model.nv = 8;
  model.ngeom = 5;
  model.nsite = 2;
  model.nu = 2;
  model.npair = 1;
  model.nexclude = 3;
  model.nmesh = 2;
  model.nmeshvert = 6;
  model.nmeshgraph = 11;
  model.nmeshface = 4;
  model.neq = 2;
  model.nkey = 2;
  model.nsensor = 3;
  model.nsensordata = 7;
  model.nuser_body = 2;
  model.nuser_jnt = 1;
  model.nuser_geom = 3;
  model.nuser_site = 1;
  model.nuser_tendon = 2;
  model.nuser_actuator = 2;
  model.nuser_sensor = 1;
  model.ntendon = 2;
  model.nwrap = 5;
  lever::size_model(model);

  const std::vector<lever::FieldInfo>& table = lever::model_field_table();
  const std::vector<Stored> stored = stored_arrays(model);
  const std::vector<FieldView> views = lever::model_fields(model);
  REQUIRE(stored.size() == table.size());
  for (size_t i = 0; i < table.size(); ++i) {
    INFO("Model::" << table[i].name);
    REQUIRE(stored[i].name == table[i].name);
    CHECK(stored[i].numbers == promised(model, table[i]));
    CHECK(stored[i].numbers > 0);  // every count above is positive
    CHECK(stored[i].data == views[i].data);
    // zero-filled: the world's row kept what it held, every new row is zero (body_mocapid: -1,
    // no mocap body)
    const long first_new = table[i].rows == lever::Size::kNbody ? views[i].cols : 0;
    const double fill = std::string(table[i].name) == "body_mocapid" ? -1.0 : 0.0;
    for (long k = first_new; k < views[i].size(); ++k) {
      double x = 0.0;
      if (table[i].scalar == Scalar::kDouble) x = static_cast<const double*>(views[i].data)[k];
      if (table[i].scalar == Scalar::kInt) x = static_cast<const int*>(views[i].data)[k];
      if (table[i].scalar == Scalar::kByte) x = static_cast<const uint8_t*>(views[i].data)[k];
      CHECK(x == fill);
    }
  }
  CHECK(model.body_mass[0] == 2.5);
  CHECK(model.body_quat[0] == Eigen::Vector4d(0.5, 0.5, 0.5, 0.5));
  CHECK(model.body_jntadr[0] == -1);  // the default Model's world row, kept
  // outside the table: one name per object, and the keyframes
  CHECK(model.body_name == std::vector<std::string>{"ground", "", "", ""});
  CHECK(model.jnt_name.size() == 3);
  CHECK(model.geom_name.size() == 5);
  CHECK(model.site_name.size() == 2);
  CHECK(model.actuator_name.size() == 2);
  CHECK(model.key_name.size() == 2);
  CHECK(model.key_time == std::vector<double>{0.0, 0.0});
  CHECK((model.key_qpos.rows() == 2 && model.key_qpos.cols() == 9));
  CHECK((model.key_qvel.rows() == 2 && model.key_qvel.cols() == 8));
  CHECK((model.key_ctrl.rows() == 2 && model.key_ctrl.cols() == 2));
  CHECK(model.key_qpos.isZero());
  CHECK(model.fit_tag == 0);  // set_const must run again before a Data trusts the model

  // smaller counts cut the arrays, keeping the rows within them
  model.body_mass[1] = 4.0;
  model.nbody = 2;
  model.nkey = 1;
  model.key_qpos(0, 3) = 1.5;
  lever::size_model(model);
  CHECK(model.body_mass == std::vector<double>{2.5, 4.0});
  CHECK(model.body_name.size() == 2);
  CHECK((model.key_qpos.rows() == 1 && model.key_qpos(0, 3) == 1.5));
  for (size_t i = 0; i < table.size(); ++i) {
    INFO("Model::" << table[i].name);
    CHECK(stored_arrays(model)[i].numbers == promised(model, table[i]));
  }
}

TEST_CASE("size_model refuses a negative count or no world body, and changes nothing", "[fields]") {
  const lever::Model base = load("models/arm3.xml");
  const auto refuses = [&](auto&& edit, const char* count) {
    INFO(count);
    lever::Model model = base;
    edit(model);
    const std::vector<double> numbers = numbers_of(model);
    const std::vector<std::string> names = names_of(model);
    try {
      lever::size_model(model);
      FAIL("no ModelError");
    } catch (const lever::ModelError& e) {
      CHECK_THAT(text_of(e), Catch::Contains(count));
    }
    CHECK(same_bits(numbers_of(model), numbers));
    CHECK(names_of(model) == names);
    CHECK(model.fit_tag == base.fit_tag);
  };
  refuses([](lever::Model& m) { m.njnt = -1; }, "njnt");
  refuses([](lever::Model& m) { m.nkey = -2; }, "nkey");
  refuses([](lever::Model& m) { m.nexclude = -1; }, "nexclude");
  refuses([](lever::Model& m) { m.nbody = 0; }, "nbody");
}

TEST_CASE("a compiled model's arrays have the lengths size_model gives them", "[fields]") {
  for (const lever::Model& model : all_models()) {
    INFO("model " << model.name);
    const std::vector<lever::FieldInfo>& table = lever::model_field_table();
    const std::vector<Stored> stored = stored_arrays(model);
    for (size_t i = 0; i < table.size(); ++i) {
      INFO("Model::" << table[i].name);
      CHECK(stored[i].numbers == promised(model, table[i]));
    }
#define LEVER_TEST_NAME_COUNT(name, count) \
  CHECK(static_cast<int>(model.name.size()) == model.count);
    LEVER_MODEL_NAMES(LEVER_TEST_NAME_COUNT)
#undef LEVER_TEST_NAME_COUNT
    CHECK(static_cast<int>(model.key_time.size()) == model.nkey);
    // sizing it again moves nothing: every array already has its length and keeps its numbers
    lever::Model sized = model;
    lever::size_model(sized);
    CHECK(same_bits(numbers_of(sized), numbers_of(model)));
    CHECK(names_of(sized) == names_of(model));
    lever::set_const(sized);
    CHECK(same_bits(numbers_of(sized), numbers_of(model)));
  }
}
