// The model room: Model and Data as arrays (the field table expanded, fields.cpp), Data's sizing
// (data.cpp), Model's block and the name lookups (model.cpp). What other rooms take from it: the entry check every
// public function runs at its door, argument-size checks, and warnings recorded into Data.
#pragma once

#include <lever/data.hpp>
#include <lever/fields.hpp>
#include <lever/model.hpp>

#include <algorithm>
#include <memory>
#include <type_traits>

namespace lever {

/// Record a warning of kind w about index info (MuJoCo's mj_warning).
inline void record_warning(Data& data, Warning w, int info) {
  WarningStat& stat = data.warning[static_cast<int>(w)];
  ++stat.number;
  stat.lastinfo = info;
}

/// The check at the door of every public function. Model and Data are matched where they meet:
/// set_const gives a model a fresh tag, and a Data that passed check_fit against a model keeps its
/// tag. A call then costs a comparison of tags (a Data's arrays keep the sizes they were made with:
/// lever/arena.hpp); only a Data meeting a model (or a model edition) it has not been checked
/// against walks the whole field table. No guard object: nothing to unwind on the hot path.
inline bool checked_before(const Model& model, const Data& data) {
  return model.fit_tag != 0 && data.model_tag == model.fit_tag;
}

/// The entry check of a function that writes data: a Data that fits adopts the model's tag.
inline void check_entry(const Model& model, Data& data, const char* where) {
  if (checked_before(model, data)) return;
  check_fit(model, data, where);  // throws, naming the array that does not fit
  data.model_tag = model.fit_tag;
}

/// The same for functions that only read data (Jacobians, solves).
inline void check_entry(const Model& model, const Data& data, const char* where) {
  if (checked_before(model, data)) return;
  check_fit(model, data, where);
}

/// Throws StateError unless a vector argument has n elements.
void check_argument_size(long size, long n, const char* where, const char* what);

namespace detail {

/// The walk both placers below share: hands out a block's bytes in order, each array starting on
/// a cache line; with no block yet it only counts them.
class BlockCursor {
 public:
  explicit BlockCursor(unsigned char* block) : block_(block) {}
  /// The block's size in bytes, once every array has been laid out.
  std::size_t bytes() const { return offset_; }

 protected:
  // the place of the next array, and the offset after it, rounded up to a cache line
  unsigned char* next(std::size_t bytes) {
    unsigned char* at = block_ == nullptr ? nullptr : block_ + offset_;
    offset_ += (bytes + kCacheLine - 1) / kCacheLine * kCacheLine;
    return at;
  }

  unsigned char* block_;

 private:
  std::size_t offset_ = 0;
};

/// Numbers and Eigen's fixed-size types start as a new block's zeroed bytes; a struct with
/// defaults (Contact, RigidInertia, FramePlacement) gets them.
template <class T>
void give_defaults(T* at, std::size_t n) {
  if constexpr (!std::is_trivially_default_constructible_v<T> &&
                !requires { T::RowsAtCompileTime; }) {
    std::uninitialized_value_construct_n(at, n);
  }
}

/// Lays a Data's arrays out in its block, one after the other, each starting on a cache line. One
/// walk over the arrays serves four purposes: measuring the block (no block yet), pointing every
/// view at its place and giving each element its first value (a new Data: the block is zeroed
/// first), pointing the views only (a copied block), and detaching them (a Data moved from).
class ArrayPlacer : public BlockCursor {
 public:
  enum class Mode { kMeasure, kConstruct, kRebase, kDetach };
  ArrayPlacer(unsigned char* block, Mode mode) : BlockCursor(block), mode_(mode) {}

  template <class T>
  void operator()(ArenaArray<T>& array, std::size_t n) {
    // the block is copied as bytes and never destroyed element by element
    static_assert(std::is_trivially_destructible_v<T>);
    if (mode_ == Mode::kDetach) return array.place(nullptr, 0);
    T* at = reinterpret_cast<T*>(next(n * sizeof(T)));
    if (mode_ == Mode::kMeasure) return;
    if (mode_ == Mode::kConstruct) give_defaults(at, n);
    array.place(at, n);
  }

  template <class Plain>
  void operator()(ArenaMap<Plain>& map, Eigen::Index rows, Eigen::Index cols = 1) {
    if (mode_ == Mode::kDetach) {
      return map.place(nullptr, Plain::RowsAtCompileTime == 1 ? 1 : 0,
                       Plain::ColsAtCompileTime == 1 ? 1 : 0);
    }
    auto* at = reinterpret_cast<typename Plain::Scalar*>(
        next(static_cast<std::size_t>(rows * cols) * sizeof(typename Plain::Scalar)));
    if (mode_ != Mode::kMeasure) map.place(at, rows, cols);
  }

 private:
  Mode mode_;
};

/// Lay out the arrays of the field table (fields.cpp); Data's constructor lays out the rest.
void lay_out_table_arrays(Data& data, ArrayPlacer& place);

/// Lays a Model's arrays out in its block, each starting on a cache line, in four ways: measuring
/// the block its counts need (no block yet), moving every array into a new block (size_model: the
/// new block is zeroed first, each array keeps what it held within its new length, and a struct's
/// new entries get their defaults), pointing the views into a copy of another model's block, and
/// detaching them (a Model moved from). A copy's views keep their lengths, so that a Model whose
/// counts were edited after its last size_model copies as it is (validate names the difference).
class ModelArrayPlacer : public BlockCursor {
 public:
  enum class Mode { kMeasure, kResize, kRebase, kDetach };
  /// kRebase: `from` is the block the views point into now, `block` its copy
  ModelArrayPlacer(unsigned char* block, Mode mode, const unsigned char* from = nullptr)
      : BlockCursor(block), from_(from), mode_(mode) {}

  template <class T>
  void operator()(ArenaArray<T>& array, std::size_t n) {
    // the block is copied as bytes and never destroyed element by element
    static_assert(std::is_trivially_destructible_v<T>);
    switch (mode_) {
      case Mode::kDetach: return array.place(nullptr, 0);
      case Mode::kRebase: return array.place(rebased(array.data()), array.size());
      case Mode::kMeasure: next(n * sizeof(T)); return;
      case Mode::kResize: break;
    }
    T* at = reinterpret_cast<T*>(next(n * sizeof(T)));
    give_defaults(at, n);
    std::copy_n(array.data(), std::min(n, array.size()), at);
    array.place(at, n);
  }

  template <class Plain>
  void operator()(ArenaMap<Plain>& map, Eigen::Index rows, Eigen::Index cols = 1) {
    using Scalar = typename Plain::Scalar;
    switch (mode_) {
      case Mode::kDetach:
        return map.place(nullptr, Plain::RowsAtCompileTime == 1 ? 1 : 0,
                         Plain::ColsAtCompileTime == 1 ? 1 : 0);
      case Mode::kRebase: return map.place(rebased(map.data()), map.rows(), map.cols());
      case Mode::kMeasure: next(static_cast<std::size_t>(rows * cols) * sizeof(Scalar)); return;
      case Mode::kResize: break;
    }
    auto* at = reinterpret_cast<Scalar*>(next(static_cast<std::size_t>(rows * cols) * sizeof(Scalar)));
    Eigen::Map<Plain> moved(at, rows, cols);  // zero: the block was zeroed
    const Eigen::Index keep_rows = std::min(rows, map.rows()), keep_cols = std::min(cols, map.cols());
    if (keep_rows > 0 && keep_cols > 0) {
      moved.topLeftCorner(keep_rows, keep_cols) = map.topLeftCorner(keep_rows, keep_cols);
    }
    map.place(at, rows, cols);
  }

 private:
  template <class T>
  T* rebased(T* at) const {
    if (at == nullptr) return nullptr;
    return reinterpret_cast<T*>(block_ + (reinterpret_cast<const unsigned char*>(at) - from_));
  }

  const unsigned char* from_;
  Mode mode_;
};

/// Lay out a Model's arrays: the field table's (fields.cpp), then the rest (model.cpp).
void lay_out_model_table_arrays(Model& model, ModelArrayPlacer& place);
void lay_out_model(Model& model, ModelArrayPlacer& place);

}  // namespace detail

}  // namespace lever
