// Composite-rigid-body algorithm and the LTDL factorization of the joint-space inertia.
//
// crba() is Featherstone's composite-rigid-body algorithm (RBDA 2008, section 6.2) with every
// quantity in absolute coordinates (see kinematics.cpp), where it needs no coordinate transforms:
//   IC_b = I_b + sum of IC over b's children           (composite inertia of b's subtree)
//   H_ij = S_j . (IC_body(i) S_i)   for j = i and each ancestor dof j of i
// factor_mass() and solve_mass() are his LTDL factorization and solves (section 6.5), which keep
// M's branch-induced sparsity: row i of L is non-zero only at i's ancestors. A simple body's block
// (Model::body_simple: diagonal and constant) is copied from dof_M0 and skipped by the LTDL steps,
// as MuJoCo's mj_crb and mj_factorM do.
//   lambda(i) = model.dof_parentid[i] (-1: the world), S_i = data.cdof[i], I_b = data.cinert[b].
#include <lever/data.hpp>
#include <lever/dynamics.hpp>

#include <algorithm>

#include "basics/basics.hpp"
#include "model/model_room.hpp"
#include "smooth/recursion.hpp"
#include "smooth/smooth.hpp"

namespace lever {

namespace {

// Zeroes H(i, k) and H(k, i) for every dof k < i that is no ancestor of dof i (a branch elsewhere
// in the tree: no coupling). With crba's ancestor entries this writes every entry of H.
void zero_uncoupled(const Model& model, Eigen::Ref<Eigen::MatrixXd> H, int i) {
  int gap_end = i;  // rows (j, gap_end) lie between two consecutive ancestors
  for (int j = model.dof_parentid[i];; j = model.dof_parentid[j]) {
    for (int k = j + 1; k < gap_end; ++k) H(k, i) = H(i, k) = 0.0;
    if (j < 0) return;
    gap_end = j;
  }
}

// H's column i and its transpose row over i's ancestors: the force that accelerating dof i needs,
// seen by i and by each of its ancestors.
inline void crba_column(const Model& model, const Data& data, Eigen::Ref<Eigen::MatrixXd> H,
                        int i) {
  const Force F = data.work.crb[model.dof_bodyid[i]] * data.cdof[i];
  H(i, i) = power(data.cdof[i], F) + model.dof_armature[i];  // armature: the motor's rotor
  for (int j = model.dof_parentid[i]; j >= 0; j = model.dof_parentid[j]) {
    H(i, j) = H(j, i) = power(data.cdof[j], F);
  }
}

// The same for a run of n simple dofs from `first` (Model::body_simple; dof_simplenum counts the
// dofs of simple bodies one after another): their diagonal entries are the same at every state and
// their couplings are zero, as MuJoCo's mj_crb copies them. A simple body hangs from the world (or
// from a body welded to it), so its dofs couple with no dof outside it either: the run's columns
// are zero whole but for the diagonal, and so are its rows left of it, written without walking any
// ancestors (zero_uncoupled need not visit the run). M is contiguous (a Data's array), so the
// run's columns are one span.
inline void simple_run(const Model& model, ArenaMatrix& M, int first, int n) {
  const std::ptrdiff_t nv = model.nv;
  std::fill_n(&M(0, first), n * nv, 0.0);
  for (int j = 0; j < first; ++j) std::fill_n(&M(first, j), n, 0.0);
  for (int k = first; k < first + n; ++k) M(k, k) = model.dof_M0[k];
}

// crba()'s columns and zeros where the model has simple dofs: a run of them whole; each other
// column with its zeros, once a dof before it is no ancestor of it. Out of line, so that it costs
// the common case one test.
[[gnu::noinline]] void columns_with_simple_runs(const Model& model, const Data& data,
                                                ArenaMatrix& H) {
  bool chain = true;  // dofs 0..i-1 are a chain down to i
  for (int i = 0; i < model.nv;) {
    const int run = model.dof_simplenum[i];
    if (run > 0) {
      simple_run(model, H, i, run);
      i += run;
      chain = false;
      continue;
    }
    crba_column(model, data, H, i);
    chain = chain && model.dof_parentid[i] == i - 1;
    if (!chain) zero_uncoupled(model, H, i);
    ++i;
  }
}

}  // namespace

void unchecked::crba(const Model& model, Data& data) {
  auto& H = data.M;

  // composite inertias, leaves to root (bodies on the world stop there: nothing above them moves)
  composite_inertias(model, data, data.work.crb);

  // the columns, and the other entries, which are zero: written where there are any (past the
  // chain the first dofs form), not by clearing all of H first, and every call, so nothing a
  // caller left in M stays
  if (model.has_simple_dofs) {
    columns_with_simple_runs(model, data, H);
    return;
  }
  // a model without simple dofs does not ask for each dof
  for (int i = 0; i < model.nv; ++i) crba_column(model, data, H, i);
  int i = 1;
  while (i < model.nv && model.dof_parentid[i] == i - 1) ++i;
  for (; i < model.nv; ++i) zero_uncoupled(model, H, i);
}

void crba(const Model& model, Data& data) {
  check_entry(model, data, "lever::crba");
  unchecked::crba(model, data);
}

namespace {

constexpr double kMinPivot = detail::kMinVal;  // keep the solve finite, as MuJoCo does

// LTDL's steps at the columns k = last down to first of H (upper triangle), leaves to root: D_k's
// pivot made positive, then column k eliminated from its ancestors' columns. Returns the first
// (lowest) column whose pivot was not positive, or -1. SkipSimple: the model has simple dofs
// (Model::body_simple), whose columns hold zeros off the diagonal (crba() writes them so) and are
// skipped; without any, the loop does not ask (the factorization and solves below are
// instantiated both ways, chosen once per call).
template <bool SkipSimple>
[[gnu::always_inline]] inline int ltdl_columns(const Model& model, Eigen::Ref<Eigen::MatrixXd> H,
                                               int last, int first) {
  int bad = -1;
  for (int k = last; k >= first; --k) {
    if (H(k, k) < kMinPivot) {
      bad = k;
      H(k, k) = kMinPivot;
    }
    if (SkipSimple && model.dof_simplenum[k] > 0) continue;  // nothing to eliminate
    const double* Hk = &H(0, k);  // column k: H(j, k) for the ancestors j of k
    for (int i = model.dof_parentid[k]; i >= 0; i = model.dof_parentid[i]) {
      const double a = Hk[i] / Hk[k];
      double* Hi = &H(0, i);
      for (int j = i; j >= 0; j = model.dof_parentid[j]) Hi[j] -= a * Hk[j];
      H(i, k) = a;
    }
  }
  return bad;
}

// The same step at a column k whose ancestors are the dofs 0..k-1 (a chain): the same arithmetic
// over contiguous rows (vectorized; restrict: two different columns).
inline bool ltdl_chain_column(Eigen::Ref<Eigen::MatrixXd> H, int k) {
  const bool bad = H(k, k) < kMinPivot;
  if (bad) H(k, k) = kMinPivot;
  double* __restrict Hk = &H(0, k);
  for (int i = k - 1; i >= 0; --i) {
    const double a = Hk[i] / Hk[k];
    double* __restrict Hi = &H(0, i);
    for (int j = 0; j <= i; ++j) Hi[j] -= a * Hk[j];
    Hk[i] = a;  // H(i, k)
  }
  return bad;
}

// Whether ltdl() takes the chain steps: dofs 0..kLongChain form a chain. Below that the vector
// loop's setup costs what it saves.
constexpr int kLongChain = 8;
bool long_leading_chain(const Model& model) {
  if (model.nv <= kLongChain) return false;
  for (int k = 1; k <= kLongChain; ++k) {
    if (model.dof_parentid[k] != k - 1) return false;
  }
  return true;
}

// ltdl() for a model whose first dofs form a long chain: the chain's columns from kLongChain on
// take the chain step, the others the general one. Out of line, so that it costs ltdl()'s common
// case one test.
// (The chain step does not skip simple dofs: a simple body has no child and hangs from the
// world, so a chain from dof 0 holds one only as a single body of nine or more joints, whose zero
// columns it eliminates to the same result.)
template <bool SkipSimple>
[[gnu::noinline]] int ltdl_long_chain(const Model& model, Eigen::Ref<Eigen::MatrixXd> H) {
  int chain_end = kLongChain + 1;  // dofs 0..chain_end-1 form one chain
  while (chain_end < model.nv && model.dof_parentid[chain_end] == chain_end - 1) ++chain_end;
  int bad = ltdl_columns<SkipSimple>(model, H, model.nv - 1, chain_end);
  for (int k = chain_end - 1; k >= kLongChain; --k) {
    if (ltdl_chain_column(H, k)) bad = k;
  }
  const int bad_below = ltdl_columns<SkipSimple>(model, H, kLongChain - 1, 0);
  return bad_below >= 0 ? bad_below : bad;
}

// In-place LTDL factorization of the symmetric H, working in its upper triangle: on return D is
// on the diagonal and L^T above it (L(k, i), i an ancestor of k, at (i, k)), so that every inner
// loop runs down one column. Returns the first dof whose pivot was not positive, or -1.
template <bool SkipSimple>
int ltdl_factor(const Model& model, Eigen::Ref<Eigen::MatrixXd> H,
                Eigen::Ref<Eigen::VectorXd> diag_inverse) {
  const int bad = long_leading_chain(model) ? ltdl_long_chain<SkipSimple>(model, H)
                                            : ltdl_columns<SkipSimple>(model, H, model.nv - 1, 0);
  for (int k = 0; k < model.nv; ++k) diag_inverse[k] = 1.0 / H(k, k);
  return bad;
}

int ltdl(const Model& model, Eigen::Ref<Eigen::MatrixXd> H,
         Eigen::Ref<Eigen::VectorXd> diag_inverse) {
  return model.has_simple_dofs ? ltdl_factor<true>(model, H, diag_inverse)
                               : ltdl_factor<false>(model, H, diag_inverse);
}

// x <- L^-T x with a factor from ltdl(), leaves to root.
template <bool SkipSimple>
void solve_half(const Model& model, const Eigen::Ref<const Eigen::MatrixXd>& LD,
                Eigen::Ref<Eigen::VectorXd> x) {
  for (int k = model.nv - 1; k >= 0; --k) {
    if (SkipSimple && model.dof_simplenum[k] > 0) continue;  // column k of L is zero
    const double* Lk = LD.col(k).data();
    for (int i = model.dof_parentid[k]; i >= 0; i = model.dof_parentid[i]) x[i] -= Lk[i] * x[k];
  }
}

void ltdl_solve_half(const Model& model, const Eigen::Ref<const Eigen::MatrixXd>& LD,
                     Eigen::Ref<Eigen::VectorXd> x) {
  if (model.has_simple_dofs) {
    solve_half<true>(model, LD, x);
  } else {
    solve_half<false>(model, LD, x);
  }
}

// x = (L^T D L)^-1 x with a factor from ltdl().
template <bool SkipSimple>
void solve(const Model& model, const Eigen::Ref<const Eigen::MatrixXd>& LD,
           const Eigen::Ref<const Eigen::VectorXd>& diag_inverse, Eigen::Ref<Eigen::VectorXd> x) {
  const int n = model.nv;
  solve_half<SkipSimple>(model, LD, x);  // x <- L^-T x
  // x <- D^-1 x
  for (int k = 0; k < n; ++k) x[k] *= diag_inverse[k];
  // x <- L^-1 x, root to leaves
  for (int k = 0; k < n; ++k) {
    if (SkipSimple && model.dof_simplenum[k] > 0) continue;  // row k of L is zero
    const double* Lk = LD.col(k).data();
    for (int i = model.dof_parentid[k]; i >= 0; i = model.dof_parentid[i]) x[k] -= Lk[i] * x[i];
  }
}

void ltdl_solve(const Model& model, const Eigen::Ref<const Eigen::MatrixXd>& LD,
                const Eigen::Ref<const Eigen::VectorXd>& diag_inverse,
                Eigen::Ref<Eigen::VectorXd> x) {
  if (model.has_simple_dofs) {
    solve<true>(model, LD, diag_inverse, x);
  } else {
    solve<false>(model, LD, diag_inverse, x);
  }
}

}  // namespace

void unchecked::factor_mass(const Model& model, Data& data) {
  data.qLD = data.M;
  const int bad = ltdl(model, data.qLD, data.qLDiagInv);
  if (bad >= 0) record_warning(data, Warning::kInertia, bad);
}

void factor_mass(const Model& model, Data& data) {
  check_entry(model, data, "lever::factor_mass");
  unchecked::factor_mass(model, data);
}

void unchecked::solve_mass(const Model& model, const Data& data, double* x) {
  ltdl_solve(model, data.qLD, data.qLDiagInv, Eigen::Map<Eigen::VectorXd>(x, model.nv));
}

void detail::mass_times(const Model& model, const Data& data, const double* x, double* out) {
  const int nv = model.nv;
  const ArenaMatrix& M = data.M;
  for (int i = 0; i < nv; ++i) out[i] = 0.0;
  // row by row, M's lower triangle as MuJoCo stores it: each coupling M_ij (j an ancestor of i)
  // read once, for both of the products it enters (the later rows add to the earlier ones)
  for (int i = 0; i < nv; ++i) {
    if (model.dof_simplenum[i] > 0) {  // no couplings: M's diagonal entry alone
      out[i] = M(i, i) * x[i];
      continue;
    }
    out[i] += M(i, i) * x[i];
    for (int j = model.dof_parentid[i]; j >= 0; j = model.dof_parentid[j]) {
      out[i] += M(i, j) * x[j];
      out[j] += M(i, j) * x[i];
    }
  }
}

void solve_mass(const Model& model, const Data& data, Eigen::Ref<Eigen::VectorXd> x) {
  check_entry(model, data, "lever::solve_mass");
  check_argument_size(x.size(), model.nv, "lever::solve_mass", "x");
  ltdl_solve(model, data.qLD, data.qLDiagInv, x);
}

void solve_mass_half(const Model& model, const Data& data, Eigen::Ref<Eigen::VectorXd> x) {
  ltdl_solve_half(model, data.qLD, x);
}

void factor_mass_damped(const Model& model, Data& data, double h) {
  // M + h diag(damping): the matrix of the Euler step's implicit damping
  data.work.LD2 = data.M;
  for (int i = 0; i < model.nv; ++i) data.work.LD2(i, i) += h * model.dof_damping[i];
  ltdl(model, data.work.LD2, data.work.LD2DiagInv);
}

void factor_mass_minus(const Model& model, Data& data, const Eigen::Ref<const Eigen::MatrixXd>& D,
                       double h) {
  data.work.LD2 = data.M;
  data.work.LD2 -= h * D;
  ltdl(model, data.work.LD2, data.work.LD2DiagInv);
}

void solve_mass_damped(const Model& model, const Data& data, Eigen::Ref<Eigen::VectorXd> x) {
  ltdl_solve(model, data.work.LD2, data.work.LD2DiagInv, x);
}

}  // namespace lever
