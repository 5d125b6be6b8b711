#include <catch2/catch.hpp>

#include "glbudget/model/configuration_space.hpp"

using namespace glbudget::model;

// A probe's error is a pass's only where the probed (or shown) configuration leaves every other
// pass at its best: the shown configuration's error is taken for a pass's cheapest level only
// then, and calibrate --app's level ratios only from such streams.
TEST_CASE("only_pass_changed names the one pass off its best, and no pass when several are", "[model]") {
  CHECK(only_pass_changed({}) == -1);
  CHECK(only_pass_changed({0, 0, 0, 0, 0, 0}) == -1);
  CHECK(only_pass_changed({2, 0, 0, 0, 0, 0}) == 0);
  CHECK(only_pass_changed({0, 0, 0, 0, 2, 0}) == 4);
  CHECK(only_pass_changed({0, 0, 0, 0, 0, 1}) == 5);
  CHECK(only_pass_changed({1, 0, 0, 0, 0, 2}) == -1);
  // An odd number of passes changed: the demo's Sponza shown at 2:2:1:2:2:0 once had its whole
  // error (0.10) taken for metals' cheapest level (pass 4), which ranked every configuration
  // with cheap metals far too high (rho 0.70 over the 729).
  CHECK(only_pass_changed({2, 2, 1, 0, 0, 0}) == -1);
  CHECK(only_pass_changed({2, 2, 1, 2, 2, 0}) == -1);
  CHECK(only_pass_changed({1, 1, 1, 1, 1, 1}) == -1);
}
