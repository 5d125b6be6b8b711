#include "glbudget/analysis/cost_fit.hpp"

#include <Eigen/Core>
#include <map>
#include <utility>

#include "glbudget/model/nonnegative_least_squares.hpp"
#include "glbudget/model/power_curve.hpp"

namespace glbudget::analysis {

using namespace glbudget::model;

namespace {

constexpr Eigen::Index kCostColumns = 5;  // batch, vertex, fragment, instruction, texel

// The frame's row of the five cost columns: each pass's normalised counts times what each
// cost multiplies in its coefficients.
Eigen::Matrix<double, 1, kCostColumns> cost_row(const PlatformProfile& profile, const ConfigurationSpace& space,
                                                const ConfiguredSample& s) {
  Eigen::Matrix<double, 1, kCostColumns> row = Eigen::Matrix<double, 1, kCostColumns>::Zero();
  for (const PassFrame& p : s.sample.passes) {
    const double b = p.counts.batches / profile.saturation_batches;
    const double v = p.counts.vertices / profile.saturation_vertices;
    const double f = p.counts.fragments / profile.saturation_fragments;
    const VariantCost* level = space.level_of(p.pass, s.configuration);
    const VariantCost cost = level ? *level : VariantCost{};
    row(0) += b;
    row(1) += v;
    row(2) += f;
    row(3) += cost.ins_v * v + cost.ins_f * f;
    row(4) += cost.tex_f * f;
  }
  return row;
}

}  // namespace

std::optional<PlatformCostsFit> fit_platform_costs(std::span<const CostLog> logs, const PlatformProfile& profile) {
  if (!(profile.range_w() > 0.0)) return std::nullopt;
  struct Row {
    std::size_t log;
    const ConfiguredSample* sample;
  };
  std::vector<Row> rows;
  for (std::size_t l = 0; l < logs.size(); ++l) {
    if (logs[l].space == nullptr) continue;
    for (const ConfiguredSample& s : logs[l].samples) {
      if (is_usable(s.sample) && logs[l].space->contains(s.configuration)) rows.push_back({l, &s});
    }
  }
  if (rows.empty()) return std::nullopt;

  const Eigen::Index cols = kCostColumns + static_cast<Eigen::Index>(logs.size());
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(rows.size()), cols);
  Eigen::VectorXd y(a.rows());
  for (Eigen::Index r = 0; r < a.rows(); ++r) {
    const Row& row = rows[static_cast<std::size_t>(r)];
    const LinearisedPower target = linearise_power(profile, row.sample->sample.power_w);
    y(r) = target.weight * target.alpha;
    a.block<1, kCostColumns>(r, 0) = target.weight * cost_row(profile, *logs[row.log].space, *row.sample);
    a(r, kCostColumns + static_cast<Eigen::Index>(row.log)) = target.weight;
  }
  // As the other fits (ridge_nonnegative): a faint ridge towards 0 so that a cost no log can
  // identify (no pass samples a texture) stays 0 instead of taking noise, costs >= 0. The
  // per-frame loads are left free; a log with no usable frame keeps a load of 0.
  Eigen::VectorXd ridge = Eigen::VectorXd::Zero(cols);
  ridge.head<kCostColumns>().setConstant(1e-10 * static_cast<double>(cols));
  const Eigen::VectorXd unknowns = ridge_nonnegative(std::move(a), y, Eigen::VectorXd::Zero(cols), ridge);

  PlatformCostsFit fit;
  fit.costs = {unknowns(0), unknowns(1), unknowns(2), unknowns(3), unknowns(4)};
  fit.samples_used = rows.size();
  for (std::size_t l = 0; l < logs.size(); ++l) {
    fit.frame_alpha.push_back(unknowns(kCostColumns + static_cast<Eigen::Index>(l)));
    fit.per_frame.emplace_back(profile.range_w());
    fit.per_configuration.emplace_back(profile.range_w());
  }
  // In-sample errors, per frame and of each configuration's mean.
  std::vector<std::map<Configuration, std::pair<double, double>>> sums(logs.size());
  std::vector<std::map<Configuration, std::size_t>> counts(logs.size());
  const Eigen::Matrix<double, kCostColumns, 1> k = unknowns.head<kCostColumns>();
  for (const Row& row : rows) {
    const double alpha = (cost_row(profile, *logs[row.log].space, *row.sample) * k)(0) + fit.frame_alpha[row.log];
    const double predicted = power_from_alpha(profile, alpha);
    const double measured = row.sample->sample.power_w;
    fit.per_frame[row.log].add(predicted, measured);
    auto& sum = sums[row.log][row.sample->configuration];
    sum.first += predicted, sum.second += measured;
    ++counts[row.log][row.sample->configuration];
  }
  for (std::size_t l = 0; l < logs.size(); ++l) {
    for (const auto& [configuration, sum] : sums[l]) {
      const double n = static_cast<double>(counts[l][configuration]);
      fit.per_configuration[l].add(sum.first / n, sum.second / n);
    }
  }
  return fit;
}

}  // namespace glbudget::analysis
