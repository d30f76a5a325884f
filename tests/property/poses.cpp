// The lean pose stage against the whole kinematics: poses() is what kinematics() places, and the
// quaternions kinematics() composes beside the rotation matrices describe the same rotations;
// place_site() places one site's frame, and the bodies on its path, as poses() does, and nothing
// else; body_poses(), body_kinematics() and jac_site_from_q() write what they promise bit for bit
// as poses(), kinematics() and kinematics() + jac_site() do, and nothing else.
#include "property_models.hpp"

namespace lever::test {

namespace {

template <class Array>  // a std::vector or a Data's array
bool same(const Array& a, const Array& b) {
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i] != b[i]) return false;
  }
  return a.size() == b.size();
}

}  // namespace

TEST_CASE("property: poses() writes kinematics()' frames bit for bit",
          "[property][kinematics]") {
  for (const ModelCase& c : every_model_and_random_trees()) {
    Data full(c.model), lean(c.model);
    std::mt19937_64 rng(c.seed);
    for (int k = 0; k < kStatesPerModel / 10; ++k) {
      const auto state = random_state(c.model, rng);
      apply(state, full);
      apply(state, lean);
      kinematics(c.model, full);
      // a mark poses() must overwrite: the quaternions are what the frames are made from
      for (auto& q : lean.xquat) q = Eigen::Vector4d(2, 0, 0, 0);
      poses(c.model, lean);
      INFO(c.name << ", seed " << c.seed << ", state " << k);
      CHECK(lean.qpos == full.qpos);  // both normalized the state's quaternions
      CHECK(same(lean.xpos, full.xpos));
      CHECK(same(lean.xmat, full.xmat));
      CHECK(same(lean.xipos, full.xipos));
      CHECK(same(lean.ximat, full.ximat));
      CHECK(same(lean.xanchor, full.xanchor));
      CHECK(same(lean.xaxis, full.xaxis));
      CHECK(same(lean.geom_xpos, full.geom_xpos));
      CHECK(same(lean.geom_xmat, full.geom_xmat));
      CHECK(same(lean.site_xpos, full.site_xpos));
      CHECK(same(lean.site_xmat, full.site_xmat));
      CHECK(same(lean.xquat, full.xquat));
    }
  }
}

TEST_CASE("property: the bodies welded to the world are copied as kinematics() would place them",
          "[property][kinematics]") {
  // set_const places them once (Model::body_static_*); with body_static_leading 0 every call
  // places every body from the parameters, which the copies must equal bit for bit
  int copied = 0;
  for (const ModelCase& c : every_model_and_random_trees()) {
    Model placed = c.model;
    placed.body_static_leading = 0;
    copied += c.model.body_static_leading;
    Data with_copies(c.model), without(placed);
    std::mt19937_64 rng(c.seed);
    for (int k = 0; k < 3; ++k) {
      const auto state = random_state(c.model, rng);
      apply(state, with_copies);
      apply(state, without);
      kinematics(c.model, with_copies);
      kinematics(placed, without);
      INFO(c.name << ", seed " << c.seed << ", state " << k);
      CHECK(same(with_copies.xpos, without.xpos));
      CHECK(same(with_copies.xquat, without.xquat));
      CHECK(same(with_copies.xmat, without.xmat));
      CHECK(same(with_copies.xipos, without.xipos));
      CHECK(same(with_copies.ximat, without.ximat));
      CHECK(same(with_copies.subtree_com, without.subtree_com));
    }
    for (int b = 0; b < c.model.nbody; ++b) {
      // the leading run: bodies 1, 2, ... as long as each is welded to the world
      const bool leading = b > 0 && b <= c.model.body_static_leading;
      INFO(c.name << ", body " << b);
      if (leading) CHECK(c.model.body_static[b] == 1);
      if (b == c.model.body_static_leading + 1 && b < c.model.nbody) CHECK(c.model.body_static[b] == 0);
      const bool welded = b > 0 && c.model.body_jntnum[b] == 0 && c.model.body_mocapid[b] < 0 &&
                          (c.model.body_parentid[b] == 0 ||
                           c.model.body_static[c.model.body_parentid[b]] == 1);
      CHECK(c.model.body_static[b] == (welded ? 1 : 0));
    }
  }
  CHECK(copied > 0);  // panda7's link0 at least
}

TEST_CASE("property: a body welded to the world moves with body_pos and body_quat after set_const",
          "[property][kinematics]") {
  Model model = mjcf::load_file(model_path("models/panda7.xml"));
  REQUIRE(model.body_static_leading >= 1);
  Data before(model);
  kinematics(model, before);
  model.body_pos[1] += Eigen::Vector3d(0.1, -0.2, 0.3);
  model.body_quat[1] = Eigen::Vector4d(0.9, 0.1, -0.3, 0.2).normalized();
  set_const(model);
  Model placed = model;
  placed.body_static_leading = 0;
  Data copied(model), computed(placed);
  kinematics(model, copied);
  kinematics(placed, computed);
  CHECK(copied.xpos[1] != before.xpos[1]);
  CHECK(copied.xquat[1] != before.xquat[1]);
  CHECK(same(copied.xpos, computed.xpos));
  CHECK(same(copied.xquat, computed.xquat));
  CHECK(same(copied.xmat, computed.xmat));
  CHECK(same(copied.xipos, computed.xipos));
  CHECK(same(copied.ximat, computed.ximat));
}

TEST_CASE("property: kinematics()' xquat is a unit quaternion whose rotation is xmat",
          "[property][kinematics]") {
  // xmat is made from the normalized xquat (as MuJoCo's mj_kinematics makes it): the matrix of
  // the quaternion to the bit, and the quaternion unit to rounding
  constexpr double kBound = 1e-13;
  for (const ModelCase& c : every_model_and_random_trees()) {
    Data data(c.model);
    std::mt19937_64 rng(c.seed);
    for (int k = 0; k < kStatesPerModel / 10; ++k) {
      apply(random_state(c.model, rng), data);
      kinematics(c.model, data);
      for (int b = 0; b < c.model.nbody; ++b) {
        INFO(c.name << ", seed " << c.seed << ", state " << k << ", body " << b);
        CHECK(std::abs(data.xquat[b].norm() - 1.0) <= kBound);
        const Eigen::Matrix3d from_quat = quat_to_mat(data.xquat[b]);
        CHECK(from_quat == Eigen::Matrix3d(data.xmat[b]));
      }
    }
  }
}

TEST_CASE("property: the world's frame is set on every call, whatever Data held there",
          "[property][kinematics]") {
  // MuJoCo's mj_kinematics sets the world's frame each time; every other frame is placed on it
  for (const ModelCase& c : every_model_and_random_trees()) {
    Data clean(c.model), spoiled(c.model);
    std::mt19937_64 rng(c.seed);
    for (int k = 0; k < kStatesPerModel / 10; ++k) {
      const auto state = random_state(c.model, rng);
      apply(state, clean);
      apply(state, spoiled);
      forward(c.model, clean);
      const auto spoil = [&] {
        spoiled.xpos[0].setConstant(0.5);
        spoiled.xmat[0].setConstant(0.5);
        spoiled.xquat[0].setConstant(0.5);
        spoiled.xipos[0].setConstant(0.5);
        spoiled.ximat[0].setConstant(0.5);
      };
      spoil();
      forward(c.model, spoiled);
      INFO(c.name << ", seed " << c.seed << ", state " << k);
      CHECK(same(spoiled.xpos, clean.xpos));
      CHECK(same(spoiled.xmat, clean.xmat));
      CHECK(same(spoiled.xquat, clean.xquat));
      CHECK(same(spoiled.xipos, clean.xipos));
      CHECK(same(spoiled.ximat, clean.ximat));
      CHECK(same(spoiled.site_xpos, clean.site_xpos));
      CHECK(spoiled.qacc == clean.qacc);
      CHECK(clean.xpos[0] == Eigen::Vector3d::Zero());
      CHECK(Eigen::Matrix3d(clean.xmat[0]) == Eigen::Matrix3d::Identity());
      CHECK(clean.xquat[0] == Eigen::Vector4d(1, 0, 0, 0));
      // the lean stages too: poses() and place_site() place on the world's frame as well (each
      // from the state itself: normalizing qpos's quaternions again may move their last bit)
      const auto lean_check = [&](const auto& place) {
        apply(state, clean);
        apply(state, spoiled);
        place(clean);
        spoil();
        place(spoiled);
        CHECK(same(spoiled.site_xpos, clean.site_xpos));
      };
      lean_check([&](Data& d) { poses(c.model, d); });
      for (int s = 0; s < c.model.nsite; ++s) {
        lean_check([&](Data& d) { place_site(c.model, d, s); });
      }
    }
  }
}

namespace {

constexpr double kUnplaced = -7.25;  // a value no frame holds: what place_site() must leave alone

// Every frame and com-frame array of data but the world body's (which place_site() reads) set to
// kUnplaced.
void mark_unplaced(Data& data) {
  for (std::size_t b = 1; b < data.xpos.size(); ++b) {
    data.xpos[b].setConstant(kUnplaced);
    data.xmat[b].setConstant(kUnplaced);
    data.xquat[b].setConstant(kUnplaced);
    data.xipos[b].setConstant(kUnplaced);
    data.ximat[b].setConstant(kUnplaced);
  }
  for (auto* a :
       {&data.xanchor, &data.xaxis, &data.geom_xpos, &data.site_xpos, &data.subtree_com}) {
    for (auto& v : *a) v.setConstant(kUnplaced);
  }
  for (auto* a : {&data.geom_xmat, &data.site_xmat}) {
    for (auto& m : *a) m.setConstant(kUnplaced);
  }
  for (auto& S : data.cdof) S.setConstant(kUnplaced);
}

template <class T>
bool unplaced(const T& value) {
  return (value.array() == kUnplaced).all();
}

template <class Array>
bool all_unplaced(const Array& values) {
  return std::all_of(values.begin(), values.end(),
                     [](const typename Array::value_type& v) { return unplaced(v); });
}

}  // namespace

TEST_CASE(
    "property: place_site() writes poses()' frames of the site and its path, bit for bit, "
    "and nothing else",
    "[property][kinematics]") {
  int sites_checked = 0;
  for (const ModelCase& c : every_model_and_random_trees()) {
    const Model& m = c.model;
    Data full(m), tip(m);
    std::mt19937_64 rng(c.seed);
    for (int k = 0; k < kStatesPerModel / 20; ++k) {
      const auto state = random_state(m, rng);
      apply(state, full);
      poses(m, full);
      for (int s = 0; s < m.nsite; ++s) {
        apply(state, tip);
        mark_unplaced(tip);
        place_site(m, tip, s);
        ++sites_checked;
        // the path, found here independently of place_site()
        std::vector<bool> on_path(m.nbody, false);
        for (int b = m.site_bodyid[s]; b > 0; b = m.body_parentid[b]) on_path[b] = true;
        INFO(c.name << ", seed " << c.seed << ", state " << k << ", site " << s);
        CHECK(tip.qpos == full.qpos);  // both normalized the state's quaternions
        for (int b = 1; b < m.nbody; ++b) {
          INFO("body " << b << (on_path[b] ? " (on the path)" : ""));
          if (on_path[b]) {
            CHECK(tip.xpos[b] == full.xpos[b]);
            CHECK(tip.xquat[b] == full.xquat[b]);
            CHECK(tip.xmat[b] == full.xmat[b]);
          } else {
            CHECK(unplaced(tip.xpos[b]));
            CHECK(unplaced(tip.xquat[b]));
            CHECK(unplaced(tip.xmat[b]));
          }
          CHECK(unplaced(tip.xipos[b]));
          CHECK(unplaced(tip.ximat[b]));
        }
        for (int other = 0; other < m.nsite; ++other) {
          INFO("site_xpos/site_xmat of site " << other);
          if (other == s) {
            CHECK(tip.site_xpos[s] == full.site_xpos[s]);
            CHECK(tip.site_xmat[s] == full.site_xmat[s]);
          } else {
            CHECK(unplaced(tip.site_xpos[other]));
            CHECK(unplaced(tip.site_xmat[other]));
          }
        }
        CHECK(all_unplaced(tip.xanchor));
        CHECK(all_unplaced(tip.xaxis));
        CHECK(all_unplaced(tip.geom_xpos));
        CHECK(all_unplaced(tip.geom_xmat));
        CHECK(all_unplaced(tip.subtree_com));
        CHECK(all_unplaced(tip.cdof));
      }
    }
  }
  CHECK(sites_checked > 0);  // some model has sites: the checks above ran
}

TEST_CASE("property: place_site() refuses a site index out of range and changes nothing",
          "[property][kinematics]") {
  for (const ModelCase& c : every_model_and_random_trees()) {
    const Model& m = c.model;
    Data data(m);
    std::mt19937_64 rng(c.seed);
    apply(random_state(m, rng), data);
    mark_unplaced(data);
    const Eigen::VectorXd qpos = data.qpos;
    INFO(c.name);
    for (const int bad : {-1, m.nsite, m.nsite + 5}) {
      CHECK_THROWS_AS(place_site(m, data, bad), StateError);
      CHECK_THROWS_WITH(place_site(m, data, bad),
                        Catch::Contains("lever::place_site: site " + std::to_string(bad)));
    }
    CHECK(data.qpos == qpos);
    CHECK(all_unplaced(std::vector<Eigen::Vector3d>(data.xpos.begin() + 1, data.xpos.end())));
    CHECK(all_unplaced(data.site_xpos));
  }
}

TEST_CASE("property: body_poses() writes poses()' body frames bit for bit, and nothing else",
          "[property][kinematics]") {
  for (const ModelCase& c : every_model_and_random_trees()) {
    const Model& m = c.model;
    Data full(m), lean(m);
    std::mt19937_64 rng(c.seed);
    for (int k = 0; k < kStatesPerModel / 20; ++k) {
      const auto state = random_state(m, rng);
      apply(state, full);
      poses(m, full);
      apply(state, lean);
      mark_unplaced(lean);
      body_poses(m, lean);
      INFO(c.name << ", seed " << c.seed << ", state " << k);
      CHECK(lean.qpos == full.qpos);
      CHECK(same(lean.xpos, full.xpos));
      CHECK(same(lean.xquat, full.xquat));
      CHECK(same(lean.xmat, full.xmat));
      CHECK(all_unplaced(std::vector<Eigen::Vector3d>(lean.xipos.begin() + 1, lean.xipos.end())));
      CHECK(all_unplaced(std::vector<Mat3>(lean.ximat.begin() + 1, lean.ximat.end())));
      CHECK(all_unplaced(lean.xanchor));
      CHECK(all_unplaced(lean.xaxis));
      CHECK(all_unplaced(lean.geom_xpos));
      CHECK(all_unplaced(lean.geom_xmat));
      CHECK(all_unplaced(lean.site_xpos));
      CHECK(all_unplaced(lean.site_xmat));
      CHECK(all_unplaced(lean.subtree_com));
      CHECK(all_unplaced(lean.cdof));
    }
  }
}

TEST_CASE(
    "property: body_kinematics() writes kinematics()' arrays bit for bit, but for the geom and "
    "site frames, which it leaves alone",
    "[property][kinematics]") {
  for (const ModelCase& c : every_model_and_random_trees()) {
    const Model& m = c.model;
    Data full(m), lean(m);
    std::mt19937_64 rng(c.seed);
    for (int k = 0; k < kStatesPerModel / 20; ++k) {
      const auto state = random_state(m, rng);
      apply(state, full);
      kinematics(m, full);
      apply(state, lean);
      mark_unplaced(lean);
      for (auto& I : lean.cinert) I.m = kUnplaced;
      body_kinematics(m, lean);
      INFO(c.name << ", seed " << c.seed << ", state " << k);
      CHECK(lean.qpos == full.qpos);
      CHECK(same(lean.xpos, full.xpos));
      CHECK(same(lean.xquat, full.xquat));
      CHECK(same(lean.xmat, full.xmat));
      CHECK(same(lean.xipos, full.xipos));
      CHECK(same(lean.ximat, full.ximat));
      CHECK(same(lean.xanchor, full.xanchor));
      CHECK(same(lean.xaxis, full.xaxis));
      CHECK(same(lean.subtree_com, full.subtree_com));
      CHECK(same(lean.cdof, full.cdof));
      for (int b = 1; b < m.nbody; ++b) {
        INFO("cinert of body " << b);
        CHECK(lean.cinert[b].m == full.cinert[b].m);
        CHECK(lean.cinert[b].h == full.cinert[b].h);
        CHECK(lean.cinert[b].I == full.cinert[b].I);
      }
      CHECK(all_unplaced(lean.geom_xpos));
      CHECK(all_unplaced(lean.geom_xmat));
      CHECK(all_unplaced(lean.site_xpos));
      CHECK(all_unplaced(lean.site_xmat));
    }
  }
}

TEST_CASE(
    "property: jac_site_from_q() gives kinematics() + jac_site() bit for bit, and writes only "
    "the site's tree and the site",
    "[property][kinematics]") {
  int sites_checked = 0;
  for (const ModelCase& c : every_model_and_random_trees()) {
    const Model& m = c.model;
    Data full(m), lean(m);
    Eigen::MatrixXd jacp(3, m.nv), jacr(3, m.nv), lean_jacp(3, m.nv), lean_jacr(3, m.nv);
    std::mt19937_64 rng(c.seed);
    for (int k = 0; k < kStatesPerModel / 20; ++k) {
      const auto state = random_state(m, rng);
      apply(state, full);
      kinematics(m, full);
      for (int s = 0; s < m.nsite; ++s) {
        jac_site(m, full, s, jacp, jacr);
        apply(state, lean);
        mark_unplaced(lean);
        lean_jacp.setConstant(kUnplaced);  // every entry must be written, zeros included
        lean_jacr.setConstant(kUnplaced);
        jac_site_from_q(m, lean, s, lean_jacp, lean_jacr);
        ++sites_checked;
        const int root = m.body_rootid[m.site_bodyid[s]];
        INFO(c.name << ", seed " << c.seed << ", state " << k << ", site " << s);
        CHECK(lean.qpos == full.qpos);
        CHECK(lean_jacp == jacp);
        CHECK(lean_jacr == jacr);
        CHECK(lean.site_xpos[s] == full.site_xpos[s]);
        CHECK(lean.site_xmat[s] == full.site_xmat[s]);
        for (int b = 1; b < m.nbody; ++b) {
          const bool in_tree = root > 0 && m.body_rootid[b] == root;
          INFO("body " << b << (in_tree ? " (in the site's tree)" : ""));
          if (in_tree) {
            CHECK(lean.xpos[b] == full.xpos[b]);
            CHECK(lean.xquat[b] == full.xquat[b]);
            CHECK(lean.xmat[b] == full.xmat[b]);
            CHECK(lean.xipos[b] == full.xipos[b]);
            CHECK(lean.subtree_com[b] == full.subtree_com[b]);
          } else {
            CHECK(unplaced(lean.xpos[b]));
            CHECK(unplaced(lean.xipos[b]));
            CHECK(unplaced(lean.subtree_com[b]));
          }
          CHECK(unplaced(lean.ximat[b]));
        }
        for (int j = 0; j < m.njnt; ++j) {
          const bool in_tree = root > 0 && m.body_rootid[m.jnt_bodyid[j]] == root;
          INFO("joint " << j << (in_tree ? " (in the site's tree)" : ""));
          CHECK(unplaced(lean.xanchor[j]) != in_tree);
          if (in_tree) {
            CHECK(lean.xanchor[j] == full.xanchor[j]);
            CHECK(lean.xaxis[j] == full.xaxis[j]);
          }
        }
        for (int other = 0; other < m.nsite; ++other) {
          if (other != s) CHECK(unplaced(lean.site_xpos[other]));
        }
        CHECK(all_unplaced(lean.geom_xpos));
        CHECK(all_unplaced(lean.cdof));
      }
    }
    // refused before anything is written
    apply(random_state(m, rng), lean);
    mark_unplaced(lean);
    for (const int bad : {-1, m.nsite}) {
      CHECK_THROWS_WITH(jac_site_from_q(m, lean, bad, lean_jacp, lean_jacr),
                        Catch::Contains("lever::jac_site_from_q: site " + std::to_string(bad)));
    }
    if (m.nsite > 0) {
      Eigen::MatrixXd wide(3, m.nv + 1);
      CHECK_THROWS_WITH(jac_site_from_q(m, lean, 0, wide, lean_jacr),
                        Catch::Contains("lever::jac_site_from_q: a Jacobian must be 3 x"));
    }
    CHECK(all_unplaced(lean.site_xpos));
    CHECK(all_unplaced(std::vector<Eigen::Vector3d>(lean.xpos.begin() + 1, lean.xpos.end())));
  }
  CHECK(sites_checked > 0);
}

}  // namespace lever::test
