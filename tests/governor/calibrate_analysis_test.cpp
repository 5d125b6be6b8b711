// The analysis of `glbudget calibrate` on synthetic sweeps: the plateau rule at its extremes.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "glbudget/analysis/calibration.hpp"

using namespace glbudget::model;
using namespace glbudget::analysis;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kIdle = 10.0;

// Counts doubling from `first`, as a sweep steps them.
std::vector<CalibrationPoint> sweep(double first, int steps, const std::function<double(double)>& power) {
  std::vector<CalibrationPoint> points;
  for (int i = 0; i < steps; ++i) {
    const double count = first * std::pow(2.0, i);
    points.push_back({count, power(count)});
  }
  return points;
}

// A paced frame: power rises with the busy share of the period until the frame fills it.
double hinge(double count, double knee = 1e5, double plateau = 22.0) {
  return kIdle + (plateau - kIdle) * std::min(count / knee, 1.0);
}

// Deterministic noise in [-amplitude, amplitude].
struct Noise {
  std::uint32_t state = 12345;
  double operator()(double amplitude) {
    state = state * 1664525u + 1013904223u;
    return amplitude * (2.0 * (state >> 8) / double(1u << 24) - 1.0);
  }
};

}  // namespace

TEST_CASE("a paced curve saturates just below its knee", "[model][calibration]") {
  const auto points = sweep(16, 16, [](double c) { return hinge(c); });  // 16 .. 524288
  const Saturation s = find_saturation(points, kIdle, 12.0);
  CHECK(s.kind == SaturationKind::saturated);
  CHECK(s.plateau_w == Approx(22.0));
  // 95 % of the rise lies between the steps at 65536 (65 %) and 131072 (100 %).
  CHECK(s.count > 65536);
  CHECK(s.count < 131072);
}

TEST_CASE("the model's own curve saturates near k c / B = ln 20", "[model][calibration]") {
  const double tau = 1000.0;
  const auto points = sweep(16, 18, [&](double c) { return kIdle + 12.0 * -std::expm1(-c / tau); });
  const Saturation s = find_saturation(points, kIdle, 12.0);
  CHECK(s.kind == SaturationKind::saturated);
  // Doubling steps bracket 3 tau = 3000 between 2048 and 4096; interpolation lands inside.
  CHECK(s.count > 2048);
  CHECK(s.count < 4096);
  CHECK(s.count == Approx(3.0 * tau).epsilon(0.25));
}

TEST_CASE("a flat curve is flat, and says so with its largest count", "[model][calibration]") {
  const auto points = sweep(16, 10, [](double) { return kIdle + 0.05; });
  const Saturation s = find_saturation(points, kIdle, 12.0);
  CHECK(s.kind == SaturationKind::flat);
  CHECK(s.count == 16 * 512);
  // Flat at idle with no range at all (every sweep flat): still flat, never a division by 0.
  CHECK(find_saturation(points, kIdle + 0.05, 0.0).kind == SaturationKind::flat);
}

TEST_CASE("a curve already at its plateau at the first step", "[model][calibration]") {
  const auto points = sweep(16, 6, [](double) { return 22.0; });
  const Saturation s = find_saturation(points, kIdle, 12.0);
  CHECK(s.kind == SaturationKind::saturated_at_start);
  CHECK(s.count == 16);
}

TEST_CASE("a noisy curve: the fit pools the noise, the plateau ignores one lucky step", "[model][calibration]") {
  Noise noise;
  const auto points = sweep(16, 18, [&](double c) { return hinge(c) + noise(0.7); });
  const Saturation s = find_saturation(points, kIdle, 12.0);
  CHECK(s.kind == SaturationKind::saturated);
  CHECK(s.plateau_w == Approx(22.0).margin(0.7));
  CHECK(s.count > 0.5e5);
  CHECK(s.count < 2e5);

  // One high step at the end (a step the machine happened to leave alone) moves nothing.
  auto blip = sweep(16, 15, [](double c) { return hinge(c); });
  blip.push_back({blip.back().count * 2, 24.5});
  const Saturation with_blip = find_saturation(blip, kIdle, 12.0);
  CHECK(with_blip.kind == SaturationKind::saturated);
  CHECK(with_blip.plateau_w == Approx(22.0));
  CHECK(with_blip.count ==
        Approx(find_saturation(sweep(16, 16, [](double c) { return hinge(c); }), kIdle, 12.0).count));
  // Two are a rise.
  blip.push_back({blip.back().count * 2, 24.5});
  CHECK(find_saturation(blip, kIdle, 12.0).kind == SaturationKind::still_rising);
}

TEST_CASE("a curve that never saturates gives its largest count as a lower bound", "[model][calibration]") {
  const auto points = sweep(16, 12, [](double c) { return kIdle + 1e-3 * c; });
  const Saturation s = find_saturation(points, kIdle, 40.0);
  CHECK(s.kind == SaturationKind::still_rising);
  CHECK(s.count == 16 * 2048);
}

TEST_CASE("a curve that creeps on once frames are late is frame-limited", "[model][calibration]") {
  // Paced at 30 fps with a knee at 1e5 batches; past it, +1.5 W a doubling (llvmpipe's batches).
  auto points = sweep(16, 16, [](double c) { return hinge(c) + (c > 1e5 ? 1.5 * std::log2(c / 1e5) : 0.0); });
  const Saturation unflagged = find_saturation(points, kIdle, 15.0);
  CHECK(unflagged.kind == SaturationKind::still_rising);
  CHECK(unflagged.count == points.back().count);
  points[points.size() - 1].late = points[points.size() - 2].late = true;
  const Saturation s = find_saturation(points, kIdle, 15.0);
  CHECK(s.kind == SaturationKind::frame_limited);
  CHECK(s.count > 131072);  // 95 % of the level it reached: beyond the knee, short of the end
  CHECK(s.count < points.back().count);
}

TEST_CASE("NaN samples and unusable counts are dropped, not averaged", "[model][calibration]") {
  auto points = sweep(16, 16, [](double c) { return hinge(c); });
  const Saturation clean = find_saturation(points, kIdle, 12.0);
  points.push_back({4096, kNaN});
  points.push_back({kNaN, 15.0});
  points.push_back({0.0, 30.0});
  points.push_back({-5.0, 30.0});
  points.push_back({1e6, std::numeric_limits<double>::infinity()});
  points.insert(points.begin(), {2e6, kNaN});  // out of order, too
  const Saturation dirty = find_saturation(points, kIdle, 12.0);
  CHECK(dirty.kind == clean.kind);
  CHECK(dirty.count == Approx(clean.count));
  CHECK(dirty.plateau_w == Approx(clean.plateau_w));

  const std::vector<CalibrationPoint> only_nan = {{16, kNaN}, {32, kNaN}};
  CHECK(find_saturation(only_nan, kIdle, 12.0).kind == SaturationKind::no_data);
  CHECK(std::isnan(find_saturation({}, kIdle, 12.0).count));
  CHECK(std::isnan(plateau_power({})));
}

TEST_CASE("huge counts and a single step", "[model][calibration]") {
  const auto huge = sweep(1e9, 12, [](double c) { return hinge(c, 1e11, 300.0); });
  const Saturation s = find_saturation(huge, kIdle, 290.0);
  CHECK(s.kind == SaturationKind::saturated);
  CHECK(s.count > 6.4e10);
  CHECK(s.count < 1.3e11);
  const std::vector<CalibrationPoint> one = {{1000, 20.0}};
  CHECK(find_saturation(one, kIdle, 10.0).kind == SaturationKind::still_rising);
}

TEST_CASE("the isotonic fit is non-decreasing and keeps increasing curves", "[model][calibration]") {
  const std::vector<CalibrationPoint> points = {{1, 10}, {2, 14}, {4, 12}, {8, 13}, {16, 20}};
  const MonotoneCurve fit = monotone_fit(points);
  REQUIRE(fit.power_w.size() == 5);
  CHECK(fit.power_w[0] == 10);
  CHECK(fit.power_w[1] == Approx(13));  // 14, 12, 13 pooled
  CHECK(fit.power_w[3] == Approx(13));
  CHECK(fit.power_w[4] == 20);
  CHECK(plateau_power(points) == 13);  // the median of 12, 13, 20
}

TEST_CASE("a calibration becomes a profile that loads", "[model][calibration]") {
  CalibrationMeasurements m;
  m.idle_w = kIdle;
  m.batches = {sweep(16, 16, [](double c) { return hinge(c, 1e5, 22.0); }), true};
  m.vertices = {sweep(1024, 16, [](double c) { return hinge(c, 4e6, 23.0); }), true};
  m.fragments = {sweep(65536, 10, [](double c) { return hinge(c, 8e6, 21.0); }), true};
  const CalibrationResult r = calibrate_profile(m);
  CHECK(r.defaults.empty());
  CHECK(r.profile.p_min_w == kIdle);
  CHECK(r.profile.p_max_w == Approx(23.0));
  CHECK(r.p_max_from == "vertices");
  CHECK(r.profile.saturation_batches == Approx(r.batches.count));
  CHECK(r.profile.saturation_vertices > 2e6);
  CHECK(r.profile.saturation_vertices < 4e6 * 1.01);
  CHECK(r.fragments.kind == SaturationKind::saturated);
  const PlatformProfile loaded = parse_platform_profile(platform_profile_to_json(r.profile), "test");
  CHECK(loaded.p_min_w < loaded.p_max_w);
  CHECK(loaded.saturation_batches == Approx(r.profile.saturation_batches));
  CHECK(loaded.saturation_fragments > 0);
}

TEST_CASE("an interrupted calibration keeps what it measured and names the defaults", "[model][calibration]") {
  const PlatformProfile defaults;
  CalibrationMeasurements m;
  m.idle_w = kIdle;
  m.batches = {sweep(16, 16, [](double c) { return hinge(c); }), true};
  m.vertices = {sweep(1024, 4, [](double c) { return hinge(c, 4e6); }), false};  // cut off while rising
  const CalibrationResult r = calibrate_profile(m);
  CHECK(r.profile.p_min_w == kIdle);
  CHECK(r.profile.p_max_w == Approx(22.0));
  CHECK(r.profile.saturation_batches == Approx(r.batches.count));
  CHECK(r.profile.saturation_vertices == defaults.saturation_vertices);
  CHECK(r.profile.saturation_fragments == defaults.saturation_fragments);
  CHECK(r.defaults == std::vector<std::string>{"saturation.vertices", "saturation.fragments"});

  // Interrupted before anything: every field is a default, and it says so.
  const CalibrationResult nothing = calibrate_profile({});
  CHECK(nothing.defaults.size() == 5);
  CHECK(nothing.profile.p_max_w == defaults.p_max_w);

  // Only the idle step: P_m measured, P_M a default.
  CalibrationMeasurements idle_only;
  idle_only.idle_w = kIdle;
  const CalibrationResult idle = calibrate_profile(idle_only);
  CHECK(idle.defaults.front() == "p_max_w");
  CHECK(idle.profile.p_min_w == kIdle);
}

TEST_CASE("a step's power is its frames' energy over their time", "[model][calibration]") {
  auto frame = [](double time_ns, double power_w, double seconds, double batches) {
    LoggedFrame f;
    f.time_ns = time_ns;
    f.power_w = power_w;
    f.energy_j = power_w * seconds;
    LoggedPass p;
    p.counts = {batches, 3 * batches, 0.0};
    f.passes.push_back(p);
    return f;
  };
  std::vector<LoggedFrame> frames = {
      frame(100, 99.0, 1.0, 7),     // before the step
      frame(200, 10.0, 0.9, 16),    // 0.9 s at 10 W
      frame(300, 40.0, 0.1, 16),    // 0.1 s at 40 W: a plain mean of powers would say 25 W
      frame(350, kNaN, 0.1, 16),    // a dropped sensor sample
      frame(400, 20.0, 1.0, kNaN),  // counts lost with the last frames
      frame(500, 99.0, 1.0, 7),     // after it
  };
  frames[3].energy_j = kNaN;
  const StepMeasurement m = measure_step(frames, 150, 400);
  CHECK(m.frames == 3);
  CHECK(m.power_w == Approx((9.0 + 4.0 + 20.0) / 2.0));
  CHECK(m.batches == 16);
  CHECK(m.vertices == 48);
  CHECK(m.fragments == 0);
  const StepMeasurement empty = measure_step(frames, 1000, 2000);
  CHECK(empty.frames == 0);
  CHECK(std::isnan(empty.power_w));
  CHECK(std::isnan(empty.batches));
}
