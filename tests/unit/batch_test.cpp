// BatchRunner's worker pool: the same numbers on any number of threads, call after call on one
// runner, an exception thrown in a worker's block reaching the caller, and forward_each handing
// every state over exactly once.
#include <catch2/catch.hpp>

#include <lever/batch.hpp>
#include <lever/error.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <atomic>
#include <chrono>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <lever/harness/models.hpp>

namespace {

struct States {
  Eigen::MatrixXd qpos, qvel, ctrl;
};

// n random states inside the joint ranges (or +-1 where a joint has none), seeded.
States random_states(const lever::Model& m, Eigen::Index n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  States s{Eigen::MatrixXd(m.nq, n), Eigen::MatrixXd(m.nv, n), Eigen::MatrixXd(m.nu, n)};
  for (Eigen::Index k = 0; k < n; ++k) {
    for (int i = 0; i < m.nq; ++i) s.qpos(i, k) = unit(rng);
    for (int i = 0; i < m.nv; ++i) s.qvel(i, k) = unit(rng);
    for (int i = 0; i < m.nu; ++i) s.ctrl(i, k) = unit(rng);
  }
  return s;
}

// forward() one state at a time in its own Data: what every batch must equal bit for bit.
Eigen::MatrixXd one_by_one(const lever::Model& m, const States& s) {
  lever::Data d(m);
  Eigen::MatrixXd qacc(m.nv, s.qpos.cols());
  for (Eigen::Index k = 0; k < s.qpos.cols(); ++k) {
    d.qpos = s.qpos.col(k);
    d.qvel = s.qvel.col(k);
    d.ctrl = s.ctrl.col(k);
    lever::forward(m, d);
    qacc.col(k) = d.qacc;
  }
  return qacc;
}

}  // namespace

TEST_CASE("one BatchRunner gives the one-state results call after call, on 1 to 3 threads",
          "[batch]") {
  const lever::Model m = lever::mjcf::load_file(lever::test::model_path("models/panda7.xml"));
  for (const int threads : {1, 2, 3}) {
    INFO(threads << " thread(s)");
    lever::BatchRunner runner(m, threads);
    // batch sizes that leave blocks empty (1, 2 < 3 threads), uneven and even
    for (const Eigen::Index n :
         {Eigen::Index{1}, Eigen::Index{2}, Eigen::Index{7}, Eigen::Index{64}}) {
      for (unsigned call = 0; call < 3; ++call) {  // the same workers, woken again
        INFO(n << " states, call " << call);
        const States s = random_states(m, n, static_cast<unsigned>(n) * 10 + call);
        Eigen::MatrixXd qacc(m.nv, n);
        runner.forward(s.qpos, s.qvel, s.ctrl, qacc);
        CHECK(qacc == one_by_one(m, s));  // exactly: the same calls on the same numbers
      }
    }
    // step: every state's trajectory the same as on one thread
    const States s = random_states(m, 9, 7);
    States one = s, many = s;
    lever::BatchRunner single(m, 1);
    single.step(one.qpos, one.qvel, one.ctrl, 4);
    runner.step(many.qpos, many.qvel, many.ctrl, 4);
    CHECK(many.qpos == one.qpos);
    CHECK(many.qvel == one.qvel);
  }
}

TEST_CASE("an exception thrown in a worker reaches the caller, the runner still works", "[batch]") {
  const lever::Model m = lever::mjcf::load_file(lever::test::model_path("models/arm2.xml"));
  lever::BatchRunner runner(m, 2);
  const States s = random_states(m, 10, 3);
  Eigen::MatrixXd qacc(m.nv, 10);

  // thread 1's Data is another model's: forward() throws there, in the worker only. Whether
  // the worker takes a state before the calling thread has taken all ten is the scheduler's
  // choice, so the calling thread pauses a millisecond after each of its states (ten states
  // take microseconds, less than a loaded machine may take to wake the worker), and the call is
  // repeated until the worker has taken one; on an idle machine the first call does
  const lever::Model other = lever::mjcf::load_file(lever::test::model_path("models/arm3.xml"));
  runner.data(1) = lever::Data(other);
  const auto collect_slowly = [&](const lever::Data& data, Eigen::Index k, int thread) {
    qacc.col(k) = data.qacc;
    if (thread == 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  };
  std::string message;
  for (int attempt = 0; attempt < 100 && message.empty(); ++attempt) {
    try {
      runner.forward_each(s.qpos, s.qvel, s.ctrl, collect_slowly);
    } catch (const lever::StateError& e) {
      message = e.what();
    }
  }
  CHECK_THAT(message, Catch::Contains("keep the sizes"));  // its qpos cannot take the state
  // the calling thread went on taking states: every state but the one the worker failed on (if
  // it woke before the calling thread had taken them all) was computed all the same
  const Eigen::MatrixXd expected = one_by_one(m, s);
  const auto computed = [&] {
    int n = 0;
    for (int k = 0; k < 10; ++k) n += qacc.col(k) == expected.col(k);
    return n;
  };
  CHECK(computed() >= 9);

  // repaired, the same runner (the same workers) gives every state again
  runner.data(1) = lever::Data(m);
  qacc.setZero();
  runner.forward(s.qpos, s.qvel, s.ctrl, qacc);
  CHECK(qacc == expected);

  // thrown on the calling thread too: the worker takes every other state before the error comes
  // back. A worker already awake may take all ten before the calling thread takes one (then
  // nothing throws): repeated until the calling thread took a state
  runner.data(0) = lever::Data(other);
  bool thrown = false;
  for (int attempt = 0; attempt < 1000 && !thrown; ++attempt) {
    qacc.setZero();
    try {
      runner.forward(s.qpos, s.qvel, s.ctrl, qacc);
    } catch (const lever::StateError&) {
      thrown = true;
    }
  }
  CHECK(thrown);
  CHECK(computed() == 9);
  runner.data(0) = lever::Data(m);
  runner.forward(s.qpos, s.qvel, s.ctrl, qacc);
  CHECK(qacc == expected);
}

TEST_CASE(
    "forward_each hands every state's Data over once, with forward()'s qacc, on 1 and 2 threads",
    "[batch]") {
  const lever::Model m = lever::mjcf::load_file(lever::test::model_path("models/panda7.xml"));
  const Eigen::Index n = 37;
  const States s = random_states(m, n, 11);
  const Eigen::MatrixXd no_ctrl(m.nu, 0);
  for (const int threads : {1, 2}) {
    INFO(threads << " thread(s)");
    lever::BatchRunner runner(m, threads);
    for (const bool zero_controls : {false, true}) {
      INFO((zero_controls ? "no controls" : "controls"));
      const Eigen::MatrixXd& ctrl = zero_controls ? no_ctrl : s.ctrl;
      Eigen::MatrixXd expected(m.nv, n);
      runner.forward(s.qpos, s.qvel, ctrl, expected);

      // each state's column written by its own call only; the count per state is atomic because
      // two threads may (wrongly) collect the same state at once
      Eigen::MatrixXd collected = Eigen::MatrixXd::Constant(m.nv, n, -1.0);
      std::vector<std::atomic<int>> calls(static_cast<std::size_t>(n));
      std::vector<int> thread_of(static_cast<std::size_t>(n), -1);
      std::atomic<bool> right_data{true};
      runner.forward_each(s.qpos, s.qvel, ctrl, [&](const lever::Data& d, Eigen::Index k, int t) {
        calls[static_cast<std::size_t>(k)].fetch_add(1);
        thread_of[static_cast<std::size_t>(k)] = t;
        if (&d != &runner.data(t)) right_data = false;
        collected.col(k) = d.qacc;
      });
      CHECK(collected == expected);  // exactly: forward() at the same state
      CHECK(right_data);             // the Data handed over is data(thread)
      for (Eigen::Index k = 0; k < n; ++k) {
        INFO("state " << k);
        CHECK(calls[static_cast<std::size_t>(k)].load() == 1);
        CHECK(thread_of[static_cast<std::size_t>(k)] >= 0);
        CHECK(thread_of[static_cast<std::size_t>(k)] < threads);
      }
    }
  }
  // an exception thrown by collect reaches the caller, and the runner still works
  lever::BatchRunner runner(m, 2);
  CHECK_THROWS_WITH(runner.forward_each(s.qpos, s.qvel, s.ctrl,
                                        [](const lever::Data&, Eigen::Index k, int) {
                                          if (k == 5) throw lever::StateError("state 5 refused");
                                        }),
                    Catch::Contains("state 5 refused"));
  Eigen::MatrixXd qacc(m.nv, n);
  runner.forward(s.qpos, s.qvel, s.ctrl, qacc);
  CHECK(qacc == one_by_one(m, s));
  // sizes are checked before any state runs
  CHECK_THROWS_AS(runner.forward_each(s.qpos, s.qvel.leftCols(n - 1), s.ctrl,
                                      [](const lever::Data&, Eigen::Index, int) {}),
                  lever::StateError);
}
