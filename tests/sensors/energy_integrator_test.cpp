#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "glbudget/sensors/energy_integrator.hpp"
#include "glbudget/sensors/energy_timeline.hpp"

#include "nanoseconds.hpp"

using namespace glbudget::sensors;

namespace {
Reading energy(double joules) { return Reading{ReadStatus::ok, ReadingKind::energy_j, joules, {}}; }
Reading power(double watts) { return Reading{ReadStatus::ok, ReadingKind::power_w, watts, {}}; }
Reading status(ReadStatus s) { return Reading{s, ReadingKind::energy_j, 0.0, "test"}; }
}  // namespace

TEST_CASE("energy counters are differenced from the first reading", "[integrator]") {
  EnergyIntegrator integrator;
  auto first = integrator.accept(0, energy(1000.0));
  REQUIRE(first.point);
  CHECK(first.point->energy_j == 0.0);
  auto second = integrator.accept(10 * ms, energy(1000.5));
  REQUIRE(second.point);
  CHECK(second.point->energy_j == Approx(0.5));
  CHECK(second.point->segment == first.point->segment);
  CHECK(integrator.faults().total() == 0);
}

TEST_CASE("power readings are integrated with the trapezoid rule", "[integrator]") {
  EnergyIntegrator integrator;
  integrator.accept(0, power(10.0));
  auto p = integrator.accept(100 * ms, power(30.0));  // mean 20 W over 0.1 s
  REQUIRE(p.point);
  CHECK(p.point->energy_j == Approx(2.0));
  // Zero power is a legitimate reading, not a fault.
  p = integrator.accept(200 * ms, power(0.0));
  REQUIRE(p.point);
  CHECK(p.point->energy_j == Approx(3.5));
  CHECK(integrator.faults().total() == 0);
}

TEST_CASE("NaN, infinity, negative and implausible samples are dropped and counted", "[integrator][faults]") {
  EnergyIntegrator integrator(IntegratorLimits{1000.0, 1'000 * ms});
  integrator.accept(0, power(10.0));
  const double bad[] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(), -1.0,
                        1000.5};
  std::int64_t t = 0;
  for (double value : bad) {
    const auto outcome = integrator.accept(t += 10 * ms, power(value));
    CHECK_FALSE(outcome.point);
    CHECK(outcome.fault == Fault::garbage);
  }
  CHECK(integrator.faults().garbage == 4);
  // The curve carries on from the last good sample, in the same segment.
  const auto good = integrator.accept(t += 10 * ms, power(10.0));
  REQUIRE(good.point);
  CHECK(good.point->segment == 0);
  CHECK(good.point->energy_j == Approx(10.0 * 0.05));
}

TEST_CASE("an energy counter that goes backwards starts a new segment", "[integrator][faults]") {
  EnergyIntegrator integrator;
  integrator.accept(0, energy(50.0));
  integrator.accept(10 * ms, energy(50.2));
  const auto back = integrator.accept(20 * ms, energy(49.0));
  CHECK(back.fault == Fault::backwards);
  REQUIRE(back.point);
  CHECK(back.point->segment == 1);
  CHECK(back.point->energy_j == Approx(0.2));  // no energy charged for the jump
  const auto next = integrator.accept(30 * ms, energy(49.1));
  REQUIRE(next.point);
  CHECK(next.point->energy_j == Approx(0.3));
  CHECK(integrator.faults().backwards == 1);
}

TEST_CASE("an energy jump implying implausible power is garbage", "[integrator][faults]") {
  EnergyIntegrator integrator(IntegratorLimits{500.0, 1'000 * ms});
  integrator.accept(0, energy(0.0));
  const auto jump = integrator.accept(10 * ms, energy(6.0));  // 600 W over 10 ms
  CHECK(jump.fault == Fault::garbage);
  REQUIRE(jump.point);
  CHECK(jump.point->energy_j == 0.0);
  CHECK(jump.point->segment == 1);
  // 499 W is still believed.
  const auto fine = integrator.accept(20 * ms, energy(6.0 + 4.99));
  REQUIRE(fine.point);
  CHECK(fine.point->energy_j == Approx(4.99));
}

TEST_CASE("an unchanged counter waits, then stalls after the timeout", "[integrator][faults]") {
  EnergyIntegrator integrator(IntegratorLimits{5000.0, 100 * ms});
  integrator.accept(0, energy(7.0));
  auto same = integrator.accept(50 * ms, energy(7.0));
  CHECK_FALSE(same.point);
  CHECK_FALSE(same.fault);
  same = integrator.accept(100 * ms, energy(7.0));
  CHECK(same.fault == Fault::stalled);
  CHECK(integrator.faults().stalled == 1);
  REQUIRE(same.point);
  CHECK(same.point->segment == 1);  // the stall's marker, a segment of its own
  // When it moves again the energy accumulated during the stall is not charged to anyone.
  const auto resumed = integrator.accept(150 * ms, energy(9.0));
  REQUIRE(resumed.point);
  CHECK(resumed.point->segment == 2);
  CHECK(resumed.point->energy_j == 0.0);
}

TEST_CASE("a silent source stalls; read errors and garbage reads are counted", "[integrator][faults]") {
  EnergyIntegrator integrator(IntegratorLimits{5000.0, 100 * ms});
  integrator.accept(0, power(5.0));
  CHECK_FALSE(integrator.accept(50 * ms, status(ReadStatus::no_new_data)).fault);
  const auto stall = integrator.accept(120 * ms, status(ReadStatus::no_new_data));
  CHECK(stall.fault == Fault::stalled);
  // The stall closes the segment at once: a marker opens the next one.
  REQUIRE(stall.point);
  CHECK(stall.point->segment == 1);
  CHECK(stall.point->t_ns == 120 * ms);
  const auto error = integrator.accept(130 * ms, status(ReadStatus::read_error));
  CHECK(error.fault == Fault::read_error);
  CHECK_FALSE(error.point);  // already broken
  CHECK(integrator.accept(140 * ms, status(ReadStatus::garbage)).fault == Fault::garbage);
  const FaultCounts& f = integrator.faults();
  CHECK(f.stalled == 1);
  CHECK(f.read_error == 1);
  CHECK(f.garbage == 1);
  CHECK(f.total() == 3);
  // After a vanished source comes back, integration restarts in a new segment, not the
  // marker's (marker and first point would make a flat stretch: zero watts over the outage).
  const auto back = integrator.accept(150 * ms, power(5.0));
  REQUIRE(back.point);
  CHECK(back.point->segment == 2);
}

TEST_CASE("samples a source discarded itself are counted with the reading", "[integrator][faults]") {
  EnergyIntegrator integrator;
  Reading r = power(3.0);
  r.discarded_garbage = 2;
  r.discarded_backwards = 1;
  r.detail = "bad lines";
  const auto outcome = integrator.accept(0, r);
  CHECK(outcome.point);
  CHECK(outcome.fault == Fault::garbage);
  CHECK(integrator.faults().garbage == 2);
  CHECK(integrator.faults().backwards == 1);
}

TEST_CASE("huge counters keep microjoule resolution", "[integrator][extremes]") {
  EnergyIntegrator integrator;
  const double big = 4.0e9;  // 4 GJ: a 64-bit µJ counter after years of uptime
  integrator.accept(0, energy(big));
  const auto p = integrator.accept(10 * ms, energy(big + 1e-3));
  REQUIRE(p.point);
  CHECK(p.point->energy_j == Approx(1e-3).epsilon(1e-3));
}

TEST_CASE("two readings at the same instant integrate nothing", "[integrator][extremes]") {
  EnergyIntegrator integrator;
  integrator.accept(5 * ms, power(10.0));
  const auto same = integrator.accept(5 * ms, power(20.0));
  CHECK_FALSE(same.point);
  CHECK_FALSE(same.fault);
}

TEST_CASE("a read error closes the segment at once", "[integrator][faults]") {
  EnergyIntegrator integrator;
  integrator.accept(0, energy(1.0));
  integrator.accept(10 * ms, energy(2.0));
  const auto error = integrator.accept(20 * ms, status(ReadStatus::read_error));
  REQUIRE(error.point);
  CHECK(error.point->segment == 1);
  CHECK(error.point->energy_j == Approx(1.0));
  const auto back = integrator.accept(30 * ms, energy(3.0));
  REQUIRE(back.point);
  CHECK(back.point->segment == 2);  // a segment of its own: the marker is a lone point
  CHECK(back.point->energy_j == Approx(1.0));
  const auto next = integrator.accept(40 * ms, energy(3.5));
  REQUIRE(next.point);
  CHECK(next.point->energy_j == Approx(1.5));
}

TEST_CASE("a source failing from its first read publishes nothing", "[integrator][faults]") {
  EnergyIntegrator integrator;
  const auto error = integrator.accept(0, status(ReadStatus::read_error));
  CHECK_FALSE(error.point);
  const auto first = integrator.accept(10 * ms, energy(4.0));
  REQUIRE(first.point);
  CHECK(first.point->segment == 0);
  CHECK(first.point->energy_j == 0.0);
}

TEST_CASE("no frame is charged across an outage, however the swaps fall around it", "[integrator][timeline][faults]") {
  // A counter rising at 5 W that vanishes from 20 to 60 ms. A swap during the outage, or just
  // after the source returns (one good sample: no rate yet), has no energy; from the second
  // good sample on, the curve is exact again. Before the fix, the marker and the first good
  // sample shared a segment and made a zero-watt stretch: a frame from 65 to 68 ms read
  // 0 W and the next one far too much (seen as 8.3 W for 5 W under load).
  EnergyIntegrator integrator;
  EnergyTimeline timeline;
  auto feed = [&](std::int64_t t_ns, const Reading& r) {
    if (const auto outcome = integrator.accept(t_ns, r); outcome.point) timeline.publish(*outcome.point);
  };
  auto counter = [](std::int64_t t_ns) { return energy(5.0 * static_cast<double>(t_ns) * 1e-9); };
  for (std::int64_t t = 0; t <= 20 * ms; t += 10 * ms) feed(t, counter(t));
  feed(25 * ms, status(ReadStatus::read_error));
  const std::int64_t extrapolate = 100 * ms;
  CHECK_FALSE(timeline.energy_at(30 * ms, extrapolate));  // past the marker: no old slope
  CHECK_FALSE(timeline.energy_at(22 * ms, extrapolate));  // between last sample and marker
  feed(60 * ms, counter(60 * ms));
  CHECK_FALSE(timeline.energy_at(65 * ms, extrapolate));  // one good sample: no rate yet
  CHECK_FALSE(timeline.energy_at(40 * ms, extrapolate));  // inside the outage
  feed(70 * ms, counter(70 * ms));
  const auto a = timeline.energy_at(65 * ms, extrapolate), b = timeline.energy_at(78 * ms, extrapolate);
  REQUIRE(a);
  REQUIRE(b);
  CHECK(a->segment == b->segment);
  CHECK((b->energy_j - a->energy_j) / 13e-3 == Approx(5.0).epsilon(1e-9));
  const auto before = timeline.energy_at(10 * ms, extrapolate);
  REQUIRE(before);
  CHECK(before->segment != a->segment);  // never differenced across the outage
}
