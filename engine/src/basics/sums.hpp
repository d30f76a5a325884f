// MuJoCo 2.2.2's orders of summation, written once: a sum's last bit depends on the order its
// terms are added in, so a product that lever shares with MuJoCo adds its terms in MuJoCo's order.
// mju_dot (and mju_mulMatVec, one mju_dot per row) keeps four running sums over the groups of four
// and adds the last one to three numbers after them; mju_dotSparse, on a row MuJoCo holds sparse,
// adds the stored entries one after another. (Part of the basics room: basics.hpp includes it.)
#pragma once

#include <Eigen/Core>

namespace lever {

namespace detail {

// out[k] = a_k . x for Count rows a_k (`stride` apart) that share [lo, end) of n, each summed as
// dot_as_mujoco says: four running sums over the groups of four from lo's to the last whole one,
// then Tail (0 to 3) numbers past it. The rows go through the groups together (x read once for
// all of them), each row's running sums held as two pairs, (s0, s1) and (s2, s3), joined as
// (s0 + s2) + (s1 + s3): MuJoCo's sums, in its order. Count and Tail are template arguments so
// that the loops unroll.
template <int Tail, int Count>
void rows_dot_together(const double* a, Eigen::Index stride, const double* x, int groups_begin,
                       int groups_end, int tail_begin, double* out) {
  using Pair = Eigen::Array2d;
  Pair low[Count], high[Count];
  for (int k = 0; k < Count; ++k) low[k] = high[k] = Pair::Zero();
  for (int j = groups_begin; j < groups_end; j += 4) {
    const Pair x_low = Pair::Map(x + j), x_high = Pair::Map(x + j + 2);
    for (int k = 0; k < Count; ++k) {
      const double* ak = a + k * stride + j;
      low[k] += Pair::Map(ak) * x_low;
      high[k] += Pair::Map(ak + 2) * x_high;
    }
  }
  const double* t = x + tail_begin;
  for (int k = 0; k < Count; ++k) {
    const Pair joined = low[k] + high[k];  // (s0 + s2, s1 + s3)
    double sum = joined[0] + joined[1];
    if constexpr (Tail > 0) {
      const double* at = a + k * stride + tail_begin;
      double tail = at[0] * t[0];
      if constexpr (Tail > 1) tail += at[1] * t[1];
      if constexpr (Tail > 2) tail += at[2] * t[2];
      sum += tail;
    }
    out[k] = sum;
  }
}

// rows_dot_together for any number of rows, four at a time (groups [begin, end), the tail from
// `tail`).
template <int Tail>
void rows_dot(const double* a, Eigen::Index stride, int count, const double* x, int begin, int end,
              int tail, double* out) {
  for (; count >= 4; count -= 4, a += 4 * stride, out += 4) {
    rows_dot_together<Tail, 4>(a, stride, x, begin, end, tail, out);
  }
  switch (count) {
    case 1: return rows_dot_together<Tail, 1>(a, stride, x, begin, end, tail, out);
    case 2: return rows_dot_together<Tail, 2>(a, stride, x, begin, end, tail, out);
    case 3: return rows_dot_together<Tail, 3>(a, stride, x, begin, end, tail, out);
    default: return;
  }
}

}  // namespace detail

/// dot_as_mujoco for `count` rows of a (`stride` apart) at once, the bounds found once: out[k] =
/// a_k . x over [lo, end) of n.
inline void rows_dot_as_mujoco(const double* a, Eigen::Index stride, int count, const double* x,
                               int lo, int end, int n, double* out) {
  const int whole = n & ~3;  // n, lo >= 0
  const int groups_begin = lo & ~3, groups_end = end < whole ? end : whole;
  const int tail_begin = lo > whole ? lo : whole;  // past the last whole group: in order
  using detail::rows_dot;
  switch (end > tail_begin ? end - tail_begin : 0) {
    case 0: return rows_dot<0>(a, stride, count, x, groups_begin, groups_end, tail_begin, out);
    case 1: return rows_dot<1>(a, stride, count, x, groups_begin, groups_end, tail_begin, out);
    case 2: return rows_dot<2>(a, stride, count, x, groups_begin, groups_end, tail_begin, out);
    default: return rows_dot<3>(a, stride, count, x, groups_begin, groups_end, tail_begin, out);
  }
}

/// a . b over the dofs [lo, end) of n, summed as MuJoCo's mju_dot sums the whole length n: four
/// running sums by the dof's place in MuJoCo's groups of four, joined as (s0 + s2) + (s1 + s3),
/// then the dofs past the last whole group summed in order and added. The groups that [lo, end)
/// touches are summed whole, as MuJoCo sums them: a must be zero outside [lo, end) (a zero
/// product adds nothing to a sum, as in MuJoCo's) and both readable over [0, n), b finite. With D
/// up to 1e6 on a cone's rows, a row's last bit shows in its force. (lo = 0, end = n: mju_dot.)
inline double dot_as_mujoco(const double* a, const double* b, int lo, int end, int n) {
  double out;
  rows_dot_as_mujoco(a, 0, 1, b, lo, end, n, &out);
  return out;
}

/// rows_dot_as_mujoco in MuJoCo's sparse order: out[k] = a_k . x over [lo, end), the products
/// added one after another from lo. A sparse row also stores zeros (a contact's common
/// ancestors' dofs), and a zero product adds nothing to a sum: the sum over [lo, end) with a
/// zero outside it is MuJoCo's over its stored entries (x finite).
inline void rows_dot_in_order(const double* a, Eigen::Index stride, int count, const double* x,
                              int lo, int end, double* out) {
  for (int k = 0; k < count; ++k, a += stride) {
    double sum = 0.0;
    for (int j = lo; j < end; ++j) sum += a[j] * x[j];
    out[k] = sum;
  }
}

/// a . b over [lo, end) of n as MuJoCo sums a product with a row of a matrix it holds sparse or
/// dense as the model's Jacobians are (efc_J, efc_AR, ten_J): in order when sparse
/// (sparse_jacobian, lever/model.hpp), else as dot_as_mujoco. (Its
/// mju_dotSparse has four running sums of its own when MuJoCo is built with AVX; Debian's
/// libmujoco 2.2.2 is built without, and adds in order.)
inline double row_dot_as_mujoco(bool sparse, const double* a, const double* b, int lo, int end,
                                int n) {
  double out;
  if (sparse) {
    rows_dot_in_order(a, 0, 1, b, lo, end, &out);
  } else {
    rows_dot_as_mujoco(a, 0, 1, b, lo, end, n, &out);
  }
  return out;
}

}  // namespace lever
