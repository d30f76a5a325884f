// BatchRunner: forward() and step() over the columns of a state matrix, one Data per thread.
#include <lever/batch.hpp>

#include <exception>
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

// Run work(data, begin, end) on `threads` contiguous blocks of [0, n): block 0 on the calling
// thread, the others on threads started here. An exception in any block is rethrown here.
template <class Work>
void run_blocks(std::vector<std::unique_ptr<Data>>& data, Eigen::Index n, Work work) {
  const auto threads = static_cast<Eigen::Index>(data.size());
  const Eigen::Index used = n < threads ? (n > 0 ? n : 1) : threads;
  auto block = [&](Eigen::Index t) {  // columns [begin, end) of block t, sizes differing by <= 1
    return std::pair<Eigen::Index, Eigen::Index>{t * n / used, (t + 1) * n / used};
  };
  if (used == 1) {
    work(*data[0], Eigen::Index{0}, n);
    return;
  }
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(used));
  std::vector<std::thread> pool;
  pool.reserve(static_cast<std::size_t>(used - 1));
  for (Eigen::Index t = 1; t < used; ++t) {
    pool.emplace_back([&, t] {
      try {
        const auto [begin, end] = block(t);
        work(*data[static_cast<std::size_t>(t)], begin, end);
      } catch (...) {
        errors[static_cast<std::size_t>(t)] = std::current_exception();
      }
    });
  }
  try {
    const auto [begin, end] = block(0);
    work(*data[0], begin, end);
  } catch (...) {
    errors[0] = std::current_exception();
  }
  for (std::thread& th : pool) th.join();
  for (const std::exception_ptr& e : errors) {
    if (e) std::rethrow_exception(e);
  }
}

}  // namespace

BatchRunner::BatchRunner(const Model& model, int threads) : model_(&model) {
  if (threads < 1) {
    throw StateError("BatchRunner: threads is " + std::to_string(threads) + "; it must be >= 1.");
  }
  data_.reserve(static_cast<std::size_t>(threads));
  for (int t = 0; t < threads; ++t) data_.push_back(std::make_unique<Data>(model));
}

void BatchRunner::forward(const Eigen::Ref<const Eigen::MatrixXd>& qpos,
                          const Eigen::Ref<const Eigen::MatrixXd>& qvel,
                          const Eigen::Ref<const Eigen::MatrixXd>& ctrl,
                          Eigen::Ref<Eigen::MatrixXd> qacc) {
  const Model& m = *model_;
  const Eigen::Index n = qpos.cols();
  check_states(m, qpos, qvel, ctrl);
  check_rows("qacc", qacc.rows(), m.nv);
  check_cols("qacc", qacc.cols(), n);

  run_blocks(data_, n, [&](Data& d, Eigen::Index begin, Eigen::Index end) {
    if (ctrl.cols() == 0) d.ctrl.setZero();
    for (Eigen::Index k = begin; k < end; ++k) {
      load_state(d, qpos, qvel, ctrl, k);
      lever::forward(m, d);
      qacc.col(k) = d.qacc;
    }
  });
}

void BatchRunner::step(Eigen::Ref<Eigen::MatrixXd> qpos, Eigen::Ref<Eigen::MatrixXd> qvel,
                       const Eigen::Ref<const Eigen::MatrixXd>& ctrl, int nstep) {
  const Model& m = *model_;
  const Eigen::Index n = qpos.cols();
  check_states(m, qpos, qvel, ctrl);
  if (nstep < 0)
    throw StateError("BatchRunner: nstep is " + std::to_string(nstep) + "; it must be >= 0.");

  run_blocks(data_, n, [&](Data& d, Eigen::Index begin, Eigen::Index end) {
    if (ctrl.cols() == 0) d.ctrl.setZero();
    for (Eigen::Index k = begin; k < end; ++k) {
      load_state(d, qpos, qvel, ctrl, k);
      for (int s = 0; s < nstep; ++s) lever::step(m, d);
      qpos.col(k) = d.qpos;
      qvel.col(k) = d.qvel;
    }
  });
}

}  // namespace lever
