// The rule that holds an end of a share's range through the model's implausible changes
// (loop/range_end_hold.hpp), at its edges.
#include <catch2/catch.hpp>
#include <limits>

#include "glbudget/loop/range_end_hold.hpp"

using glbudget::loop::RangeEndHold;

TEST_CASE("range end hold: a change beyond a quarter of the end's power above idle is carried back", "[loop][range]") {
  RangeEndHold hold;
  // Hall at 40 %: a refit moved the best 14 W down, 25.6 W above idle before it.
  CHECK(hold.observe(0, -14.0, false, 25.6));
  CHECK(hold.carried_w(0) == Approx(14.0));
  // Just under a quarter: the model learning, it stands; what was carried stays.
  CHECK_FALSE(hold.observe(0, 0.24 * 25.6, false, 25.6));
  CHECK(hold.carried_w(0) == Approx(14.0));
  // Exactly a quarter stands too; just over it is carried back, upwards as downwards.
  CHECK_FALSE(hold.observe(0, 0.25 * 8.0, false, 8.0));
  CHECK(hold.observe(0, 2.01, false, 8.0));
  CHECK(hold.carried_w(0) == Approx(11.99));
}

TEST_CASE("range end hold: a fit that sees the top drawn clears what it carried", "[loop][range]") {
  RangeEndHold hold;
  // Valley at 60 %: the best up 18.9 W at one refit, 11.2 W above idle before it.
  REQUIRE(hold.observe(0, 18.9, false, 11.2));
  CHECK(hold.carried_w(0) == Approx(-18.9));
  // Drawn again: however far the model moved it, its own prediction holds.
  CHECK_FALSE(hold.observe(0, 50.0, true, 11.2));
  CHECK(hold.carried_w(0) == 0.0);
}

TEST_CASE("range end hold: an index that is not the top any more carries nothing", "[loop][range]") {
  RangeEndHold hold;
  REQUIRE(hold.observe(3, 9.0, false, 6.0));
  hold.keep_only(3);
  CHECK(hold.carried_w(3) == Approx(-9.0));
  hold.keep_only(5);  // the top moved from 3 to 5 (estimates tied)
  CHECK(hold.carried_w(3) == 0.0);
  REQUIRE(hold.observe(5, -3.0, false, 6.0));
  hold.clear();
  CHECK(hold.carried_w(5) == 0.0);
}

TEST_CASE("range end hold: no change or no power above idle known holds nothing", "[loop][range][extremes]") {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  RangeEndHold hold;
  CHECK_FALSE(hold.observe(0, nan, false, 10.0));
  CHECK_FALSE(hold.observe(0, inf, false, 10.0));
  CHECK_FALSE(hold.observe(0, 100.0, false, nan));
  CHECK_FALSE(hold.observe(0, 100.0, false, inf));
  CHECK_FALSE(hold.observe(0, 100.0, false, 0.0));   // predicted at idle: nothing to scale by
  CHECK_FALSE(hold.observe(0, 100.0, false, -3.0));  // under idle: a prediction gone wrong
  CHECK(hold.carried_w(0) == 0.0);
  // The least power above idle: any change beyond a quarter of it is carried.
  CHECK(hold.observe(1, 1e-9, false, 1e-12));
  CHECK(hold.carried_w(1) == Approx(-1e-9));
}
