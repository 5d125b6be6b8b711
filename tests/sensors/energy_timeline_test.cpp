#include <catch2/catch.hpp>
#include <atomic>
#include <thread>

#include "glbudget/sensors/energy_timeline.hpp"

#include "nanoseconds.hpp"

using namespace glbudget::sensors;

TEST_CASE("an empty timeline knows nothing", "[timeline]") {
  EnergyTimeline timeline;
  CHECK_FALSE(timeline.energy_at(0, 10 * ms));
}

TEST_CASE("energy is interpolated between points and extrapolated past the last", "[timeline]") {
  EnergyTimeline timeline;
  timeline.publish({0, 0.0, 0});
  timeline.publish({10 * ms, 1.0, 0});
  timeline.publish({20 * ms, 3.0, 0});

  auto e = timeline.energy_at(15 * ms, 10 * ms);
  REQUIRE(e);
  CHECK(e->energy_j == Approx(2.0));
  e = timeline.energy_at(5 * ms, 10 * ms);
  REQUIRE(e);
  CHECK(e->energy_j == Approx(0.5));
  e = timeline.energy_at(25 * ms, 10 * ms);  // latest slope: 0.2 J/ms
  REQUIRE(e);
  CHECK(e->energy_j == Approx(4.0));
  e = timeline.energy_at(20 * ms, 0);  // exactly at the newest point
  REQUIRE(e);
  CHECK(e->energy_j == Approx(3.0));
}

TEST_CASE("a point too old to extrapolate from means a stale sensor", "[timeline]") {
  EnergyTimeline timeline;
  timeline.publish({0, 0.0, 0});
  timeline.publish({10 * ms, 1.0, 0});
  CHECK(timeline.energy_at(20 * ms, 10 * ms));
  CHECK_FALSE(timeline.energy_at(21 * ms, 10 * ms));
}

TEST_CASE("no slope is taken across a segment boundary", "[timeline]") {
  EnergyTimeline timeline;
  timeline.publish({0, 0.0, 0});
  timeline.publish({10 * ms, 5.0, 1});
  CHECK_FALSE(timeline.energy_at(15 * ms, 10 * ms));  // no rate known in segment 1 yet
  auto e = timeline.energy_at(10 * ms, 10 * ms);
  REQUIRE(e);
  CHECK(e->energy_j == 5.0);
  CHECK(e->segment == 1);
  CHECK_FALSE(timeline.energy_at(5 * ms, 10 * ms));  // inside the break: unknown
  e = timeline.energy_at(0, 10 * ms);                // the old segment's last point is still known
  REQUIRE(e);
  CHECK(e->segment == 0);
  timeline.publish({20 * ms, 6.0, 1});
  e = timeline.energy_at(25 * ms, 10 * ms);
  REQUIRE(e);
  CHECK(e->energy_j == Approx(6.5));
}

TEST_CASE("times older than the reader's look-back window are unknown", "[timeline]") {
  EnergyTimeline timeline;
  for (int i = 0; i < 200; ++i) timeline.publish({i * ms, i * 1.0, 0});
  CHECK_FALSE(timeline.energy_at(10 * ms, ms));
  auto e = timeline.energy_at(199 * ms - ms / 2, ms);
  REQUIRE(e);
  CHECK(e->energy_j == Approx(198.5));
}

TEST_CASE("a reader racing the writer always sees a consistent, rising curve", "[timeline]") {
  EnergyTimeline timeline;
  constexpr int points = 200000;
  std::atomic<bool> done{false};
  std::thread writer([&] {
    for (int i = 0; i < points; ++i) timeline.publish({i * ms, 2.0 * i, 0});
    done = true;
  });
  // Extrapolating to the end from whichever two points are newest gives E = 2 J/ms * t, unless
  // the reader mixes slots the writer was rewriting.
  const std::int64_t end = points * ms;
  int checked = 0;
  while (!done) {
    if (auto e = timeline.energy_at(end, end)) {
      REQUIRE(e->energy_j == Approx(2.0 * points));
      ++checked;
    }
  }
  writer.join();
  INFO(checked << " reads raced the writer");
  const auto last = timeline.energy_at(end, end);
  REQUIRE(last);
  CHECK(last->energy_j == Approx(2.0 * points));
}
