// BatchRunner: forward(), forward_each() and step() over the columns of a state matrix, one Data
// per thread, worker threads kept alive between calls.
#include <lever/batch.hpp>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <mutex>
#include <string>
#include <thread>

#include <lever/error.hpp>
#include <lever/forward.hpp>

namespace lever {

namespace {

void check_rows(const char* what, Eigen::Index rows, int expected) {
  if (rows != expected) {
    throw StateError(std::string("BatchRunner: ") + what + " has " + std::to_string(rows) +
                     " rows; the model needs " + std::to_string(expected) + ".");
  }
}

void check_cols(const char* what, Eigen::Index cols, Eigen::Index expected) {
  if (cols != expected) {
    throw StateError(std::string("BatchRunner: ") + what + " has " + std::to_string(cols) +
                     " columns; qpos has " + std::to_string(expected) + ".");
  }
}

// The shapes both batch calls read: one column per state, ctrl empty (zero controls) or one
// column per state.
void check_states(const Model& m, const Eigen::Ref<const Eigen::MatrixXd>& qpos,
                  const Eigen::Ref<const Eigen::MatrixXd>& qvel,
                  const Eigen::Ref<const Eigen::MatrixXd>& ctrl) {
  check_rows("qpos", qpos.rows(), m.nq);
  check_rows("qvel", qvel.rows(), m.nv);
  check_rows("ctrl", ctrl.rows(), m.nu);
  check_cols("qvel", qvel.cols(), qpos.cols());
  if (ctrl.cols() != 0) check_cols("ctrl", ctrl.cols(), qpos.cols());
}

// State k of the batch into d (its controls stay zero when the batch has none).
void load_state(Data& d, const Eigen::Ref<const Eigen::MatrixXd>& qpos,
                const Eigen::Ref<const Eigen::MatrixXd>& qvel,
                const Eigen::Ref<const Eigen::MatrixXd>& ctrl, Eigen::Index k) {
  d.qpos = qpos.col(k);
  d.qvel = qvel.col(k);
  if (ctrl.cols() != 0) d.ctrl = ctrl.col(k);
}

}  // namespace

// threads - 1 workers kept asleep between batches. A batch is a job, job(t) for thread t, handed
// over under the mutex with a new generation number; the calling thread runs job(0) and waits
// until `running` is back to zero. The job is a function pointer and a context pointer, so that
// handing it over allocates nothing.
struct detail::BatchPool {
  std::mutex mutex;
  std::condition_variable wake;      // a new generation, or stopping
  std::condition_variable finished;  // running reached zero
  std::uint64_t generation = 0;
  int running = 0;  // workers still busy with the current generation
  bool stopping = false;
  void (*call)(void* job, int t) = nullptr;
  void* job = nullptr;
  std::vector<std::exception_ptr> errors;  // one per thread, sized once
  std::vector<std::thread> workers;

  explicit BatchPool(int threads) : errors(static_cast<std::size_t>(threads)) {
    workers.reserve(static_cast<std::size_t>(threads - 1));
    try {
      for (int t = 1; t < threads; ++t) workers.emplace_back([this, t] { serve(t); });
    } catch (...) {
      stop();  // a thread could not start: leave no thread behind
      throw;
    }
  }
  ~BatchPool() { stop(); }

  void stop() {
    {
      std::lock_guard<std::mutex> lock(mutex);
      stopping = true;
    }
    wake.notify_all();
    for (std::thread& worker : workers) worker.join();
    workers.clear();
  }

  // Worker t: sleep until a generation it has not run, run its part, report, sleep again.
  void serve(int t) {
    std::uint64_t seen = 0;
    for (;;) {
      std::unique_lock<std::mutex> lock(mutex);
      wake.wait(lock, [&] { return stopping || generation != seen; });
      if (stopping) return;
      seen = generation;
      lock.unlock();
      try {
        call(job, t);
      } catch (...) {
        errors[static_cast<std::size_t>(t)] = std::current_exception();
      }
      lock.lock();
      if (--running == 0) finished.notify_one();
    }
  }

  // job(t) on every thread t (t = 0 here); returns when all are done, rethrowing the first
  // exception (thread 0's first, then by thread).
  template <class Job>
  void run(Job& work) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      call = [](void* j, int t) { (*static_cast<Job*>(j))(t); };
      job = &work;
      running = static_cast<int>(workers.size());
      ++generation;
    }
    wake.notify_all();
    try {
      work(0);
    } catch (...) {
      errors[0] = std::current_exception();
    }
    {
      std::unique_lock<std::mutex> lock(mutex);
      finished.wait(lock, [&] { return running == 0; });
    }
    for (std::exception_ptr& e : errors) {
      if (e) {
        std::exception_ptr first = e;
        for (std::exception_ptr& other : errors) other = nullptr;  // the next batch starts clean
        std::rethrow_exception(first);
      }
    }
  }
};

namespace {

constexpr Eigen::Index kChunksPerThread = 8;

// Run work(data, t, begin, end) over [0, n) in chunks, thread t in its own Data. With one
// thread, or one state, everything runs here (t = 0).
template <class Work>
void run_in_chunks(detail::BatchPool& pool, std::vector<std::unique_ptr<Data>>& data,
                   Eigen::Index n, Work& work) {
  const auto threads = static_cast<Eigen::Index>(data.size());
  if (threads == 1 || n <= 1) {
    work(*data[0], 0, Eigen::Index{0}, n);
    return;
  }
  // The states are handed out in chunks from a shared counter, not in one block per thread: a
  // thread that starts late (a worker waking up) or runs slower (another process on its core)
  // takes fewer chunks, and neither waits long for the other at the end. Each state's result
  // depends on that state alone, so which thread computes it changes nothing.
  const Eigen::Index chunk = std::max<Eigen::Index>(1, n / (threads * kChunksPerThread));
  std::atomic<Eigen::Index> next{0};
  auto take_chunks = [&](int t) {
    Data& d = *data[static_cast<std::size_t>(t)];
    for (;;) {
      const Eigen::Index begin = next.fetch_add(chunk, std::memory_order_relaxed);
      if (begin >= n) return;
      work(d, t, begin, std::min(n, begin + chunk));
    }
  };
  pool.run(take_chunks);
}

}  // namespace

BatchRunner::BatchRunner(const Model& model, int threads) : model_(&model) {
  if (threads < 1) {
    throw StateError("BatchRunner: threads is " + std::to_string(threads) + "; it must be >= 1.");
  }
  data_.reserve(static_cast<std::size_t>(threads));
  for (int t = 0; t < threads; ++t) data_.push_back(std::make_unique<Data>(model));
  pool_ = std::make_unique<detail::BatchPool>(threads);  // last: nothing can throw after it
}

BatchRunner::~BatchRunner() = default;

void BatchRunner::forward(const Eigen::Ref<const Eigen::MatrixXd>& qpos,
                          const Eigen::Ref<const Eigen::MatrixXd>& qvel,
                          const Eigen::Ref<const Eigen::MatrixXd>& ctrl,
                          Eigen::Ref<Eigen::MatrixXd> qacc) {
  check_states(*model_, qpos, qvel, ctrl);  // first, as forward_each would: the same messages
  check_rows("qacc", qacc.rows(), model_->nv);
  check_cols("qacc", qacc.cols(), qpos.cols());
  // one std::function call per state, nothing against forward() (callgrind, one thread: arm2
  // 3964 -> 3954 instructions per state); the lambda holds one pointer, which std::function
  // stores without allocating
  forward_each(qpos, qvel, ctrl,
               [&qacc](const Data& d, Eigen::Index k, int /*thread*/) { qacc.col(k) = d.qacc; });
}

void BatchRunner::forward_each(const Eigen::Ref<const Eigen::MatrixXd>& qpos,
                               const Eigen::Ref<const Eigen::MatrixXd>& qvel,
                               const Eigen::Ref<const Eigen::MatrixXd>& ctrl,
                               const Collect& collect) {
  const Model& m = *model_;
  check_states(m, qpos, qvel, ctrl);

  auto work = [&](Data& d, int t, Eigen::Index begin, Eigen::Index end) {
    if (ctrl.cols() == 0) d.ctrl.setZero();
    for (Eigen::Index k = begin; k < end; ++k) {
      load_state(d, qpos, qvel, ctrl, k);
      lever::forward(m, d);
      collect(d, k, t);
    }
  };
  run_in_chunks(*pool_, data_, qpos.cols(), work);
}

void BatchRunner::step(Eigen::Ref<Eigen::MatrixXd> qpos, Eigen::Ref<Eigen::MatrixXd> qvel,
                       const Eigen::Ref<const Eigen::MatrixXd>& ctrl, int nstep) {
  const Model& m = *model_;
  const Eigen::Index n = qpos.cols();
  check_states(m, qpos, qvel, ctrl);
  if (nstep < 0)
    throw StateError("BatchRunner: nstep is " + std::to_string(nstep) + "; it must be >= 0.");

  auto work = [&](Data& d, int /*thread*/, Eigen::Index begin, Eigen::Index end) {
    if (ctrl.cols() == 0) d.ctrl.setZero();
    for (Eigen::Index k = begin; k < end; ++k) {
      load_state(d, qpos, qvel, ctrl, k);
      for (int s = 0; s < nstep; ++s) lever::step(m, d);
      qpos.col(k) = d.qpos;
      qvel.col(k) = d.qvel;
    }
  };
  run_in_chunks(*pool_, data_, n, work);
}

}  // namespace lever
