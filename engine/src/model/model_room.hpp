// The model room: Model and Data as arrays (the field table expanded, fields.cpp), Data's sizing
// (data.cpp) and the name lookups (model.cpp). What other rooms take from it: the entry check every
// public function runs at its door, argument-size checks, and warnings recorded into Data.
#pragma once

#include <lever/data.hpp>
#include <lever/fields.hpp>
#include <lever/model.hpp>

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

/// Lays a Data's arrays out in its block, one after the other, each starting on a cache line. One
/// walk over the arrays serves four purposes: measuring the block (no block yet), pointing every
/// view at its place and giving each element its first value (a new Data: the block is zeroed
/// first), pointing the views only (a copied block), and detaching them (a Data moved from).
class ArrayPlacer {
 public:
  enum class Mode { kMeasure, kConstruct, kRebase, kDetach };
  ArrayPlacer(unsigned char* block, Mode mode) : block_(block), mode_(mode) {}

  template <class T>
  void operator()(ArenaArray<T>& array, std::size_t n) {
    // the block is copied as bytes and never destroyed element by element
    static_assert(std::is_trivially_destructible_v<T>);
    if (mode_ == Mode::kDetach) return array.place(nullptr, 0);
    T* at = reinterpret_cast<T*>(next(n * sizeof(T)));
    if (mode_ == Mode::kMeasure) return;
    // numbers and Eigen's fixed-size types start as the zeroed bytes; a struct with defaults
    // (Contact, RigidInertia) gets them
    if constexpr (!std::is_trivially_default_constructible_v<T> &&
                  !requires { T::RowsAtCompileTime; }) {
      if (mode_ == Mode::kConstruct) std::uninitialized_value_construct_n(at, n);
    }
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

  /// The block's size in bytes, once every array has been laid out.
  std::size_t bytes() const { return offset_; }

 private:
  // the place of the next array, and the offset after it, rounded up to a cache line
  unsigned char* next(std::size_t bytes) {
    unsigned char* at = block_ == nullptr ? nullptr : block_ + offset_;
    offset_ += (bytes + kCacheLine - 1) / kCacheLine * kCacheLine;
    return at;
  }

  unsigned char* block_;
  Mode mode_;
  std::size_t offset_ = 0;
};

/// Lay out the arrays of the field table (fields.cpp); Data's constructor lays out the rest.
void lay_out_table_arrays(Data& data, ArrayPlacer& place);

}  // namespace detail

}  // namespace lever
