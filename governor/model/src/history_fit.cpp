#include "glbudget/model/history_fit.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <set>
#include <utility>

#include "glbudget/model/nonnegative_least_squares.hpp"
#include "glbudget/model/power_curve.hpp"

namespace glbudget::model {
namespace {

// A level's instructions and texels above the pass's cheapest drawing level.
struct Excess {
  double ins_v = 0.0, ins_f = 0.0, tex_f = 0.0;
};

std::vector<std::vector<Excess>> level_excess(const ConfigurationSpace& space) {
  std::vector<std::vector<Excess>> excess(space.pass_count());
  for (std::size_t i = 0; i < space.pass_count(); ++i) {
    const VariantCost least = cheapest_drawing_level(space.passes()[i]);
    for (const VariantCost& cost : space.passes()[i].levels) {
      // A skipped level draws nothing; its entry is never used with a count.
      excess[i].push_back(
          cost.draws ? Excess{cost.ins_v - least.ins_v, cost.ins_f - least.ins_f, cost.tex_f - least.tex_f} : Excess{});
    }
  }
  return excess;
}

}  // namespace

std::optional<HistoryFit> fit_history(std::span<const ConfiguredSample> samples, const ConfigurationSpace& space,
                                      const PowerModel& prior, const Configuration& prior_configuration,
                                      ReuseCoefficients prior_reuse, const Configuration& express_at,
                                      const HistoryFitSettings& settings) {
  const PlatformProfile& profile = prior.profile();
  if (!(profile.range_w() > 0.0) || !space.contains(express_at)) return std::nullopt;
  std::vector<const ConfiguredSample*> usable;
  std::set<Configuration> configurations;
  for (const ConfiguredSample& s : samples) {
    if (!is_usable(s.sample) || !space.contains(s.configuration)) continue;
    usable.push_back(&s);
    configurations.insert(s.configuration);
  }
  if (usable.empty()) return std::nullopt;
  const std::vector<std::vector<Excess>> excess = level_excess(space);

  // Columns: (pass, term) for every pass that drew something, then chi and psi, in order of
  // pass index.
  struct PassColumns {
    bool seen = false;
    std::array<int, 3> column{-1, -1, -1};
  };
  std::vector<PassColumns> column_of;  // [PassIndex]
  for (const ConfiguredSample* s : usable) {
    for (const PassFrame& p : s->sample.passes) {
      if (column_of.size() <= p.pass) column_of.resize(static_cast<std::size_t>(p.pass) + 1);
      PassColumns& entry = column_of[p.pass];
      entry.seen = true;
      const double counts[3] = {p.counts.batches, p.counts.vertices, p.counts.fragments};
      for (int t = 0; t < 3; ++t) {
        if (counts[t] > 0.0) entry.column[t] = 0;
      }
    }
  }
  struct Column {
    PassIndex pass;
    int term;
  };
  std::vector<Column> columns;
  for (std::size_t pass = 0; pass < column_of.size(); ++pass) {
    for (int t = 0; t < 3; ++t) {
      if (column_of[pass].column[t] >= 0) {
        column_of[pass].column[t] = static_cast<int>(columns.size());
        columns.push_back({static_cast<PassIndex>(pass), t});
      }
    }
  }
  const auto chi_column = static_cast<Eigen::Index>(columns.size());
  const Eigen::Index psi_column = chi_column + 1;
  const Eigen::Index frame_column = psi_column + 1;  // the per-frame load (power_model.hpp)
  const Eigen::Index cols = frame_column + 1;
  const auto rows = static_cast<Eigen::Index>(usable.size());

  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(rows, cols);
  Eigen::VectorXd y(rows);
  for (Eigen::Index r = 0; r < rows; ++r) {
    const ConfiguredSample& s = *usable[static_cast<std::size_t>(r)];
    const LinearisedPower target = linearise_power(profile, s.sample.power_w);
    y(r) = target.weight * target.alpha;
    a(r, frame_column) = target.weight;
    for (const PassFrame& p : s.sample.passes) {
      const double x[3] = {p.counts.batches / profile.saturation_batches,
                           p.counts.vertices / profile.saturation_vertices,
                           p.counts.fragments / profile.saturation_fragments};
      const PassColumns& entry = column_of[p.pass];
      for (int t = 0; t < 3; ++t) {
        if (entry.column[t] >= 0) a(r, entry.column[t]) += target.weight * x[t];
      }
      const std::size_t i = p.pass;
      if (i >= space.pass_count()) continue;  // outside the space: no levels
      const Excess& d = excess[i][static_cast<std::size_t>(s.configuration[i])];
      a(r, chi_column) += target.weight * (d.ins_v * x[1] + d.ins_f * x[2]);
      a(r, psi_column) += target.weight * d.tex_f * x[2];
    }
  }

  // Prior: the previous model's costs, split into level-independent parts and chi, psi.
  const bool prior_levels = space.contains(prior_configuration);
  Eigen::VectorXd z_prior(cols);
  for (Eigen::Index c = 0; c < chi_column; ++c) {
    const auto& [pass, term] = columns[static_cast<std::size_t>(c)];
    const std::size_t i = pass;
    const PassCoefficients* k = prior.find(pass);
    double value = k ? (term == 0 ? k->k_b : term == 1 ? k->k_v : k->k_f) : 0.0;
    if (k && prior_levels && i < space.pass_count()) {
      const Excess& d = excess[i][static_cast<std::size_t>(prior_configuration[i])];
      if (term == 1) value -= prior_reuse.chi * d.ins_v;
      if (term == 2) value -= prior_reuse.chi * d.ins_f + prior_reuse.psi * d.tex_f;
    }
    z_prior(c) = std::max(0.0, value);
  }
  z_prior(chi_column) = prior_reuse.chi;
  z_prior(psi_column) = prior_reuse.psi;
  z_prior(frame_column) = prior.frame_alpha();

  // A ridge towards the prior, non-negative costs (ridge_nonnegative). The per-frame load is
  // not pulled towards its prior: what no count explains is the frame's own cost first, rather
  // than the cost of a pass that happens to draw every frame.
  const double strength = profile.costs ? settings.calibrated_ridge : settings.ridge;
  Eigen::VectorXd ridge = Eigen::VectorXd::Constant(cols, strength * strength * static_cast<double>(cols));
  ridge(frame_column) = settings.frame_ridge * settings.frame_ridge * static_cast<double>(cols);
  const Eigen::VectorXd unknowns = ridge_nonnegative(std::move(a), y, z_prior, ridge);

  HistoryFit fit{prior,
                 express_at,
                 {unknowns(chi_column), unknowns(psi_column)},
                 usable.size(),
                 configurations.size(),
                 static_cast<std::size_t>(cols)};
  for (std::size_t pass = 0; pass < column_of.size(); ++pass) {
    const PassColumns& entry = column_of[pass];
    if (!entry.seen) continue;
    const auto index = static_cast<PassIndex>(pass);
    PassCoefficients k;
    if (const PassCoefficients* previous = prior.find(index)) k = *previous;
    double* terms[3] = {&k.k_b, &k.k_v, &k.k_f};
    const Excess d = pass < space.pass_count() ? excess[pass][static_cast<std::size_t>(express_at[pass])] : Excess{};
    for (int t = 0; t < 3; ++t) {
      if (entry.column[t] < 0) continue;  // no data for this term: the prior's value stands
      *terms[t] = unknowns(entry.column[t]);
    }
    if (entry.column[1] >= 0) k.k_v += fit.reuse.chi * d.ins_v;
    if (entry.column[2] >= 0) k.k_f += fit.reuse.chi * d.ins_f + fit.reuse.psi * d.tex_f;
    fit.model.set(index, k);
  }
  fit.model.set_frame_alpha(unknowns(frame_column));
  return fit;
}

}  // namespace glbudget::model
