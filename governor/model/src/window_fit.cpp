#include "glbudget/model/window_fit.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Jacobi>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "glbudget/model/nonnegative_least_squares.hpp"
#include "glbudget/model/power_curve.hpp"

namespace glbudget::model {
namespace {

constexpr int kTerms = 3;  // batches, vertices, fragments

// Up to this many columns (8 passes x 3 terms) the small matrices of a solve (A'A, its
// eigenvectors, the solver's workspace) have a fixed maximum size and live on the stack:
// at these sizes heap allocations cost as much as the arithmetic. Wider windows (every
// program its own pass, no manifest) use dynamic storage and compute the same.
constexpr int kStackColumns = 24;

template <int MaxCols>
using SmallMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, MaxCols, MaxCols>;
template <int MaxCols>
using SmallVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, MaxCols, 1>;

std::array<double, kTerms> normalised_counts(const PlatformProfile& profile, const PassCounts& c) {
  return {c.batches / profile.saturation_batches, c.vertices / profile.saturation_vertices,
          c.fragments / profile.saturation_fragments};
}

double& term(PassCoefficients& k, int t) { return t == 0 ? k.k_b : t == 1 ? k.k_v : k.k_f; }

// One pass of the window and its columns.
struct WindowPass {
  const std::string* name;
  std::array<int, kTerms> column{-1, -1, -1};             // -1: no column (the term's count is 0 throughout)
  std::array<bool, kTerms> nonzero{false, false, false};  // any count > 0 in the window
  const PassCoefficients* previous = nullptr;
};

template <int MaxCols>
struct RidgeSolution {
  SmallVector<MaxCols> coefficients;
  // Share of each estimate owed to the prior: lambda (G^-1)_jj on the scaled problem; 1 for a
  // column the data says nothing about, ~0 for a well-identified one.
  SmallVector<MaxCols> prior_share;
};

// Generalised cross-validation (Golub, Heath & Wahba 1979) picks how far a window's
// estimate may move from the prior: noiseless data get the smallest ridge and an exact fit,
// noisy or barely varying counts a stronger pull instead of noise amplified into the
// coefficients. Works on the eigen-decomposition of A'A: `s2` are the squared singular values
// of A, `v_atr` = V' A' r for the residual r = y - A prior.
template <typename Vector>
double choose_lambda(const Vector& s2, const Vector& v_atr, double residual_norm2, double rows, double floor) {
  // Squared components of r along A's left singular vectors: (v_i' A' r)^2 / s_i^2.
  const double negligible = 1e-14 * std::max(s2.maxCoeff(), 1e-300);
  Vector projected2(s2.size());
  for (Eigen::Index i = 0; i < s2.size(); ++i) {
    projected2(i) = s2(i) > negligible ? v_atr(i) * v_atr(i) / s2(i) : 0.0;
  }
  const double outside = std::max(0.0, residual_norm2 - projected2.sum());
  const double ceiling = std::max(floor, static_cast<double>(s2.size()));
  double best_lambda = floor, best_score = std::numeric_limits<double>::infinity();
  for (double lambda = floor; lambda <= ceiling * 1.0001; lambda *= std::sqrt(10.0)) {
    double rss = outside, dof = 0.0;
    for (Eigen::Index i = 0; i < s2.size(); ++i) {
      const double shrink = lambda / (s2(i) + lambda);
      rss += shrink * shrink * projected2(i);
      dof += s2(i) / (s2(i) + lambda);
    }
    const double denominator = rows - dof;
    if (denominator < 0.5) continue;  // as many effective parameters as samples
    const double score = rows * rss / (denominator * denominator);
    if (score < best_score * (1.0 - 1e-9)) best_score = score, best_lambda = lambda;
  }
  return best_lambda;
}

// min |A k - y|^2 + lambda |D (k - prior)|^2 subject to k >= 0, where D scales A's columns to
// unit norm (so the ridge means the same for counts of any magnitude). lambda is chosen by
// GCV, never below ridge^2 * columns: directions of A with singular values well below
// sqrt(lambda) stay at the prior. One symmetric eigen-decomposition of A'A serves the choice
// of lambda, the ridge solution and the prior shares; the active-set solver only runs when
// that solution has a negative coefficient. MaxCols bounds A's columns (see kStackColumns).
// The eigen-decomposition G = V diag(s2) V' of a symmetric matrix in the form the ridge
// solve needs: eigenvalues, V' b for one vector b, and V d for one vector d. It runs Eigen's
// own algorithm (SelfAdjointEigenSolver: scale, Householder tridiagonalisation
// G = Q T Q', implicit symmetric QR steps with Wilkinson shifts T = W diag W', same deflation
// test) but keeps Q as Householder vectors and W as the list of Givens rotations instead of
// multiplying them out into V: forming V cost half of a whole fit, applying Q and W to a
// vector costs n^2 and the rotation count.
template <int MaxCols>
class EigenSolve {
 public:
  using Matrix = SmallMatrix<MaxCols>;
  using Vector = SmallVector<MaxCols>;

  explicit EigenSolve(const Matrix& g) {
    const Eigen::Index n = g.rows();
    scale_ = g.cwiseAbs().maxCoeff();
    if (!(scale_ > 0.0)) scale_ = 1.0;
    tridiagonal_.compute(g / scale_);
    Vector diag = tridiagonal_.diagonal();
    Vector subdiag = Vector::Zero(n);  // the last entry is never used
    subdiag.head(n - 1) = tridiagonal_.subDiagonal();
    rotations_.reserve(static_cast<std::size_t>(4 * n * n));
    // Eigen's computeFromTridiagonal_impl, recording rotations rather than applying them.
    constexpr int kMaxIterations = 30;
    const double considered_zero = std::numeric_limits<double>::min();
    const double precision_inverse = 1.0 / std::numeric_limits<double>::epsilon();
    Eigen::Index end = n - 1, start = 0, iterations = 0;
    while (end > 0) {
      for (Eigen::Index i = start; i < end; ++i) {
        if (std::abs(subdiag(i)) < considered_zero) {
          subdiag(i) = 0.0;
        } else {
          const double scaled = precision_inverse * subdiag(i);
          if (scaled * scaled <= std::abs(diag(i)) + std::abs(diag(i + 1))) subdiag(i) = 0.0;
        }
      }
      while (end > 0 && subdiag(end - 1) == 0.0) --end;
      if (end <= 0) break;
      if (++iterations > kMaxIterations * n) break;
      start = end - 1;
      while (start > 0 && subdiag(start - 1) != 0.0) --start;
      qr_step(diag, subdiag, start, end);
    }
    eigenvalues_ = diag * scale_;
  }

  const Vector& eigenvalues() const { return eigenvalues_; }

  // V' b = W' Q' b.
  Vector transpose_times(const Vector& b) const {
    Vector u = tridiagonal_.matrixQ().adjoint() * b;
    for (const Rotation& r : rotations_) {
      const double uk = u(r.k), ul = u(r.k + 1);
      u(r.k) = r.c * uk - r.s * ul;
      u(r.k + 1) = r.s * uk + r.c * ul;
    }
    return u;
  }

  // V d = Q W d.
  Vector times(Vector d) const {
    for (auto r = rotations_.rbegin(); r != rotations_.rend(); ++r) {
      const double dk = d(r->k), dl = d(r->k + 1);
      d(r->k) = r->c * dk + r->s * dl;
      d(r->k + 1) = -r->s * dk + r->c * dl;
    }
    return tridiagonal_.matrixQ() * d;
  }

 private:
  struct Rotation {
    Eigen::Index k;
    double c, s;
  };

  // Eigen's tridiagonal_qr_step (Golub & Van Loan, algorithm 8.3.2).
  void qr_step(Vector& diag, Vector& subdiag, Eigen::Index start, Eigen::Index end) {
    const double td = (diag(end - 1) - diag(end)) * 0.5;
    const double e = subdiag(end - 1);
    double mu = diag(end);
    if (td == 0.0) {
      mu -= std::abs(e);
    } else if (e != 0.0) {
      const double e2 = e * e;
      const double h = std::hypot(td, e);
      if (e2 == 0.0)
        mu -= e / ((td + (td > 0.0 ? h : -h)) / e);
      else
        mu -= e2 / (td + (td > 0.0 ? h : -h));
    }
    double x = diag(start) - mu;
    double z = subdiag(start);
    for (Eigen::Index k = start; k < end && z != 0.0; ++k) {
      Eigen::JacobiRotation<double> rotation;
      rotation.makeGivens(x, z);
      const double c = rotation.c(), s = rotation.s();
      const double sdk = s * diag(k) + c * subdiag(k);
      const double dkp1 = s * subdiag(k) + c * diag(k + 1);
      diag(k) = c * (c * diag(k) - s * subdiag(k)) - s * (c * subdiag(k) - s * diag(k + 1));
      diag(k + 1) = s * sdk + c * dkp1;
      subdiag(k) = c * sdk - s * dkp1;
      if (k > start) subdiag(k - 1) = c * subdiag(k - 1) - s * z;
      x = subdiag(k);
      if (k < end - 1) {
        z = -s * subdiag(k + 1);
        subdiag(k + 1) = c * subdiag(k + 1);
      }
      rotations_.push_back({k, c, s});  // Eigen: eigenvectors.applyOnTheRight(k, k + 1, rotation)
    }
  }

  double scale_ = 1.0;
  Eigen::Tridiagonalization<Matrix> tridiagonal_;
  std::vector<Rotation> rotations_;
  Vector eigenvalues_;
};

// min |A k - y|^2 + lambda |D (k - prior)|^2 subject to k >= 0, where D scales A's columns to
// unit norm (so the ridge means the same for counts of any magnitude). lambda is chosen by
// GCV, never below ridge^2 * columns: directions of A with singular values well below
// sqrt(lambda) stay at the prior. One symmetric eigen-decomposition of A'A serves the choice
// of lambda and the ridge solution; the active-set solver only runs when that solution has a
// negative coefficient. MaxCols bounds A's columns (see kStackColumns).
template <int MaxCols>
RidgeSolution<MaxCols> solve_ridge_nonnegative(Eigen::MatrixXd a, const Eigen::VectorXd& y,
                                               const SmallVector<MaxCols>& prior, double ridge) {
  using Matrix = SmallMatrix<MaxCols>;
  using Vector = SmallVector<MaxCols>;
  const Eigen::Index cols = a.cols();
  const Vector scale = a.colwise().norm().transpose();
  for (Eigen::Index c = 0; c < cols; ++c) {
    if (scale(c) > 0.0) a.col(c) /= scale(c);
  }
  const Vector scaled_prior = prior.cwiseProduct(scale);
  const Eigen::VectorXd residual = y - a * scaled_prior;
  // A'A by column dot products: Eigen's general product sets up blocking and a heap buffer,
  // which costs more than the few thousand multiply-adds of a 30 x 18 window.
  Matrix gram(cols, cols);
  for (Eigen::Index j = 0; j < cols; ++j) {
    for (Eigen::Index i = j; i < cols; ++i) gram(i, j) = gram(j, i) = a.col(i).dot(a.col(j));
  }
  const EigenSolve<MaxCols> eigen(gram);
  const Vector s2 = eigen.eigenvalues().cwiseMax(0.0);
  const Vector v_atr = eigen.transpose_times(a.transpose() * residual);
  const double lambda = choose_lambda(s2, v_atr, residual.squaredNorm(), static_cast<double>(a.rows()),
                                      ridge * ridge * static_cast<double>(cols));
  const Vector inverse_eigen = (s2.array() + lambda).inverse().matrix();

  gram.diagonal().array() += lambda;  // G = A'A + lambda I from here on
  Vector z = scaled_prior + eigen.times(inverse_eigen.cwiseProduct(v_atr));
  if (z.minCoeff() < 0.0) {
    const Vector rhs = a.transpose() * y + lambda * scaled_prior;
    solve_nonnegative(gram, rhs, z);
  }

  RidgeSolution<MaxCols> solution;
  // Share of each estimate owed to the prior: lambda (G^-1)_jj, from G = L L' as the squared
  // column norms of L^-1 (V itself is never formed, see EigenSolve). G >= lambda I > 0.
  // Column j of L^-1 is L^-1 e_j, zero above row j: a forward substitution by hand, as
  // Eigen's blocked triangular solve against an identity costs several times more here.
  const Eigen::LLT<Matrix> cholesky(gram);
  const Matrix& l = cholesky.matrixLLT();  // lower triangle holds L
  solution.prior_share.resize(cols);
  Vector column(cols);
  for (Eigen::Index j = 0; j < cols; ++j) {
    double norm2 = 0.0;
    for (Eigen::Index i = j; i < cols; ++i) {
      double sum = i == j ? 1.0 : 0.0;
      for (Eigen::Index k = j; k < i; ++k) sum -= l(i, k) * column(k);
      column(i) = sum / l(i, i);
      norm2 += column(i) * column(i);
    }
    solution.prior_share(j) = lambda * norm2;
  }
  solution.coefficients = prior;  // an all-zero column keeps its prior
  for (Eigen::Index c = 0; c < cols; ++c) {
    if (scale(c) > 0.0) solution.coefficients(c) = z(c) / scale(c);
  }
  return solution;
}

// The regression of fit_window once the window is laid out as columns; MaxCols as above.
template <int MaxCols>
void fit_columns(Eigen::MatrixXd a, const Eigen::VectorXd& y, const std::vector<WindowPass>& passes,
                 const WindowFitSettings& settings, WindowFitResult& result) {
  const Eigen::Index cols = a.cols();
  // Prior for each column: the previous coefficient where the pass has one; for a pass seen
  // for the first time, the pooled fit below (one k_b, k_v, k_f shared by all passes, which
  // a window identifies far better than per-pass values).
  SmallVector<MaxCols> prior(cols);
  bool any_new = false;
  for (const WindowPass& pass : passes) {
    PassCoefficients k = pass.previous ? *pass.previous : PassCoefficients{};
    any_new = any_new || (pass.previous == nullptr && pass.column != std::array<int, kTerms>{-1, -1, -1});
    for (int t = 0; t < kTerms; ++t) {
      if (pass.column[t] >= 0) prior(pass.column[t]) = term(k, t);
    }
  }
  if (any_new) {
    // Three columns only: a 3 x 3 eigen-problem with stack storage.
    Eigen::MatrixXd pooled = Eigen::MatrixXd::Zero(a.rows(), kTerms);
    for (const WindowPass& pass : passes) {
      for (int t = 0; t < kTerms; ++t) {
        if (pass.column[t] >= 0) pooled.col(t) += a.col(pass.column[t]);
      }
    }
    const RidgeSolution<kTerms> shared =
        solve_ridge_nonnegative<kTerms>(std::move(pooled), y, SmallVector<kTerms>::Zero(kTerms), settings.ridge);
    for (const WindowPass& pass : passes) {
      if (pass.previous != nullptr) continue;
      for (int t = 0; t < kTerms; ++t) {
        if (pass.column[t] >= 0) prior(pass.column[t]) = shared.coefficients(t);
      }
    }
  }
  const RidgeSolution<MaxCols> solution = solve_ridge_nonnegative<MaxCols>(std::move(a), y, prior, settings.ridge);

  for (Eigen::Index c = 0; c < cols; ++c) {
    if (solution.prior_share(c) > settings.held_share) ++result.held_terms;
  }
  for (const WindowPass& pass : passes) {
    if (pass.column == std::array<int, kTerms>{-1, -1, -1}) continue;  // keeps what it had
    PassCoefficients k = pass.previous ? *pass.previous : PassCoefficients{};
    for (int t = 0; t < kTerms; ++t) {
      if (pass.column[t] >= 0) term(k, t) = solution.coefficients(pass.column[t]);
    }
    result.model.set(*pass.name, k);
  }
}

}  // namespace

WindowFitResult fit_window(std::span<const FrameSample> window, const PowerModel& previous,
                           const WindowFitSettings& settings) {
  WindowFitResult result{previous};
  const PlatformProfile& profile = previous.profile();

  std::vector<const FrameSample*> usable;
  usable.reserve(window.size());
  for (const FrameSample& sample : window) {
    if (is_usable(sample))
      usable.push_back(&sample);
    else
      ++result.samples_rejected;
  }
  result.samples_used = usable.size();
  if (usable.empty() || !(profile.range_w() > 0.0)) return result;  // nothing to learn

  // The window's distinct passes, and for every (sample, pass entry) which of them it is.
  // Frames list their passes in much the same order, so the search starts where the same
  // entry of the previous frame was found (a string map cost a fifth of the fit).
  std::vector<WindowPass> passes;
  std::vector<int> pass_of_entry;
  std::size_t entries = 0;
  for (const FrameSample* sample : usable) entries += sample->passes.size();
  pass_of_entry.reserve(entries);
  std::vector<int> hint;  // per entry position: the pass found there in the last frame
  for (const FrameSample* sample : usable) {
    for (std::size_t e = 0; e < sample->passes.size(); ++e) {
      const PassFrame& entry = sample->passes[e];
      if (hint.size() <= e) hint.push_back(0);
      int found = -1;
      for (std::size_t i = 0; i < passes.size() && found < 0; ++i) {
        const int p = static_cast<int>((static_cast<std::size_t>(hint[e]) + i) % passes.size());
        if (*passes[p].name == entry.pass) found = p;
      }
      if (found < 0) {
        found = static_cast<int>(passes.size());
        passes.push_back({&entry.pass});
      }
      hint[e] = found;
      pass_of_entry.push_back(found);
      const auto x = normalised_counts(profile, entry.counts);
      for (int t = 0; t < kTerms; ++t) {
        if (x[t] > 0.0) passes[found].nonzero[t] = true;
      }
    }
  }
  // One column per (pass, term) with any non-zero count in the window, numbered in order of
  // pass name (the order does not change the fit beyond rounding; it keeps it reproducible).
  std::vector<int> by_name(passes.size());
  for (std::size_t i = 0; i < by_name.size(); ++i) by_name[i] = static_cast<int>(i);
  std::sort(by_name.begin(), by_name.end(), [&](int l, int r) { return *passes[l].name < *passes[r].name; });
  int cols = 0;
  for (int p : by_name) {
    for (int t = 0; t < kTerms; ++t) {
      if (passes[p].nonzero[t]) passes[p].column[t] = cols++;
    }
    passes[p].previous = previous.find(*passes[p].name);
  }
  result.columns = static_cast<std::size_t>(cols);
  if (cols == 0) return result;

  const auto rows = static_cast<Eigen::Index>(usable.size());
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(rows, cols);
  Eigen::VectorXd y(rows);
  std::size_t next_entry = 0;
  for (Eigen::Index r = 0; r < rows; ++r) {
    const LinearisedPower target = linearise_power(profile, usable[r]->power_w);
    y(r) = target.weight * target.alpha;
    for (const PassFrame& entry : usable[r]->passes) {
      const auto& column = passes[pass_of_entry[next_entry++]].column;
      const auto x = normalised_counts(profile, entry.counts);
      for (int t = 0; t < kTerms; ++t) {
        if (column[t] >= 0) a(r, column[t]) += target.weight * x[t];
      }
    }
  }

  if (cols <= kStackColumns) {
    fit_columns<kStackColumns>(std::move(a), y, passes, settings, result);
  } else {
    fit_columns<Eigen::Dynamic>(std::move(a), y, passes, settings, result);
  }
  return result;
}

}  // namespace glbudget::model
