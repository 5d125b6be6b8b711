#include <catch2/catch.hpp>
#include <cmath>

#include "glbudget/model/additive_levels.hpp"

using namespace glbudget::model;

namespace {

ConfigurationSpace space_of(std::vector<std::size_t> levels) {
  std::vector<PassVariants> passes;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    PassVariants pass;
    pass.pass = "p" + std::to_string(i);
    pass.levels.assign(levels[i], VariantCost{});
    passes.push_back(pass);
  }
  return ConfigurationSpace(passes);
}

// A power with an interaction: levels of passes 0 and 1 together cost `coupling` more than
// their changes alone add up to.
double interacting(const Configuration& c, double coupling) {
  return 40.0 - 5.0 * c[0] - 3.0 * c[1] - 0.5 * c[2] + coupling * c[0] * c[1];
}

}  // namespace

TEST_CASE("make_additive_over_levels keeps the best and each level alone, and sums them elsewhere", "[model]") {
  const ConfigurationSpace space = space_of({3, 3, 2});
  std::vector<double> power(space.size());
  for (std::size_t i = 0; i < space.size(); ++i) power[i] = interacting(space.decode(i), 2.0);
  make_additive_over_levels(space, power);
  for (std::size_t i = 0; i < space.size(); ++i) {
    const Configuration c = space.decode(i);
    CHECK(power[i] == Approx(interacting(c, 0.0)));
    // The template for one configuration agrees with the table.
    CHECK(additive_over_levels(c, [](const Configuration& s) { return interacting(s, 2.0); }) == Approx(power[i]));
  }
  // The cheapest: 40 - 10 - 6 - 0.5, where the interacting model made it 8 W more.
  CHECK(power[space.index_of(space.cheapest())] == Approx(23.5));
}

TEST_CASE("make_additive_over_levels at its extremes", "[model]") {
  SECTION("one pass: every configuration is a level alone, nothing changes") {
    const ConfigurationSpace space = space_of({4});
    std::vector<double> power = {10.0, 9.0, 7.5, 7.0};
    make_additive_over_levels(space, power);
    CHECK(power == std::vector<double>{10.0, 9.0, 7.5, 7.0});
  }
  SECTION("a NaN level alone makes every configuration drawing it NaN, and no other") {
    const ConfigurationSpace space = space_of({2, 2});
    std::vector<double> power = {10.0, 8.0, std::nan(""), 1.0};  // 0:0, 0:1, 1:0, 1:1
    make_additive_over_levels(space, power);
    CHECK(power[0] == 10.0);
    CHECK(power[1] == 8.0);
    CHECK(std::isnan(power[2]));
    CHECK(std::isnan(power[3]));
  }
  SECTION("a NaN best makes every configuration NaN") {
    const ConfigurationSpace space = space_of({2, 2});
    std::vector<double> power = {std::nan(""), 8.0, 9.0, 1.0};
    make_additive_over_levels(space, power);
    for (double p : power) CHECK(std::isnan(p));
  }
  SECTION("a table of the wrong size is left as it is") {
    const ConfigurationSpace space = space_of({2, 2});
    std::vector<double> power = {10.0, 8.0, 9.0};
    make_additive_over_levels(space, power);
    CHECK(power == std::vector<double>{10.0, 8.0, 9.0});
  }
  SECTION("single-level indices follow the row-major order") {
    const ConfigurationSpace space = space_of({3, 2, 2});
    const auto single = single_level_indices(space);
    CHECK(single[0] == std::vector<std::size_t>{0, 4, 8});
    CHECK(single[1] == std::vector<std::size_t>{0, 2});
    CHECK(single[2] == std::vector<std::size_t>{0, 1});
  }
}

TEST_CASE("interaction_share: the model's interaction scaled towards the measured, never beyond it", "[model]") {
  CHECK(interaction_share(-8.0, -4.0) == Approx(0.5));  // the model doubles what was measured
  CHECK(interaction_share(4.0, 1.0) == Approx(0.25));
  CHECK(interaction_share(-2.0, -6.0) == 1.0);  // never amplified
  CHECK(interaction_share(-2.0, -2.0) == 1.0);
  CHECK(interaction_share(5.7, -3.4) == 0.0);  // turned round: the sum alone
  CHECK(interaction_share(-3.0, 0.0) == 0.0);
  CHECK(interaction_share(0.0, -3.0) == 0.0);  // nothing to scale
  CHECK(interaction_share(std::nan(""), -3.0) == 0.0);
  CHECK(interaction_share(-3.0, std::nan("")) == 0.0);
  CHECK(interaction_share(-3.0, -INFINITY) == 0.0);
}
