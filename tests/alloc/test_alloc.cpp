// Once Data is built, evaluating and stepping allocate nothing (lever/data.hpp's promise).
//
// This executable replaces the global operator new/delete with counting versions. Eigen does not
// allocate through operator new but through malloc, so on glibc (without a sanitizer, which has
// its own malloc) malloc, calloc, realloc and the aligned variants are replaced as well, counting
// and then forwarding to glibc's own (__libc_malloc, ...). A test first proves that both counters
// see what they should: a std::vector and an Eigen::VectorXd.
#include <catch2/catch.hpp>

#include <lever/batch.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <lever/harness/models.hpp>

#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <new>
#include <random>
#include <string>
#include <vector>

#ifdef LEVER_ALLOC_HAVE_MUJOCO
#include <lever/harness/from_mujoco.hpp>
#endif

// ---- counting allocation functions ------------------------------------------------------------

namespace {
std::atomic<long> g_new_calls{0};     // operator new, every form
std::atomic<long> g_malloc_calls{0};  // malloc, calloc, realloc, aligned forms
}  // namespace

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define LEVER_ALLOC_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || \
    __has_feature(memory_sanitizer)
#define LEVER_ALLOC_SANITIZER 1
#endif
#endif

#if defined(__GLIBC__) && !defined(LEVER_ALLOC_SANITIZER)
#define LEVER_ALLOC_COUNTS_MALLOC 1
extern "C" {
// glibc's own entry points, so the counting malloc below can forward to them (reserved names by
// design: these are glibc's exported aliases of its allocator)
void* __libc_malloc(std::size_t size);                     // NOLINT(bugprone-reserved-identifier)
void* __libc_calloc(std::size_t count, std::size_t size);  // NOLINT(bugprone-reserved-identifier)
void* __libc_realloc(void* ptr, std::size_t size);         // NOLINT(bugprone-reserved-identifier)
// NOLINTNEXTLINE(bugprone-reserved-identifier)
void* __libc_memalign(std::size_t alignment, std::size_t size);
void __libc_free(void* ptr);  // NOLINT(bugprone-reserved-identifier)

void* malloc(std::size_t size) noexcept {
  g_malloc_calls.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(size);
}
void* calloc(std::size_t nmemb, std::size_t size) noexcept {  // glibc's parameter names
  g_malloc_calls.fetch_add(1, std::memory_order_relaxed);
  return __libc_calloc(nmemb, size);
}
void* realloc(void* ptr, std::size_t size) noexcept {
  g_malloc_calls.fetch_add(1, std::memory_order_relaxed);
  return __libc_realloc(ptr, size);
}
void free(void* ptr) noexcept { __libc_free(ptr); }
void* memalign(std::size_t alignment, std::size_t size) noexcept {
  g_malloc_calls.fetch_add(1, std::memory_order_relaxed);
  return __libc_memalign(alignment, size);
}
void* aligned_alloc(std::size_t alignment, std::size_t size) noexcept {
  g_malloc_calls.fetch_add(1, std::memory_order_relaxed);
  return __libc_memalign(alignment, size);
}
int posix_memalign(void** memptr, std::size_t alignment, std::size_t size) noexcept {
  g_malloc_calls.fetch_add(1, std::memory_order_relaxed);
  void* p = __libc_memalign(alignment, size);
  if (p == nullptr) return ENOMEM;
  *memptr = p;
  return 0;
}
}  // extern "C"
#endif

namespace {
void* counted_new(std::size_t size) {
  g_new_calls.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* counted_new(std::size_t size, std::align_val_t alignment) {
  g_new_calls.fetch_add(1, std::memory_order_relaxed);
  const auto a = static_cast<std::size_t>(alignment);
  const std::size_t rounded = (size + a - 1) / a * a;  // aligned_alloc wants a multiple
  if (void* p = std::aligned_alloc(a, rounded == 0 ? a : rounded)) return p;
  throw std::bad_alloc();
}
}  // namespace

void* operator new(std::size_t size) { return counted_new(size); }
void* operator new[](std::size_t size) { return counted_new(size); }
void* operator new(std::size_t size, std::align_val_t a) { return counted_new(size, a); }
void* operator new[](std::size_t size, std::align_val_t a) { return counted_new(size, a); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return counted_new(size);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return counted_new(size);
  } catch (...) {
    return nullptr;
  }
}
void* operator new(std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
  try {
    return counted_new(size, a);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
  try {
    return counted_new(size, a);
  } catch (...) {
    return nullptr;
  }
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }

// ---- helpers
// ---------------------------------------------------------------------------------------

namespace {

struct Allocations {
  long news = 0, mallocs = 0;
};

// The allocations `fn` makes. Nothing else may run between the two readings.
template <class Fn>
Allocations count(Fn&& fn) {
  const long n0 = g_new_calls.load(), m0 = g_malloc_calls.load();
  fn();
  return {g_new_calls.load() - n0, g_malloc_calls.load() - m0};
}

lever::Model load(const std::string& path, std::string& how) {
  try {
    how = "mjcf_lite";
    return lever::mjcf::load_file(path);
  } catch (const lever::Error& e) {
#ifdef LEVER_ALLOC_HAVE_MUJOCO
    how = std::string("from_mujoco (mjcf_lite: ") + e.what() + ")";
    const auto mj = lever::test::mujoco_load(path);
    return lever::test::from_mujoco(mj.get());
#else
    throw;
#endif
  }
}

struct NamedState {
  std::string name;
  Eigen::VectorXd qpos, qvel, ctrl;
};

// Inside the ranges; every limited joint past its lower stop; past its upper stop; alternating
// (so several rows are active and the limit solve pivots); controls beyond their ranges; a NaN
// control; and a NaN velocity (step() resets the state).
std::vector<NamedState> states_for(const lever::Model& m) {
  std::mt19937_64 rng(lever::test::seed_for(m.name));
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  NamedState inside{"inside the ranges", m.qpos0, Eigen::VectorXd(m.nv), Eigen::VectorXd(m.nu)};
  for (int j = 0; j < m.njnt; ++j) {
    const int a = m.jnt_qposadr[j];
    if (m.jnt_limited[j]) {
      const double mid = 0.5 * (m.jnt_range[j][0] + m.jnt_range[j][1]);
      inside.qpos[a] = mid + 0.3 * (m.jnt_range[j][1] - m.jnt_range[j][0]) * u(rng);
    } else {
      inside.qpos[a] += u(rng);
    }
  }
  for (int i = 0; i < m.nv; ++i) inside.qvel[i] = u(rng);
  for (int a = 0; a < m.nu; ++a) inside.ctrl[a] = u(rng);

  std::vector<NamedState> states{inside};
  auto past = [&](const std::string& name, auto side_of) {
    NamedState s = inside;
    s.name = name;
    for (int j = 0; j < m.njnt; ++j) {
      if (!m.jnt_limited[j]) continue;
      const int side = side_of(j);
      s.qpos[m.jnt_qposadr[j]] = side == 0 ? m.jnt_range[j][0] - 0.01 : m.jnt_range[j][1] + 0.01;
    }
    states.push_back(s);
  };
  past("every limited joint past its lower stop", [](int) { return 0; });
  past("every limited joint past its upper stop", [](int) { return 1; });
  past("alternate stops", [](int j) { return j % 2; });

  NamedState wild = inside;
  wild.name = "controls beyond their ranges";
  for (int a = 0; a < m.nu; ++a) wild.ctrl[a] = 1e3 * (a % 2 ? 1 : -1);
  states.push_back(wild);
  if (m.nu > 0) {
    NamedState bad = inside;
    bad.name = "a NaN control";
    bad.ctrl[0] = std::numeric_limits<double>::quiet_NaN();
    states.push_back(bad);
  }
  if (m.nv > 0) {
    NamedState bad = inside;
    bad.name = "a NaN velocity";
    bad.qvel[0] = std::numeric_limits<double>::quiet_NaN();
    states.push_back(bad);
  }
  return states;
}

void set_state(lever::Data& d, const NamedState& s) {
  d.qpos = s.qpos;
  d.qvel = s.qvel;
  d.ctrl = s.ctrl;
}

}  // namespace

TEST_CASE("the counting allocator sees operator new and Eigen's allocations", "[alloc]") {
  const Allocations a = count([] {
    std::vector<double> v(100, 1.0);
    REQUIRE(v.size() == 100);
  });
  CHECK(a.news >= 1);
#ifdef LEVER_ALLOC_COUNTS_MALLOC
  const Allocations b = count([] {
    Eigen::VectorXd x = Eigen::VectorXd::Ones(100);
    REQUIRE(x.sum() == 100.0);
  });
  CHECK(b.mallocs >= 1);
#else
  WARN("malloc is not counted here (sanitizer or not glibc): Eigen's allocations are invisible");
#endif
}

TEST_CASE(
    "forward, step, step1, step2, inverse, jac_site, place_site, jac_site_from_q, body_poses, "
    "body_kinematics and compute_energy allocate nothing",
    "[alloc]") {
  const std::vector<std::string> files = lever::test::all_model_files();
  REQUIRE(!files.empty());
  for (const std::string& path : files) {
    std::string how;
    const lever::Model base = load(path, how);
    const std::string model_name = std::filesystem::path(path).filename().string();
    INFO("model " << model_name << " loaded by " << how);
    for (const lever::Integrator integrator :
         {lever::Integrator::kEuler, lever::Integrator::kRK4, lever::Integrator::kImplicit}) {
      lever::Model m = base;
      m.opt.integrator = integrator;
      INFO("integrator " << lever::integrator_name(integrator));
      lever::Data d(m);  // the only allocations allowed
      Eigen::MatrixXd jacp(3, m.nv), jacr(3, m.nv);
      int rows_seen = 0;
      for (const NamedState& s : states_for(m)) {
        INFO("state: " << s.name);
        set_state(d, s);
        Allocations a = count([&] { lever::forward(m, d); });
        rows_seen = std::max(rows_seen, d.nefc);
        CHECK(a.news == 0);
        CHECK(a.mallocs == 0);

        a = count([&] { lever::compute_energy(m, d); });
        CHECK(a.news == 0);
        CHECK(a.mallocs == 0);

        for (int site = 0; site < m.nsite; ++site) {
          a = count([&] { lever::jac_site(m, d, site, jacp, jacr); });
          CHECK(a.news == 0);
          CHECK(a.mallocs == 0);
        }

        // one site's frame from q, each in turn (after the Jacobians: it rewrites site frames)
        for (int site = 0; site < m.nsite; ++site) {
          a = count([&] { lever::place_site(m, d, site); });
          CHECK(a.news == 0);
          CHECK(a.mallocs == 0);
          a = count([&] { lever::jac_site_from_q(m, d, site, jacp, jacr); });
          CHECK(a.news == 0);
          CHECK(a.mallocs == 0);
        }
        // the lean kinematics (they rewrite frames forward() wrote)
        for (void (*lean)(const lever::Model&, lever::Data&) :
             {lever::body_poses, lever::body_kinematics}) {
          a = count([&] { lean(m, d); });
          CHECK(a.news == 0);
          CHECK(a.mallocs == 0);
        }

        set_state(d, s);
        d.qacc.setConstant(0.5);
        a = count([&] { lever::inverse(m, d); });
        CHECK(a.news == 0);
        CHECK(a.mallocs == 0);

        set_state(d, s);
        a = count([&] {
          for (int k = 0; k < 5; ++k) lever::step(m, d);
        });
        CHECK(a.news == 0);
        CHECK(a.mallocs == 0);

        // the split step, with a controller between the halves (MuJoCo's mj_step1/mj_step2)
        set_state(d, s);
        a = count([&] {
          for (int k = 0; k < 5; ++k) {
            lever::step1(m, d);
            d.qfrc_applied = d.qfrc_bias;  // same size: Eigen copies without allocating
            lever::step2(m, d);
          }
        });
        CHECK(a.news == 0);
        CHECK(a.mallocs == 0);
        d.qfrc_applied.setZero();
      }
      // the limited models must really have exercised the limit rows
      bool limited = false;
      for (int j = 0; j < m.njnt; ++j) limited = limited || m.jnt_limited[j];
      if (limited) CHECK(rows_seen >= 1);
    }
  }
}

TEST_CASE("BatchRunner allocates nothing on one thread", "[alloc]") {
  for (const std::string& path : lever::test::all_model_files()) {
    std::string how;
    const lever::Model m = load(path, how);
    INFO("model " << path << " loaded by " << how);
    const std::vector<NamedState> states = states_for(m);
    const auto n = static_cast<Eigen::Index>(states.size());
    Eigen::MatrixXd qpos(m.nq, n), qvel(m.nv, n), ctrl(m.nu, n), qacc(m.nv, n);
    for (Eigen::Index k = 0; k < n; ++k) {
      qpos.col(k) = states[static_cast<std::size_t>(k)].qpos;
      qvel.col(k) = states[static_cast<std::size_t>(k)].qvel;
      ctrl.col(k) = states[static_cast<std::size_t>(k)].ctrl;
    }
    const Eigen::MatrixXd no_ctrl(m.nu, 0);
    lever::BatchRunner runner(m, 1);
    Allocations a = count([&] { runner.forward(qpos, qvel, ctrl, qacc); });
    CHECK(a.news == 0);
    CHECK(a.mallocs == 0);
    a = count([&] { runner.forward(qpos, qvel, no_ctrl, qacc); });
    CHECK(a.news == 0);
    CHECK(a.mallocs == 0);
    a = count([&] { runner.step(qpos, qvel, ctrl, 3); });
    CHECK(a.news == 0);
    CHECK(a.mallocs == 0);
  }
}

TEST_CASE("BatchRunner on two threads allocates nothing per batch: its workers are kept",
          "[alloc]") {
  const lever::Model m = lever::mjcf::load_file(lever::test::model_path("models/panda7.xml"));
  const std::vector<NamedState> states = states_for(m);
  const auto n = static_cast<Eigen::Index>(states.size());
  Eigen::MatrixXd qpos(m.nq, n), qvel(m.nv, n), ctrl(m.nu, n), qacc(m.nv, n);
  for (Eigen::Index k = 0; k < n; ++k) {
    qpos.col(k) = states[static_cast<std::size_t>(k)].qpos;
    qvel.col(k) = states[static_cast<std::size_t>(k)].qvel;
    ctrl.col(k) = states[static_cast<std::size_t>(k)].ctrl;
  }
  REQUIRE(n >= 2);  // both threads get states
  lever::BatchRunner runner(m, 2);
  for (int call = 0; call < 3; ++call) {  // the counters are atomic: the worker's calls count too
    Allocations a = count([&] { runner.forward(qpos, qvel, ctrl, qacc); });
    CHECK(a.news == 0);
    CHECK(a.mallocs == 0);
    a = count([&] { runner.step(qpos, qvel, ctrl, 2); });
    CHECK(a.news == 0);
    CHECK(a.mallocs == 0);
  }
}

TEST_CASE("rnea_derivatives, forward_derivatives, step_derivatives and regressor allocate nothing",
          "[alloc][derivatives]") {
  // every model, and the fixed tendons', friction loss's and equality constraints' rows, the site
  // actuators (with and without a reference site), the muscles and activation dynamics and the
  // spatial tendons, straight and wrapping (which the derivatives take too)
  std::vector<std::string> files = lever::test::all_model_files();
  for (const char* file :
       {"tests/models/constraints/tendons.xml", "tests/models/constraints/friction_loss.xml",
        "tests/models/constraints/equality.xml", "tests/derivatives/site_actuators.xml",
        "tests/models/actuators/muscles.xml", "tests/derivatives/refsite_actuators.xml",
        "tests/derivatives/spatial_tendons.xml", "tests/models/constraints/spatial_tendons.xml"}) {
    files.push_back(lever::test::model_path(file));
  }
  for (const std::string& path : files) {
    std::string how;
    const lever::Model base = load(path, how);
    // what the regressor covers: hinges and slides, no tendons
    const bool hinges_and_slides = base.nq == base.nv && base.ntendon == 0;
    INFO("model " << std::filesystem::path(path).filename().string() << " loaded by " << how);
    for (const lever::Integrator integrator :
         {lever::Integrator::kEuler, lever::Integrator::kRK4, lever::Integrator::kImplicit}) {
      lever::Model m = base;
      m.opt.integrator = integrator;
      INFO("integrator " << lever::integrator_name(integrator));
      lever::Data d(m);
      lever::Derivatives deriv(m);  // sized once, with Data
      const Eigen::VectorXd qacc = Eigen::VectorXd::Constant(m.nv, 0.5);
      Eigen::MatrixXd Y(m.nv, hinges_and_slides ? lever::regressor_columns(m) : 0);
      std::vector<NamedState> states = states_for(m);
      if (m.contacts_possible) {  // and at rest after a second from qpos0: contacts pushing
        lever::Data settle(m);
        for (int k = 0; k < 500; ++k) lever::step(m, settle);
        states.push_back({"settled from qpos0", settle.qpos, settle.qvel, settle.ctrl});
      }
      for (const NamedState& s : states) {
        INFO("state: " << s.name);
        set_state(d, s);
        Allocations a = count([&] {
          lever::kinematics(m, d);
          lever::rnea_derivatives(m, d, qacc, deriv);
          lever::forward_derivatives(m, d, deriv);
          lever::step_derivatives(m, d, deriv);
          if (hinges_and_slides) lever::regressor(m, d, qacc, Y);
        });
        if (s.name == "settled from qpos0") CHECK(d.ncon > 0);
        CHECK(a.news == 0);
        CHECK(a.mallocs == 0);
      }
    }
  }
}

#ifdef LEVER_ALLOC_HAVE_MUJOCO
// collision() is not part of forward() yet: it is checked on its own, on the contact
// scenes of tests/diff (MuJoCo's compiled model: mjcf_lite does not read contact attributes yet)
TEST_CASE("the elliptic cones' Newton solver allocates nothing", "[alloc]") {
  for (const char* file : {"models/box_drop.xml", "models/gripper.xml"}) {
    INFO(file);
    std::string how;
    lever::Model m = load(lever::test::model_path(file), how);
    m.opt.cone = lever::Cone::kElliptic;
    lever::Data d(m);
    if (m.nkey > 0) lever::reset_keyframe(m, d, 0);
    int elliptic_rows = 0;
    for (int k = 0; k < 500; ++k) {  // one second: the box falls or rests in contact
      Allocations a = count([&] { lever::step(m, d); });
      CHECK(a.news == 0);
      CHECK(a.mallocs == 0);
      a = count([&] { lever::inverse(m, d); });
      CHECK(a.news == 0);
      CHECK(a.mallocs == 0);
      for (int r = 0; r < d.nefc; ++r)
        elliptic_rows += d.efc_type[r] == lever::ConstraintType::kContactElliptic;
    }
    CHECK(elliptic_rows > 0);
  }
}

TEST_CASE("MuJoCo's CG and PGS solvers allocate nothing, with every integrator and both cones",
          "[alloc]") {
  std::string how;
  const lever::Model base = load(lever::test::model_path("models/box_drop.xml"), how);
  for (const lever::Solver solver : {lever::Solver::kCG, lever::Solver::kPGS})
  for (const lever::Cone cone : {lever::Cone::kPyramidal, lever::Cone::kElliptic}) {
    for (const lever::Integrator integrator :
         {lever::Integrator::kEuler, lever::Integrator::kRK4, lever::Integrator::kImplicit}) {
      lever::Model m = base;
      m.opt.cone = cone;
      m.opt.integrator = integrator;
      m.opt.solver = solver;  // MuJoCo's default tolerance: the solver iterates
      lever::Data d(m);
      if (m.nkey > 0) lever::reset_keyframe(m, d, 0);
      int iterations = 0;
      for (int k = 0; k < 250; ++k) {  // half a second: the box lands
        const Allocations a = count([&] { lever::step(m, d); });
        CHECK(a.news == 0);
        CHECK(a.mallocs == 0);
        iterations += d.solver_iter;
      }
      CHECK(iterations > 0);
    }
  }
}

namespace {

// `steps` steps of the model in `file` under each integrator (a fresh Data each, every control at
// `ctrl`), each step counted: none may allocate. after_step(m, d) runs after each step (more
// calls to count, tallies); after_run(m, d) after each integrator's run.
template <typename AfterStep, typename AfterRun>
void check_steps_allocate_nothing(const char* file, double ctrl, int steps, AfterStep after_step,
                                  AfterRun after_run) {
  INFO(file);
  std::string how;
  const lever::Model base = load(lever::test::model_path(file), how);
  for (const lever::Integrator integrator :
       {lever::Integrator::kEuler, lever::Integrator::kRK4, lever::Integrator::kImplicit}) {
    lever::Model m = base;
    m.opt.integrator = integrator;
    lever::Data d(m);
    d.ctrl.setConstant(ctrl);
    for (int k = 0; k < steps; ++k) {
      const Allocations a = count([&] { lever::step(m, d); });
      CHECK(a.news == 0);
      CHECK(a.mallocs == 0);
      after_step(m, d);
    }
    after_run(m, d);
  }
}

}  // namespace

TEST_CASE("equality constraints and friction loss allocate nothing", "[alloc]") {
  // spatial_tendons.xml: a tendon coupling and tendon friction loss, along wrapped paths
  for (const char* file :
       {"tests/models/constraints/equality.xml", "tests/models/constraints/friction_loss.xml",
        "tests/models/constraints/spatial_tendons.xml"}) {
    int rows = 0;
    check_steps_allocate_nothing(
        file, 1.0, 200,
        [&](const lever::Model& m, lever::Data& d) {
          const Allocations a = count([&] { lever::inverse(m, d); });
          CHECK(a.news == 0);
          CHECK(a.mallocs == 0);
          rows += d.ne + d.nf;
        },
        [&](const lever::Model&, const lever::Data&) {
          CHECK(rows > 0);
          rows = 0;
        });
  }
}

TEST_CASE("transmissions, muscles and activations allocate nothing", "[alloc]") {
  // adhesion.xml: body transmissions over contacts with rows and in the gap
  for (const char* file :
       {"tests/models/actuators/transmissions.xml", "tests/models/actuators/muscles.xml",
        "tests/models/actuators/shortcuts.xml", "tests/models/actuators/adhesion.xml"}) {
    check_steps_allocate_nothing(
        file, 0.5, 100, [](const lever::Model&, const lever::Data&) {},
        [](const lever::Model& m, const lever::Data& d) {
          CHECK(d.act.size() == m.na);
          if (m.na > 0) CHECK(d.act.cwiseAbs().maxCoeff() > 0);  // the activations moved
        });
  }
}

TEST_CASE("collision allocates nothing", "[alloc]") {
  // the scenes' cylinders and ellipsoids, and the Menagerie's Panda's meshes, run MPR
  // (with multiccd too)
  const std::string scenes = lever::test::source_dir() + "/tests/diff/contact_scenes/";
  const std::string panda =
      lever::test::robots_dir() + "/menagerie-2022/franka_emika_panda/panda_nohand.xml";
  for (const std::string& file : {scenes + "arm_and_objects.xml", scenes + "capsule_stack.xml",
                                  scenes + "free_objects.xml", panda}) {
    INFO(file);
    const auto mj = lever::test::mujoco_load(file);
    lever::Model m = lever::test::from_mujoco(mj.get());
    if (file == scenes + "free_objects.xml") m.opt.enableflags |= lever::kEnableMulticcd;
    lever::Data d(m);
    std::mt19937_64 rng(19);
    std::uniform_real_distribution<double> u(file == panda ? -2.5 : -0.15, file == panda ? 2.5 : 0.15);
    int contacts = 0;
    for (int s = 0; s < (file == panda ? 400 : 50); ++s) {
      for (int i = 0; i < m.nq; ++i) d.qpos[i] = m.qpos0[i] + u(rng);
      lever::kinematics(m, d);
      const Allocations a = count([&] { lever::collision(m, d); });
      contacts += d.ncon;
      CHECK(a.news == 0);
      CHECK(a.mallocs == 0);
    }
    CHECK(contacts > 0);
  }
}
#endif
