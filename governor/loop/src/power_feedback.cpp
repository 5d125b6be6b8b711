#include "glbudget/loop/power_feedback.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "normal_quantile.hpp"

namespace glbudget::loop {
namespace {

// The spread is the mean square of the last minute's deviations (of 1-s windows). The cpu
// estimate on the demo's scenes moves between two levels 2-5 W apart for tens of frames at a
// time: over 16 windows the spread fell to a third of the run's in quiet stretches, and the
// windows after one went over the budget.
constexpr std::size_t kSpreadWindows = 64;

}  // namespace

PowerFeedback::PowerFeedback(FeedbackSettings settings)
    : settings_(settings), z_(std::max(0.0, normal_quantile(settings.keep_share))) {}

void PowerFeedback::interrupt() { open_.reset(); }

std::optional<PowerFeedback::Window> PowerFeedback::add(const model::Configuration& configuration, std::int64_t time_ns,
                                                        double measured_w, double predicted_w) {
  if (!settings_.enabled || !std::isfinite(measured_w) || !std::isfinite(predicted_w)) return std::nullopt;
  if (open_ && (open_->configuration != configuration || time_ns < open_->start_ns)) open_.reset();
  if (!open_) {
    open_ = Open{configuration, time_ns};
    ++windows_opened_;
  }
  Open& w = *open_;
  ++w.frames;
  ++frames_taken_;
  w.measured += measured_w;
  w.predicted += predicted_w;
  w.frame_residual_sq += (measured_w - predicted_w) * (measured_w - predicted_w);
  if (static_cast<double>(time_ns - w.start_ns) * 1e-9 < settings_.window_s) return std::nullopt;

  const Open done = w;
  open_.reset();
  if (done.frames < settings_.min_frames) return std::nullopt;
  const double n = static_cast<double>(done.frames);
  Window window{done.configuration, done.measured / n, done.predicted / n, done.frames};
  const double r = window.measured_w - window.predicted_w;

  // Until windows of one configuration can be compared, the spread of a window's mean is
  // taken from its frames as if they were independent, which understates it when frames
  // are correlated; the comparison between windows replaces it as soon as it exists.
  const double frame_var = std::max(0.0, done.frame_residual_sq / n - r * r);
  within_sq_ = frame_var / n;

  // Surprise fades with every window, so that a run whose predictions have since improved may
  // try configurations it has not measured again.
  surprise_sq_ *= 1.0 - 1.0 / std::max(1.0, settings_.surprise_fade_windows);
  Residual& residual = residuals_[done.configuration];
  if (residual.windows == 0 && windows_ > 0) {
    // Over the bias still as fitted before this window, what the selection counted on. Only
    // power above it puts a window over the budget: a configuration that drew less than
    // predicted is no reason to keep the others from being tried.
    const double surprise = std::max(0.0, r - bias(done.configuration));
    const double weight = 1.0 / std::min(static_cast<double>(++surprises_), std::max(1.0, settings_.surprise_memory));
    surprise_sq_ += weight * (surprise * surprise - surprise_sq_);
  }
  if (residual.windows > 0) {
    const double deviation = r - residual.value;
    between_sq_ += (deviation * deviation - between_sq_) /
                   static_cast<double>(std::min<std::size_t>(++between_count_, kSpreadWindows));
  }
  ++residual.windows;
  residual.value += memory_weight(residual.windows, settings_.memory_windows) * (r - residual.value);
  ++windows_;
  mean_power_w_ += (window.measured_w - mean_power_w_) / static_cast<double>(std::min<std::size_t>(windows_, 16));
  fit();
  return window;
}

// Without this, a refit moves every corrected prediction by its change until windows at the
// new coefficients replace the residuals (memory_windows of them): on the demo's scenes refits
// every 60-100 frames moved the prediction of the configuration being drawn by 0.7-1.5 W on
// average (up to 6 W), and selections counted on power that was not there; each such step
// also entered the spread of windows as if it were the sensor's scatter.
void PowerFeedback::rebase(const model::Configuration& configuration, double change_w) {
  if (!settings_.enabled) return;
  if (!std::isfinite(change_w)) {
    open_.reset();
    return;
  }
  if (open_ && open_->configuration == configuration) {
    // Its frames' predictions as the new coefficients would have made them, and the sum of
    // their squared residuals with them: sum (r - d)^2 = sum r^2 - 2 d sum r + n d^2.
    Open& w = *open_;
    const double n = static_cast<double>(w.frames);
    w.frame_residual_sq += change_w * (n * change_w - 2.0 * (w.measured - w.predicted));
    w.predicted += change_w * n;
  } else {
    open_.reset();
  }
  const auto it = residuals_.find(configuration);
  if (it == residuals_.end()) return;
  it->second.value -= change_w;
  fit();
}

double PowerFeedback::residual(const model::Configuration& configuration) const {
  const auto it = residuals_.find(configuration);
  return it == residuals_.end() ? 0.0 : it->second.value;
}

void PowerFeedback::set_prior(std::vector<std::vector<double>> terms) {
  prior_ = std::move(terms);
  fit();
}

double PowerFeedback::bias(const model::Configuration& configuration) const {
  const double fitted = fitted_bias(configuration);
  if (!settings_.enabled || !settings_.own_residuals) return fitted;
  const auto it = residuals_.find(configuration);
  if (it == residuals_.end()) return fitted;
  return fitted + own_weight(it->second.windows) * (it->second.value - fitted);
}

// The residual is the mean of a configuration's windows up to memory_windows of them, then an
// exponential average with weight 1/m, whose variance is that of a mean of 2m - 1 windows.
// Shrinkage as a normal prior of scale tau on the configuration's own deviation from the fit
// would give, with the windows' spread as each window's scatter.
double PowerFeedback::own_weight(std::size_t windows) const {
  if (windows == 0) return 0.0;
  const double memory = std::max(1.0, settings_.memory_windows);
  const double n = std::min(static_cast<double>(windows), 2.0 * memory - 1.0);
  const double tau = std::max(1e-6, settings_.prior_share * mean_power_w_);
  const double spread = spread_w();
  const double weight = n * tau * tau / (n * tau * tau + spread * spread);
  return std::isfinite(weight) ? weight : 0.0;
}

double PowerFeedback::fitted_bias(const model::Configuration& configuration) const {
  if (!settings_.enabled || (residuals_.empty() && prior_.empty())) return 0.0;
  double b = offset_;
  for (std::size_t i = 0; i < configuration.size() && i < terms_.size(); ++i) {
    const auto level = static_cast<std::size_t>(configuration[i]);
    if (level < terms_[i].size()) b += terms_[i][level];
  }
  return b;
}

// Weighted ridge least squares over the measured configurations: unknowns the offset
// (unpenalised) and a term per pass and non-best level (a pass's best level is the reference),
// each penalised by (spread / prior)^2 so that a term is believed once the measurements
// show it beyond their own scatter.
void PowerFeedback::fit() {
  std::vector<std::pair<std::size_t, std::size_t>> columns;  // (pass, level) of each term
  for (const auto& [configuration, r] : residuals_) {
    for (std::size_t i = 0; i < configuration.size(); ++i) {
      const auto level = static_cast<std::size_t>(configuration[i]);
      if (level == 0) continue;
      const std::pair<std::size_t, std::size_t> key{i, level};
      if (std::find(columns.begin(), columns.end(), key) == columns.end()) columns.push_back(key);
    }
  }
  for (std::size_t pass = 0; pass < prior_.size(); ++pass)
    for (std::size_t level = 1; level < prior_[pass].size(); ++level) {
      const std::pair<std::size_t, std::size_t> key{pass, level};
      if (prior_[pass][level] != 0.0 && std::find(columns.begin(), columns.end(), key) == columns.end())
        columns.push_back(key);
    }
  const std::size_t n = columns.size() + 1;
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
  Eigen::VectorXd row(static_cast<Eigen::Index>(n));
  for (const auto& [configuration, r] : residuals_) {
    row.setZero();
    row[0] = 1.0;
    for (std::size_t c = 0; c < columns.size(); ++c) {
      const auto [pass, level] = columns[c];
      if (pass < configuration.size() && static_cast<std::size_t>(configuration[pass]) == level)
        row[static_cast<Eigen::Index>(c + 1)] = 1.0;
    }
    const double weight = std::min(static_cast<double>(r.windows), std::max(1.0, settings_.memory_windows));
    normal.noalias() += weight * row * row.transpose();
    rhs.noalias() += weight * r.value * row;
  }
  const double prior = std::max(1e-6, settings_.prior_share * mean_power_w_);
  const double spread = std::max(spread_w(), 1e-3 * prior);
  const double ridge = (spread * spread) / (prior * prior);
  for (std::size_t c = 1; c < n; ++c) {
    const auto i = static_cast<Eigen::Index>(c);
    normal(i, i) += ridge;
    rhs[i] += ridge * prior_at(columns[c - 1].first, columns[c - 1].second);
  }
  normal(0, 0) += 1e-9;  // a well-posed system even if every column were collinear with the offset
  const Eigen::VectorXd x = normal.ldlt().solve(rhs);

  offset_ = x.allFinite() ? x[0] : 0.0;
  terms_.clear();
  for (std::size_t c = 0; c < columns.size(); ++c) {
    const auto [pass, level] = columns[c];
    if (terms_.size() <= pass) terms_.resize(pass + 1);
    if (terms_[pass].size() <= level) terms_[pass].resize(level + 1, 0.0);
    terms_[pass][level] = x.allFinite() ? x[static_cast<Eigen::Index>(c + 1)] : 0.0;
  }
}

double PowerFeedback::spread_w() const {
  if (!settings_.enabled || windows_ == 0) return 0.0;
  return std::sqrt(between_count_ > 0 ? between_sq_ : within_sq_);
}

double PowerFeedback::margin_w() const { return z_ * spread_w(); }

double PowerFeedback::unmeasured_margin_w() const { return std::max(0.0, z_ * typical_surprise_w() - margin_w()); }

double PowerFeedback::typical_surprise_w() const {
  if (!settings_.enabled || !settings_.guard_unmeasured || windows_ == 0) return 0.0;
  // surprise_sq_ is 0 until the first surprise; mean_power_w_ averages finite windows only.
  return std::max(std::sqrt(surprise_sq_), std::max(0.0, settings_.surprise_floor_share) * mean_power_w_);
}

std::vector<model::Configuration> PowerFeedback::measured_configurations() const {
  std::vector<model::Configuration> out;
  out.reserve(residuals_.size());
  for (const auto& [configuration, residual] : residuals_) out.push_back(configuration);
  return out;
}

void PowerFeedback::correct(const model::ConfigurationSpace& space, std::vector<double>& predicted_w) const {
  if (!settings_.enabled || (residuals_.empty() && prior_.empty())) return;
  for (std::size_t i = 0; i < predicted_w.size() && i < space.size(); ++i) predicted_w[i] += bias(space.decode(i));
}

}  // namespace glbudget::loop
