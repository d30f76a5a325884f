// lever/arena.hpp: the views a Data's (and a Model's) arrays are, into the one block that holds
// them all.
//
// A Data allocates one block when it is made, as MuJoCo's mj_makeData does, and a Model one when it
// is sized (lever::size_model), as mj_makeModel does: every array starts on a cache line, and the
// block is a whole number of cache lines, so two Data never share one. Each array member is a view
// into the block that reads and writes like the container it replaces:
//   ArenaArray<T>    a std::vector<T> that cannot grow: [i], size(), data(), begin()/end(), for
//   ArenaVector      an Eigen::VectorXd that cannot be resized: every Eigen expression reads it
//   ArenaMatrix      an Eigen::MatrixXd the same way
//   ArenaRowMatrix   a row-major one (efc_J, ten_J, actuator_moment)
// Assigning to a view copies the numbers, as the containers did; assigning numbers of another
// shape throws StateError instead of resizing.
//
// A view is never copied on its own: it would alias the Data (Model) it came from. `auto x = data.qpos`
// does not compile (the copy constructor is private to Data); write the type to copy the numbers,
// `Eigen::VectorXd x = data.qpos` or `std::vector<Motion> v = data.cvel.to_vector()`, or copy the
// whole Data. Beware what Eigen allows implicitly: `const Eigen::VectorXd& x = data.qpos` and a
// function taking `const Eigen::VectorXd&` given data.qpos copy into a temporary (it allocates);
// take `Eigen::Ref<const Eigen::VectorXd>` (or `const ArenaVector&`) to read an array in place.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cstddef>
#include <new>
#include <string>
#include <type_traits>
#include <vector>

#include <lever/error.hpp>

namespace lever {

/// Every array of a Data's (Model's) block starts on a cache line, and the block ends on one.
inline constexpr std::size_t kCacheLine = 64;

struct DataFields;
struct DataWorkspace;
struct ModelFields;

namespace detail {
[[noreturn]] void throw_arena_shape(long rows, long cols, long other_rows, long other_cols);
}  // namespace detail

/// A std::vector<T> that cannot grow: `size()` elements of a Data's (Model's) block.
template <class T>
class ArenaArray {
 public:
  using value_type = T;
  using iterator = T*;
  using const_iterator = const T*;

  ArenaArray() = default;
  /// Copies the numbers; the two must have the same size.
  ArenaArray& operator=(const ArenaArray& other) {
    if (&other != this) assign_from(other.data(), other.size());
    return *this;
  }
  ArenaArray& operator=(const std::vector<T>& other) {
    assign_from(other.data(), other.size());
    return *this;
  }
  /// A copy of the elements in a std::vector (allocates).
  std::vector<T> to_vector() const { return std::vector<T>(begin(), end()); }

  T& operator[](std::size_t i) { return data_[i]; }
  const T& operator[](std::size_t i) const { return data_[i]; }
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  T* data() { return data_; }
  const T* data() const { return data_; }
  T* begin() { return data_; }
  T* end() { return data_ + size_; }
  const T* begin() const { return data_; }
  const T* end() const { return data_ + size_; }
  T& front() { return data_[0]; }
  T& back() { return data_[size_ - 1]; }
  const T& front() const { return data_[0]; }
  const T& back() const { return data_[size_ - 1]; }

  /// Point the view at n elements (the layout only).
  void place(T* at, std::size_t n) {
    data_ = at;
    size_ = n;
  }

 private:
  // Only a Data or a Model copies its views (pointing them at its own block right after).
  friend struct DataFields;
  friend struct DataWorkspace;
  friend struct ModelFields;
  ArenaArray(const ArenaArray&) = default;

  void assign_from(const T* from, std::size_t n) {
    if (n != size_) {
      detail::throw_arena_shape(static_cast<long>(size_), 1, static_cast<long>(n), 1);
    }
    std::copy(from, from + n, data_);
  }

  T* data_ = nullptr;
  std::size_t size_ = 0;
};

/// Whether two arrays hold the same elements (a view against a view or a std::vector).
template <class T>
bool operator==(const ArenaArray<T>& a, const ArenaArray<T>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end());
}
template <class T>
bool operator==(const ArenaArray<T>& a, const std::vector<T>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end());
}

/// An Eigen vector or matrix of a Data's (Model's) block: an Eigen::Map that cannot be resized.
template <class Plain>
class ArenaMap : public Eigen::Map<Plain, Eigen::AlignedMax> {
  using Base = Eigen::Map<Plain, Eigen::AlignedMax>;

 public:
  ArenaMap()
      : Base(nullptr, Plain::RowsAtCompileTime == 1 ? 1 : 0,
             Plain::ColsAtCompileTime == 1 ? 1 : 0) {}
  /// Copies the numbers; the shapes must match (an assignment never resizes a Data's array).
  ArenaMap& operator=(const ArenaMap& other) {
    if (&other != this) assign(other);
    return *this;
  }
  template <class Other>
  ArenaMap& operator=(const Eigen::DenseBase<Other>& other) {
    assign(other.derived());
    return *this;
  }
  template <class Other>
  ArenaMap& operator=(const Eigen::EigenBase<Other>& other) {
    assign(other.derived());
    return *this;
  }

  /// Point the view at rows x cols numbers (the layout only).
  void place(typename Plain::Scalar* at, Eigen::Index rows, Eigen::Index cols) {
    new (static_cast<Base*>(this)) Base(at, rows, cols);
  }

  /// A view never changes its size (Eigen's Map::resize would silently do nothing): a Model's
  /// arrays change size with its counts (lever::size_model), a Data's never.
  template <class... Sizes>
  void resize(Sizes...) = delete;

 private:
  // Only a Data or a Model copies its views (pointing them at its own block right after).
  friend struct DataFields;
  friend struct DataWorkspace;
  friend struct ModelFields;
  ArenaMap(const ArenaMap& other) : Base(other) {}

  template <class Other>
  void assign(const Other& other) {
    if (other.rows() != this->rows() || other.cols() != this->cols()) {
      detail::throw_arena_shape(this->rows(), this->cols(), other.rows(), other.cols());
    }
    Base::operator=(other);
  }
};

using ArenaVector = ArenaMap<Eigen::VectorXd>;
using ArenaMatrix = ArenaMap<Eigen::MatrixXd>;
using ArenaRowMatrix =
    ArenaMap<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>;

/// The block of memory behind a Data's (Model's) arrays: 64-byte aligned, its size a multiple of
/// 64 bytes.
class ArenaBlock {
 public:
  ArenaBlock() = default;
  explicit ArenaBlock(std::size_t bytes)
      : bytes_(bytes),
        data_(bytes == 0 ? nullptr
                         : static_cast<unsigned char*>(
                               ::operator new (bytes, std::align_val_t{kCacheLine}))) {}
  ArenaBlock(const ArenaBlock&) = delete;
  ArenaBlock& operator=(const ArenaBlock&) = delete;
  ArenaBlock(ArenaBlock&& other) noexcept : bytes_(other.bytes_), data_(other.data_) {
    other.bytes_ = 0;
    other.data_ = nullptr;
  }
  ArenaBlock& operator=(ArenaBlock&& other) noexcept {
    if (&other != this) {
      release();
      bytes_ = other.bytes_;
      data_ = other.data_;
      other.bytes_ = 0;
      other.data_ = nullptr;
    }
    return *this;
  }
  ~ArenaBlock() { release(); }

  unsigned char* data() const { return data_; }
  std::size_t bytes() const { return bytes_; }

 private:
  void release() {
    if (data_ != nullptr) ::operator delete (data_, std::align_val_t{kCacheLine});
    data_ = nullptr;
  }
  std::size_t bytes_ = 0;
  unsigned char* data_ = nullptr;
};

}  // namespace lever
