// lever/batch.hpp: many independent states at once, one const Model, one Data per thread.
//
// A batch is a set of states stored as matrix columns: qpos is nq x N, qvel is nv x N, ctrl is
// nu x N (or nu x 0: no control), so state k is column k and its numbers are contiguous
// (Eigen's default column-major order). The calling thread and the runner's worker threads
// (threads() - 1 of them, started by the constructor and kept until the destructor) take the
// columns in chunks from a shared counter, so a thread that starts late or runs slower takes
// fewer. A call returns when every thread is done; an exception thrown in a thread stops that
// thread (the others go on taking the remaining states) and reaches the caller once all are done
// (the calling thread's first, else the lowest worker's).
//
// Cost: per state, exactly what forward() or step() costs on its own (nothing is allocated: the
// Data of each thread was built by the constructor). Per call with threads() > 1, waking the
// workers and waiting for them (a few microseconds), so keep the runner and give each call many
// states. The results do not depend on the number of threads: lever keeps no warm start between
// states.
//
//   lever::BatchRunner runner(model, 2);
//   Eigen::MatrixXd qpos(model.nq, n), qvel(model.nv, n), ctrl(model.nu, n), qacc(model.nv, n);
//   ...  // fill the states
//   runner.forward(qpos, qvel, ctrl, qacc);  // qacc.col(k) = forward() at state k
//   runner.step(qpos, qvel, ctrl, 10);       // every state advanced by 10 steps, in place
//
// forward() keeps qacc only; forward_each() hands the caller the whole Data after forward() at
// each state, on the thread that computed it, to take whatever it needs (site_xpos for a
// workspace map, qfrc_bias and M for an identification sweep): the Python binding's
// BatchRunner.forward(fields=...) is built on it.
//
//   Eigen::MatrixXd tips(3, n);
//   runner.forward_each(qpos, qvel, ctrl, [&](const lever::Data& d, Eigen::Index k, int) {
//     tips.col(k) = d.site_xpos[0];  // column k is written by this call alone
//   });
#pragma once

#include <Eigen/Core>

#include <functional>
#include <memory>
#include <vector>

#include <lever/data.hpp>
#include <lever/model.hpp>

namespace lever {

namespace detail {
struct BatchPool;  // the worker threads and what they wait on (batch.cpp)
}

class BatchRunner {
 public:
  /// One Data per thread and threads - 1 worker threads, built here (the only allocations the
  /// runner makes). The model must outlive the runner and stay unchanged while it is used.
  /// Throws StateError if threads < 1.
  explicit BatchRunner(const Model& model, int threads = 1);
  ~BatchRunner();                            // stops and joins the workers
  BatchRunner(const BatchRunner&) = delete;  // the workers hold this runner's address
  BatchRunner& operator=(const BatchRunner&) = delete;

  int threads() const { return static_cast<int>(data_.size()); }
  const Model& model() const { return *model_; }

  /// The Data thread t works in (t = 0 is the calling thread): set qfrc_applied in every thread's
  /// Data to apply a force to every state (which thread computes which state is decided while
  /// the call runs), or read its warnings after a call.
  Data& data(int t) { return *data_.at(static_cast<std::size_t>(t)); }

  /// qacc.col(k) = data.qacc after forward() at state k (qpos.col(k), qvel.col(k), ctrl.col(k)).
  /// ctrl may have no columns: every control is zero then. Throws StateError on a size mismatch.
  void forward(const Eigen::Ref<const Eigen::MatrixXd>& qpos,
               const Eigen::Ref<const Eigen::MatrixXd>& qvel,
               const Eigen::Ref<const Eigen::MatrixXd>& ctrl, Eigen::Ref<Eigen::MatrixXd> qacc);

  /// What forward_each() hands over for each state: the Data that forward() just ran in, the
  /// state's index k (its column in qpos), and the thread t that ran it (the Data is data(t)).
  using Collect = std::function<void(const Data& data, Eigen::Index state, int thread)>;

  /// forward() at every state k (qpos.col(k), qvel.col(k), ctrl.col(k); ctrl may have no
  /// columns: zero controls), then collect(data(t), k, t) on the thread t that computed it,
  /// before that thread moves on to its next state: take what is needed from the Data there.
  /// collect is called once per state, and concurrently from different threads for different
  /// states (in no set order), so it must be safe to call so: writing into column k of a
  /// preallocated output is; appending to a shared container is not. `thread` lets a caller keep
  /// per-thread scratch (views of data(t) resolved once, accumulators) without locks. An
  /// exception thrown by collect stops its thread as forward()'s own would (see the top of this
  /// file). Nothing is allocated per state. Throws StateError on a size mismatch.
  void forward_each(const Eigen::Ref<const Eigen::MatrixXd>& qpos,
                    const Eigen::Ref<const Eigen::MatrixXd>& qvel,
                    const Eigen::Ref<const Eigen::MatrixXd>& ctrl, const Collect& collect);

  /// Advance every state by `nstep` calls of step() (the model's integrator), in place. Controls
  /// are held constant over the steps. A state that step() resets (NaN or huge values) comes back
  /// reset, as from step(). Throws StateError on a size mismatch or nstep < 0.
  void step(Eigen::Ref<Eigen::MatrixXd> qpos, Eigen::Ref<Eigen::MatrixXd> qvel,
            const Eigen::Ref<const Eigen::MatrixXd>& ctrl, int nstep = 1);

 private:
  const Model* model_;
  std::vector<std::unique_ptr<Data>> data_;  // one per thread, each its own allocation
  std::unique_ptr<detail::BatchPool> pool_;  // the worker threads
};

}  // namespace lever
