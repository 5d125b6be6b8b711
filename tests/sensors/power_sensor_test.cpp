#include <catch2/catch.hpp>
#include <atomic>
#include <cmath>
#include <thread>

#include "glbudget/sensors/sensor.hpp"
#include "swap_until_valid.hpp"

using namespace glbudget::sensors;
using namespace std::chrono_literals;
using glbudget::sensors::testing::swap_until_valid;

namespace {

// A source whose counter rises at a constant power, and which can be made to misbehave.
class ConstantPowerSource final : public Source {
 public:
  enum class Mode { normal, nan, vanished };
  ConstantPowerSource(double watts, std::atomic<Mode>& mode) : watts_(watts), mode_(mode) {}
  std::string_view name() const override { return "constant"; }
  std::string description() const override { return "test source"; }
  bool is_estimate() const override { return true; }
  Reading read(std::int64_t now_ns) override {
    switch (mode_.load()) {
      case Mode::nan:
        return Reading{ReadStatus::ok, ReadingKind::energy_j, NAN, {}};
      case Mode::vanished:
        return Reading{ReadStatus::read_error, ReadingKind::energy_j, 0, "gone"};
      case Mode::normal:
        break;
    }
    return Reading{ReadStatus::ok, ReadingKind::energy_j, watts_ * static_cast<double>(now_ns) * 1e-9, {}};
  }

 private:
  double watts_;
  std::atomic<Mode>& mode_;
};

SamplerOptions fast() {
  SamplerOptions options;
  options.period = 1ms;
  return options;
}

}  // namespace

TEST_CASE("per-frame energies add up to the energy of the whole run", "[sensor]") {
  std::atomic mode{ConstantPowerSource::Mode::normal};
  PowerSensor sensor(std::make_unique<ConstantPowerSource>(12.0, mode), fast());
  CHECK(sensor.name() == "constant");
  CHECK(sensor.is_estimate());

  const FrameEnergy first = sensor.on_swap(monotonic_now_ns());
  CHECK_FALSE(first.valid);  // no interval before the first swap
  CHECK(std::isnan(first.energy_j));
  REQUIRE(swap_until_valid(sensor));

  std::int64_t previous = monotonic_now_ns();
  sensor.on_swap(previous);
  double total_j = 0.0, valid_seconds = 0.0;
  int valid = 0;
  for (int frame = 0; frame < 40; ++frame) {
    std::this_thread::sleep_for(3ms);
    const std::int64_t now = monotonic_now_ns();
    const FrameEnergy e = sensor.on_swap(now);
    CHECK(e.sensor == "constant");
    CHECK(e.estimate);
    if (e.valid) {
      ++valid;
      total_j += e.energy_j;
      valid_seconds += static_cast<double>(now - previous) * 1e-9;
      CHECK(e.mean_power_w == Approx(12.0).epsilon(1e-6));
    }
    previous = now;
  }
  CHECK(valid == 40);
  CHECK(total_j == Approx(12.0 * valid_seconds).epsilon(1e-6));
  CHECK(sensor.faults().total() == 0);
}

TEST_CASE("garbage samples are counted in the frames that see them", "[sensor][faults]") {
  std::atomic mode{ConstantPowerSource::Mode::normal};
  PowerSensor sensor(std::make_unique<ConstantPowerSource>(5.0, mode), fast());
  REQUIRE(swap_until_valid(sensor));
  mode = ConstantPowerSource::Mode::nan;
  while (sensor.faults().garbage < 3) std::this_thread::sleep_for(1ms);
  mode = ConstantPowerSource::Mode::normal;
  std::this_thread::sleep_for(5ms);
  const FrameEnergy e = sensor.on_swap(monotonic_now_ns());
  CHECK(e.dropped_samples > 0);
  CHECK(e.dropped_samples == sensor.faults().garbage);
  // NaN in an energy counter is dropped without breaking continuity: the frame is still valid.
  CHECK(e.valid);
  CHECK(e.mean_power_w == Approx(5.0).epsilon(1e-6));
  std::this_thread::sleep_for(5ms);
  CHECK(sensor.on_swap(monotonic_now_ns()).dropped_samples == 0);
}

TEST_CASE("a vanished sensor yields invalid frames, and valid ones when it returns", "[sensor][faults]") {
  std::atomic mode{ConstantPowerSource::Mode::normal};
  PowerSensor sensor(std::make_unique<ConstantPowerSource>(5.0, mode), fast());
  REQUIRE(swap_until_valid(sensor));

  mode = ConstantPowerSource::Mode::vanished;
  while (sensor.faults().read_error == 0) std::this_thread::sleep_for(1ms);
  // The first failed read closes the curve: no frame is charged from it any more.
  const FrameEnergy gone = sensor.on_swap(monotonic_now_ns());
  CHECK_FALSE(gone.valid);
  CHECK(gone.dropped_samples > 0);
  CHECK(gone.dropped_samples <= sensor.faults().read_error);
  std::this_thread::sleep_for(10ms);
  CHECK_FALSE(sensor.on_swap(monotonic_now_ns()).valid);

  mode = ConstantPowerSource::Mode::normal;
  REQUIRE(swap_until_valid(sensor));
  std::this_thread::sleep_for(5ms);
  const FrameEnergy back = sensor.on_swap(monotonic_now_ns());
  CHECK(back.valid);
  CHECK(back.mean_power_w == Approx(5.0).epsilon(1e-6));
}

TEST_CASE("a swap at the same instant as the previous one is not a frame", "[sensor][extremes]") {
  std::atomic mode{ConstantPowerSource::Mode::normal};
  PowerSensor sensor(std::make_unique<ConstantPowerSource>(5.0, mode), fast());
  REQUIRE(swap_until_valid(sensor));
  const std::int64_t now = monotonic_now_ns();
  sensor.on_swap(now);
  const FrameEnergy again = sensor.on_swap(now);
  CHECK_FALSE(again.valid);
}
