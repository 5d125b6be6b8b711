#pragma once
// The analysis behind `glbudget calibrate` (paper §5.2): P_m from frames that draw nothing, then
// one sweep per count (batches, vertices, fragments) with the others held small, the count
// doubling from step to step.
//
// The sweeps are paced (30 fps by default, the paper's rate): the paper's model is of a fixed
// frame rate, where "power savings are achieved when the GPU is idle between consecutive
// frames" (§5.1). Power then rises with the count while the frame fits its period and stays flat
// once it does not, so a sweep ends two steps after its frames fall under half the rate (or at
// a cap). Unpaced, the app loop keeps the renderer busy whatever it draws: with llvmpipe and the
// cpu sensor the batches curve was flat (18.5-24.7 W, no trend, from 1 to 16384 batches), so
// there was nothing to saturate.
//
// The rule. A saturation count is where the curve first reaches 95 % of its rise from P_m to its
// plateau. A measured curve never quite stops rising, so some share must stand for "saturates
// the GPU"; under the model's own curve P = P_m + (P_M - P_m)(1 - e^{-k c/B}) 95 % is
// k c/B = ln 20 ~ 3, and on a paced curve it falls just below the knee. Where the noise is wider
// than the last 5 %, the threshold is the plateau less twice the noise instead (on a loaded
// 2-core machine ~1 W of a 16 W rise): a step within the noise of the plateau cannot be told
// from it, and a threshold inside the noise would pick whichever plateau step read high.
//  - The curve is made non-decreasing (an isotonic fit, pool-adjacent-violators): power cannot
//    fall as a frame draws more, so a dip is noise, pooled with its neighbours. The crossing is
//    interpolated linearly in the count between the two fitted steps around it.
//  - The plateau is the median of the last three steps' powers: a sweep runs past its knee, so
//    they lie on it, and a median ignores the one lucky step that would set a maximum.
//  - The noise is the rms of the steps about the fit in the curve's upper half.
//  - A sweep has flattened when its last two steps gained (from the fit three steps from the
//    end to the plateau) less than 2 % of the rise, or less than twice the noise where that is
//    larger (a 2 % rule alone would call most saturated sweeps on a noisy machine still rising).
//    One that has not flattened is still rising: its count is a lower bound, its largest.
//  - Unless its last two steps were late (frames at under half the paced rate): then it is
//    frame-limited, and its count is still the crossing, of the level it reached.
//    Past the frame rate, a renderer may find more to run in parallel and power creep on (with
//    llvmpipe, batches: +1-2 W a doubling after a 12 W rise), but a governor keeps frames paced,
//    and that range is not the one it predicts.

#include <cstddef>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "glbudget/analysis/frame_log.hpp"
#include "glbudget/model/platform_profile.hpp"

namespace glbudget::analysis {

// What one step's frames measured: the frames presented after start_ns up to end_ns.
struct StepMeasurement {
  // Mean power: the frames' energy over their time (not a mean of per-frame powers, which
  // short frames would dominate). NaN when no frame had power.
  double power_w = std::numeric_limits<double>::quiet_NaN();
  // Per frame, summed over passes: the median over the frames where they were measured; NaN
  // when none was.
  double batches = std::numeric_limits<double>::quiet_NaN();
  double vertices = std::numeric_limits<double>::quiet_NaN();
  double fragments = std::numeric_limits<double>::quiet_NaN();
  std::size_t frames = 0;  // frames with power
};

StepMeasurement measure_step(std::span<const LoggedFrame> frames, double start_ns, double end_ns);

// One step of a sweep: the swept count per frame and the step's mean power.
struct CalibrationPoint {
  double count = 0.0;
  double power_w = 0.0;
  bool late = false;  // its frames ran at under half the paced rate
};

struct SaturationRule {
  double plateau_share = 0.95;    // the saturation count: where the curve reaches this share of its rise
  double flat_gain_share = 0.02;  // flattened: the last two steps gained less than this share of the rise
  double min_rise_share = 0.05;   // flat: rose less than this share of the profile's range
};

enum class SaturationKind {
  saturated,           // count: where the curve crossed plateau_share of its rise
  saturated_at_start,  // already there at the first step; count: the first (an upper bound)
  frame_limited,       // not flat, but its last two steps were late; count: the crossing
  still_rising,        // no plateau in the counts measured; count: the largest (a lower bound)
  flat,                // never rose above the noise; count: the largest measured (a lower bound)
  no_data,             // no usable step; count: NaN
};

const char* to_string(SaturationKind kind);

struct Saturation {
  SaturationKind kind = SaturationKind::no_data;
  double count = std::numeric_limits<double>::quiet_NaN();
  double plateau_w = std::numeric_limits<double>::quiet_NaN();
};

// The curve's usable points (finite, count > 0), sorted by count, and their isotonic fit.
struct MonotoneCurve {
  std::vector<double> count;
  std::vector<double> power_w;  // non-decreasing
};
MonotoneCurve monotone_fit(std::span<const CalibrationPoint> curve);

// The median power of the curve's last three usable points (fewer when it has fewer); NaN if none.
double plateau_power(std::span<const CalibrationPoint> curve);

// range_w: P_M - P_m of the whole profile, against which a curve's rise is judged flat.
Saturation find_saturation(std::span<const CalibrationPoint> curve, double idle_w, double range_w,
                           const SaturationRule& rule = {});

struct SweepMeasurement {
  std::vector<CalibrationPoint> points;
  bool complete = false;  // false: interrupted before it saturated or reached its last step
};

// What a calibration measured; NaN or empty where a step never ran (an interrupted run).
struct CalibrationMeasurements {
  double idle_w = std::numeric_limits<double>::quiet_NaN();
  SweepMeasurement batches, vertices, fragments;
};

struct CalibrationResult {
  model::PlatformProfile profile;  // unmeasured fields keep PlatformProfile's defaults
  Saturation batches, vertices, fragments;
  std::string p_max_from;             // the sweep whose plateau gave P_M ("" when none did)
  std::vector<std::string> defaults;  // fields left at their defaults: "p_min_w", "saturation.batches", ...
};

// P_m: the idle power; P_M: the highest plateau of the sweeps, when above P_m; B, V, F: each
// sweep's saturation count. A count stays at its default when its sweep has no data, or was
// interrupted while still rising or flat (its largest count then says nothing).
CalibrationResult calibrate_profile(const CalibrationMeasurements& measured, const SaturationRule& rule = {});

}  // namespace glbudget::analysis
