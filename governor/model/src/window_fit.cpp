#include "glbudget/model/window_fit.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "glbudget/model/nonnegative_least_squares.hpp"
#include "glbudget/model/power_curve.hpp"

namespace glbudget::model {
namespace {

constexpr int kTerms = 3;  // batches, vertices, fragments

std::array<double, kTerms> normalised_counts(const PlatformProfile& profile, const PassCounts& c) {
  return {c.batches / profile.saturation_batches, c.vertices / profile.saturation_vertices,
          c.fragments / profile.saturation_fragments};
}

double& term(PassCoefficients& k, int t) { return t == 0 ? k.k_b : t == 1 ? k.k_v : k.k_f; }

// One pass of the window and its columns.
struct WindowPass {
  PassIndex pass = 0;
  std::array<int, kTerms> column{-1, -1, -1};             // -1: no column (the term's count is 0 throughout)
  std::array<bool, kTerms> nonzero{false, false, false};  // any count > 0 in the window
  const PassCoefficients* previous = nullptr;
};

struct RidgeSolution {
  Eigen::VectorXd coefficients;
  // Share of each estimate owed to the prior: lambda (G^-1)_jj on the scaled problem; 1 for a
  // column the data says nothing about, ~0 for a well-identified one.
  Eigen::VectorXd prior_share;
};

// Generalised cross-validation (Golub, Heath & Wahba 1979) picks how far a window's
// estimate may move from the prior: noiseless data get the smallest ridge and an exact fit,
// noisy or barely varying counts a stronger pull instead of noise amplified into the
// coefficients. Works on the eigen-decomposition of A'A: `s2` are the squared singular values
// of A, `v_atr` = V' A' r for the residual r = y - A prior.
double choose_lambda(const Eigen::VectorXd& s2, const Eigen::VectorXd& v_atr, double residual_norm2, double rows,
                     double floor) {
  // Squared components of r along A's left singular vectors: (v_i' A' r)^2 / s_i^2.
  const double negligible = 1e-14 * std::max(s2.maxCoeff(), 1e-300);
  Eigen::VectorXd projected2(s2.size());
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
// sqrt(lambda) stay at the prior. One symmetric eigen-decomposition A'A = V diag(s2) V'
// (Eigen's) serves the choice of lambda, the ridge solution and the prior shares; the
// active-set solver only runs when that solution has a negative coefficient.
RidgeSolution solve_ridge_nonnegative(Eigen::MatrixXd a, const Eigen::VectorXd& y, const Eigen::VectorXd& prior,
                                      double ridge) {
  const Eigen::Index cols = a.cols();
  const Eigen::VectorXd scale = a.colwise().norm().transpose();
  for (Eigen::Index c = 0; c < cols; ++c) {
    if (scale(c) > 0.0) a.col(c) /= scale(c);
  }
  const Eigen::VectorXd scaled_prior = prior.cwiseProduct(scale);
  const Eigen::VectorXd residual = y - a * scaled_prior;
  Eigen::MatrixXd gram = a.transpose() * a;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(gram);
  const Eigen::VectorXd s2 = eigen.eigenvalues().cwiseMax(0.0);
  const Eigen::MatrixXd& v = eigen.eigenvectors();
  const Eigen::VectorXd v_atr = v.transpose() * (a.transpose() * residual);
  const double lambda = choose_lambda(s2, v_atr, residual.squaredNorm(), static_cast<double>(a.rows()),
                                      ridge * ridge * static_cast<double>(cols));
  const Eigen::VectorXd inverse_eigen = (s2.array() + lambda).inverse().matrix();

  Eigen::VectorXd z = scaled_prior + v * inverse_eigen.cwiseProduct(v_atr);
  if (z.minCoeff() < 0.0) {
    gram.diagonal().array() += lambda;  // G = A'A + lambda I
    const Eigen::VectorXd rhs = a.transpose() * y + lambda * scaled_prior;
    solve_nonnegative(gram, rhs, z);
  }

  RidgeSolution solution;
  // lambda (G^-1)_jj with G^-1 = V diag(1 / (s2 + lambda)) V'.
  solution.prior_share = lambda * (v.array().square().matrix() * inverse_eigen);
  solution.coefficients = prior;  // an all-zero column keeps its prior
  for (Eigen::Index c = 0; c < cols; ++c) {
    if (scale(c) > 0.0) solution.coefficients(c) = z(c) / scale(c);
  }
  return solution;
}

// The regression of fit_window once the window is laid out as columns.
void fit_columns(Eigen::MatrixXd a, const Eigen::VectorXd& y, const std::vector<WindowPass>& passes,
                 const WindowFitSettings& settings, WindowFitResult& result) {
  const Eigen::Index cols = a.cols();
  // Prior for each column: the previous coefficient where the pass has one; for a pass seen
  // for the first time, the pooled fit below (one k_b, k_v, k_f shared by all passes, which
  // a window identifies far better than per-pass values).
  Eigen::VectorXd prior(cols);
  bool any_new = false;
  for (const WindowPass& pass : passes) {
    PassCoefficients k = pass.previous ? *pass.previous : PassCoefficients{};
    any_new = any_new || (pass.previous == nullptr && pass.column != std::array<int, kTerms>{-1, -1, -1});
    for (int t = 0; t < kTerms; ++t) {
      if (pass.column[t] >= 0) prior(pass.column[t]) = term(k, t);
    }
  }
  if (any_new) {
    Eigen::MatrixXd pooled = Eigen::MatrixXd::Zero(a.rows(), kTerms);
    for (const WindowPass& pass : passes) {
      for (int t = 0; t < kTerms; ++t) {
        if (pass.column[t] >= 0) pooled.col(t) += a.col(pass.column[t]);
      }
    }
    const RidgeSolution shared =
        solve_ridge_nonnegative(std::move(pooled), y, Eigen::VectorXd::Zero(kTerms), settings.ridge);
    for (const WindowPass& pass : passes) {
      if (pass.previous != nullptr) continue;
      for (int t = 0; t < kTerms; ++t) {
        if (pass.column[t] >= 0) prior(pass.column[t]) = shared.coefficients(t);
      }
    }
  }
  const RidgeSolution solution = solve_ridge_nonnegative(std::move(a), y, prior, settings.ridge);

  for (Eigen::Index c = 0; c < cols; ++c) {
    if (solution.prior_share(c) > settings.held_share) ++result.held_terms;
  }
  for (const WindowPass& pass : passes) {
    if (pass.column == std::array<int, kTerms>{-1, -1, -1}) continue;  // keeps what it had
    PassCoefficients k = pass.previous ? *pass.previous : PassCoefficients{};
    for (int t = 0; t < kTerms; ++t) {
      if (pass.column[t] >= 0) term(k, t) = solution.coefficients(pass.column[t]);
    }
    result.model.set(pass.pass, k);
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

  // The window's distinct passes, by index.
  std::vector<int> slot;  // [PassIndex]: its place in `passes`, -1 before it is seen
  std::vector<WindowPass> passes;
  for (const FrameSample* sample : usable) {
    for (const PassFrame& entry : sample->passes) {
      if (slot.size() <= entry.pass) slot.resize(static_cast<std::size_t>(entry.pass) + 1, -1);
      if (slot[entry.pass] < 0) {
        slot[entry.pass] = static_cast<int>(passes.size());
        passes.push_back({entry.pass});
      }
      const auto x = normalised_counts(profile, entry.counts);
      for (int t = 0; t < kTerms; ++t) {
        if (x[t] > 0.0) passes[static_cast<std::size_t>(slot[entry.pass])].nonzero[t] = true;
      }
    }
  }
  // One column per (pass, term) with any non-zero count in the window, numbered in order of
  // pass index (the order does not change the fit beyond rounding; it keeps it reproducible).
  std::sort(passes.begin(), passes.end(), [](const WindowPass& l, const WindowPass& r) { return l.pass < r.pass; });
  for (std::size_t p = 0; p < passes.size(); ++p) slot[passes[p].pass] = static_cast<int>(p);
  int cols = 0;
  for (WindowPass& pass : passes) {
    for (int t = 0; t < kTerms; ++t) {
      if (pass.nonzero[t]) pass.column[t] = cols++;
    }
    pass.previous = previous.find(pass.pass);
  }
  result.columns = static_cast<std::size_t>(cols);
  if (cols == 0) return result;

  const auto rows = static_cast<Eigen::Index>(usable.size());
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(rows, cols);
  Eigen::VectorXd y(rows);
  for (Eigen::Index r = 0; r < rows; ++r) {
    const LinearisedPower target = linearise_power(profile, usable[r]->power_w);
    y(r) = target.weight * target.alpha;
    for (const PassFrame& entry : usable[r]->passes) {
      const auto& column = passes[static_cast<std::size_t>(slot[entry.pass])].column;
      const auto x = normalised_counts(profile, entry.counts);
      for (int t = 0; t < kTerms; ++t) {
        if (column[t] >= 0) a(r, column[t]) += target.weight * x[t];
      }
    }
  }

  fit_columns(std::move(a), y, passes, settings, result);
  return result;
}

}  // namespace glbudget::model
