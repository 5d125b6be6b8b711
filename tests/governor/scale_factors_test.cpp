// ScaleFactors (governor/loop/scale_factors.hpp) and the error table's factors per render-scale
// level: the other passes' errors weighed by a factor fitted from what probes measure of the
// configurations shown.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "glbudget/loop/error_table.hpp"
#include "glbudget/loop/scale_factors.hpp"
#include "glbudget/model/configuration_space.hpp"

using glbudget::loop::ErrorTable;
using glbudget::loop::ScaleFactors;
using glbudget::model::Configuration;
using glbudget::model::ConfigurationSpace;
using glbudget::model::PassVariants;

namespace {
constexpr double kNotANumber = std::numeric_limits<double>::quiet_NaN();

ConfigurationSpace space_with_a_scale_pass() {
  std::vector<PassVariants> passes;
  for (const char* name : {"shading", "resolution", "shadows"}) {
    PassVariants pass{name, {}, {}};
    for (int l = 0; l < 3; ++l) pass.levels.push_back({});
    passes.push_back(pass);
  }
  return ConfigurationSpace(passes);
}
}  // namespace

TEST_CASE("scale factors: the least-squares factor per level, shrunk toward 1, held in [0.5, 1.5]",
          "[loop][scale-factors]") {
  ScaleFactors none;
  CHECK(none.factors(3) == std::vector<double>{1.0, 1.0, 1.0});
  CHECK(none.factors(0).empty());

  // Without the prior, probes whose others sum to 0.01-0.04 and whose measurement is the scale's
  // own error plus 0.8 of them: exactly 0.8 at level 1; level 2 never measured stays 1.
  ScaleFactors exact(16.0, 0.0);
  for (double others : {0.01, 0.02, 0.03, 0.04}) exact.add(1, 0.05, others, 0.05 + 0.8 * others);
  CHECK(exact.probes() == 4);
  const std::vector<double> m = exact.factors(3);
  CHECK(m[0] == 1.0);
  CHECK(m[1] == Approx(0.8).epsilon(1e-12));
  CHECK(m[2] == 1.0);

  // The prior: four probes' worth of 1 against the probes' faded weight.
  ScaleFactors shrunk(16.0, 4.0);
  for (int k = 0; k < 4; ++k) shrunk.add(2, 0.02, 0.02, 0.02 + 0.5 * 0.02 + 1e-12);
  double weight = 0.0;
  for (int k = 0; k < 4; ++k) weight = (1.0 - 1.0 / 16.0) * weight + 1.0;
  CHECK(shrunk.factors(3)[2] == Approx(1.0 + (0.5 - 1.0) * weight / (weight + 4.0)).epsilon(1e-6));

  // Held in [0.5, 1.5] before the prior.
  ScaleFactors far(16.0, 0.0);
  far.add(1, 0.0, 0.01, 0.1);   // ten times the others
  far.add(2, 0.05, 0.01, 0.0);  // under the scale's own error
  CHECK(far.factors(3)[1] == 1.5);
  CHECK(far.factors(3)[2] == 0.5);

  // Ignored: level 0, others summing to 0, values not finite or negative.
  ScaleFactors ignored(16.0, 0.0);
  ignored.add(0, 0.0, 0.01, 0.005);
  ignored.add(1, 0.02, 0.0, 0.03);
  ignored.add(1, kNotANumber, 0.01, 0.03);
  ignored.add(1, 0.02, 0.01, kNotANumber);
  ignored.add(1, 0.02, 0.01, -0.1);
  ignored.add(-1, 0.02, 0.01, 0.03);
  CHECK(ignored.probes() == 0);
  CHECK(ignored.factors(3) == std::vector<double>{1.0, 1.0, 1.0});

  // A scene that changes: the faded sums follow the newer factor.
  ScaleFactors moving(4.0, 0.0);
  for (int k = 0; k < 20; ++k) moving.add(1, 0.01, 0.02, 0.01 + 1.2 * 0.02);
  for (int k = 0; k < 20; ++k) moving.add(1, 0.01, 0.02, 0.01 + 0.7 * 0.02);
  CHECK(moving.factors(2)[1] == Approx(0.7).margin(0.01));
}

TEST_CASE("error table: scale factors weigh the other passes' errors, estimate and estimate_all alike",
          "[loop][scale-factors]") {
  const ConfigurationSpace space = space_with_a_scale_pass();
  ErrorTable table(space);
  for (std::size_t pass = 0; pass < 3; ++pass)
    for (int level = 1; level < 3; ++level) REQUIRE(table.set(pass, level, 0.01 * (pass + 1) * level));
  const Configuration c{2, 1, 1};  // shading 0.02, resolution 0.02, shadows 0.03
  CHECK(table.estimate(c) == Approx(0.07));
  CHECK(table.sum(c) == Approx(0.07));

  REQUIRE(table.set_scale_factors(1, {1.0, 0.5, 1.25}));
  CHECK(table.estimate(c) == Approx(0.02 + 0.5 * 0.05));
  CHECK(table.sum(c) == Approx(0.07));  // the sum itself is unchanged
  CHECK(table.estimate(Configuration{2, 0, 1}) == Approx(0.05));  // the scale at its best: the sum
  CHECK(table.estimate(Configuration{0, 2, 0}) == Approx(0.04));  // the scale's own error alone
  CHECK(table.estimate(Configuration{1, 2, 2}) == Approx(0.04 + 1.25 * (0.01 + 0.06)));
  std::vector<double> all;
  table.estimate_all(all);
  REQUIRE(all.size() == space.size());
  for (std::size_t i = 0; i < space.size(); ++i) {
    INFO("configuration " << i);
    CHECK(all[i] == Approx(table.estimate(space.decode(i))).margin(1e-15));
  }
  CHECK(std::isnan(table.estimate(Configuration{0, 3, 0})));
  CHECK(std::isnan(table.estimate(Configuration{0, 0})));

  // Refused, and the factors in force kept: a pass outside the table, a count other than the
  // pass's levels, a factor that is not finite or is negative.
  CHECK_FALSE(table.set_scale_factors(3, {1.0, 1.0, 1.0}));
  CHECK_FALSE(table.set_scale_factors(1, {1.0, 0.5}));
  CHECK_FALSE(table.set_scale_factors(1, {1.0, kNotANumber, 1.0}));
  CHECK_FALSE(table.set_scale_factors(1, {1.0, -0.5, 1.0}));
  CHECK(table.estimate(c) == Approx(0.045));

  table.clear_scale_factors();
  CHECK(table.estimate(c) == Approx(0.07));
  table.estimate_all(all);
  CHECK(all[space.index_of(c)] == Approx(0.07));
}
