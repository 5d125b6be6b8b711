#include "options.hpp"

#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <mutex>
#include <optional>
#include <string_view>
#include <utility>

namespace glbudget {

namespace {
// Variables of the whole design (DESIGN.md), including those read by other parts of glbudget;
// anything else that starts with GLBUDGET_ is most likely a typo, worth a warning.
constexpr const char* kKnownVariables[] = {
    "GLBUDGET_POWER",
    "GLBUDGET_ERROR",
    "GLBUDGET_CONFIG",
    "GLBUDGET_SENSOR",
    "GLBUDGET_FPS",
    "GLBUDGET_LOG",
    "GLBUDGET_DUMP",
    "GLBUDGET_PROFILE",
    "GLBUDGET_SENSOR_PERIOD_MS",
    "GLBUDGET_SYSFS_ROOT",
    "GLBUDGET_NVML_LIBRARY",
    "GLBUDGET_INSTRUMENT",
    "GLBUDGET_FORCE",
    "GLBUDGET_FORCE_EVERY",
    "GLBUDGET_PROBE_PERIOD",
    "GLBUDGET_SELECT_FRAMES",
    "GLBUDGET_TRANSITION_S",
    "GLBUDGET_TRANSITION_ORDER",
    "GLBUDGET_FEEDBACK",
    "GLBUDGET_FEEDBACK_OWN",
    "GLBUDGET_LEVEL_INTERACTIONS",
    "GLBUDGET_ERROR_FEEDBACK",
    "GLBUDGET_PROBE_STRETCH",
    "GLBUDGET_PROBE_MAX_AGE_S",
    "GLBUDGET_KEEP_SHARE",
    "GLBUDGET_FIRST_SAVING_DISCOUNT",
    "GLBUDGET_SURPRISE_FLOOR",
    "GLBUDGET_EXPLORE_HELD",
    "GLBUDGET_MEASURED_AT_WINDOWS",
    "GLBUDGET_BEST_BAND",
    "GLBUDGET_REMEMBER_FRAMES",
    "GLBUDGET_METER_WINDOWS",
    "GLBUDGET_WARM_BLITS",
    "GLBUDGET_DUMP_PROBES",
    "GLBUDGET_PROBE_SCALE",
    "GLBUDGET_PROBE_SSIM",
    "GLBUDGET_PROBE_LEVELS",
    "GLBUDGET_PROBE_ORDER",
    "GLBUDGET_PROBE_FOLLOW",
    "GLBUDGET_PROBE_SWEEP",
    "GLBUDGET_PROBE_PASSES",
    "GLBUDGET_SHIM",
    "GLBUDGET_COSTS",
    // A test switch, to be documented in README's options table: GL extensions the shim
    // takes as absent (comma-separated), e.g. to run it as on a driver without timer queries.
    "GLBUDGET_TEST_HIDE_EXTENSIONS",
    // A test switch: pass:level pairs whose variant builds meet a real GL_OUT_OF_MEMORY.
    "GLBUDGET_TEST_OUT_OF_MEMORY",
    // A test switch: milliseconds the governor thread adds to measuring each probe frame.
    "GLBUDGET_TEST_MEASURE_DELAY_MS",
};

void warn(std::string* out, const std::string& text) { *out += "glbudget: " + text + "\n"; }

// The items of a comma-separated value as written, empty ones included.
std::vector<std::string> comma_items(const std::string& value) {
  std::vector<std::string> items;
  for (size_t start = 0; start <= value.size();) {
    size_t comma = value.find(',', start);
    if (comma == std::string::npos) comma = value.size();
    items.push_back(value.substr(start, comma - start));
    start = comma + 1;
  }
  return items;
}
// A whole number in [min, max] as written (digits only after optional leading spaces, no
// sign), else nullopt.
std::optional<unsigned long long> whole_number(const std::string& value, unsigned long long min,
                                               unsigned long long max) {
  errno = 0;
  char* end = nullptr;
  const unsigned long long n = std::strtoull(value.c_str(), &end, 10);
  if (errno || end == value.c_str() || *end != '\0' || n < min || n > max || value[0] == '-') return std::nullopt;
  return n;
}
// A decimal number in [min, max] as written, or nothing where the text is not one.
std::optional<double> decimal(const std::string& value, double min, double max) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(value.c_str(), &end);
  if (errno || end == value.c_str() || *end != '\0' || !std::isfinite(v) || v < min || v > max) return std::nullopt;
  return v;
}
// Seconds in [0, max], or nothing where the text is not one.
std::optional<double> seconds(const std::string& value, double max) { return decimal(value, 0.0, max); }
// A share in [min, max], written 0.98 or 98%, or nothing where the text is not one.
std::optional<double> share(const std::string& value, double min, double max) {
  if (value.empty() || value.back() != '%') return decimal(value, min, max);
  const std::optional<double> percent = decimal(value.substr(0, value.size() - 1), min * 100.0, max * 100.0);
  if (!percent) return std::nullopt;
  return *percent / 100.0;
}
// A switch: 1/on or 0/off; anything else is said and leaves it as it was (its default).
void parse_switch(std::string_view name, const std::string& value, bool& on, std::string* warnings) {
  if (value == "1" || value == "on")
    on = true;
  else if (value == "0" || value == "off")
    on = false;
  else
    warn(warnings, std::string(name) + "='" + value + "' is not 0/1/on/off; " + (on ? "on" : "off"));
}
// One of a few named values; anything else is said and leaves it as it was (its default).
template <typename T>
void parse_choice(std::string_view name, const std::string& value,
                  std::initializer_list<std::pair<std::string_view, T>> choices, T& out, std::string* warnings) {
  std::string names, kept;
  std::size_t i = 0;
  for (const auto& [text, choice] : choices) {
    if (value == text) {
      out = choice;
      return;
    }
    names += std::string(i == 0 ? "" : i + 1 == choices.size() ? " or " : ", ") + std::string(text);
    if (choice == out && kept.empty()) kept = text;
    ++i;
  }
  warn(warnings, std::string(name) + "='" + value + "' is not " + names + "; " + kept);
}
}  // namespace

Options parse_options(char** env, std::string* warnings) {
  Options o;
  int instrument_switch = -1;  // -1: not given
  for (char** e = env; e && *e; ++e) {
    std::string_view entry(*e);
    if (entry.rfind("GLBUDGET_", 0) != 0) continue;
    size_t eq = entry.find('=');
    std::string_view name = entry.substr(0, eq);
    std::string value(eq == std::string_view::npos ? "" : entry.substr(eq + 1));
    bool known = false;
    for (const char* k : kKnownVariables) known = known || name == k;
    if (!known) {
      warn(warnings, "unknown variable " + std::string(name) + " ignored");
      continue;
    }
    if (name == "GLBUDGET_LOG") {
      o.log_path = value;
    } else if (name == "GLBUDGET_DUMP") {
      o.dump_dir = value;
    } else if (name == "GLBUDGET_INSTRUMENT") {
      if (value == "1" || value == "on")
        instrument_switch = 1;
      else if (value == "0" || value == "off" || value.empty())
        instrument_switch = 0;
      else
        warn(warnings, "GLBUDGET_INSTRUMENT='" + value + "' is not 0/1/on/off; ignored");
    } else if (name == "GLBUDGET_CONFIG") {
      o.config_path = value;
    } else if (name == "GLBUDGET_COSTS") {
      o.costs_path = value;
    } else if (name == "GLBUDGET_FORCE") {
      o.force = value;  // checked against the manifest when it is loaded
    } else if (name == "GLBUDGET_POWER") {
      if (value != "off") o.power = value;
    } else if (name == "GLBUDGET_ERROR") {
      if (value != "off") o.error = value;
    } else if (name == "GLBUDGET_SELECT_FRAMES") {
      if (const auto n = whole_number(value, 1, 1000000))
        o.select_frames = *n;
      else
        warn(warnings, "GLBUDGET_SELECT_FRAMES='" + value + "' is not a number of frames in [1, 1000000]; 200");
    } else if (name == "GLBUDGET_REMEMBER_FRAMES") {
      if (const auto n = whole_number(value, 0, 100000))
        o.remember_frames = static_cast<int64_t>(*n);
      else
        warn(warnings,
             "GLBUDGET_REMEMBER_FRAMES='" + value + "' is not a number of frames in [0, 100000]; the model's default");
    } else if (name == "GLBUDGET_TRANSITION_S") {
      if (const auto t = seconds(value, 3600))
        o.transition_s = *t;
      else
        warn(warnings, "GLBUDGET_TRANSITION_S='" + value + "' is not a number of seconds in [0, 3600]; 2");
    } else if (name == "GLBUDGET_PROBE_MAX_AGE_S") {
      if (const auto t = seconds(value, 3600))
        o.probe_max_age_s = *t;
      else
        warn(warnings, "GLBUDGET_PROBE_MAX_AGE_S='" + value + "' is not a number of seconds in [0, 3600]; 10");
    } else if (name == "GLBUDGET_KEEP_SHARE") {
      if (const auto k = share(value, 0.5, 0.999))
        o.keep_share = *k;
      else
        warn(warnings, "GLBUDGET_KEEP_SHARE='" + value + "' is not a share in [0.5, 0.999] (0.98 or 98%); 0.98");
    } else if (name == "GLBUDGET_BEST_BAND") {
      if (value == "off") {
        o.best_band = std::numeric_limits<double>::infinity();
      } else if (const auto b = share(value, 0.0, 1.0)) {
        o.best_band = *b;
      } else {
        warn(warnings, "GLBUDGET_BEST_BAND='" + value + "' is not a share in [0, 1] (0.1 or 10%) or off; 0.1");
      }
    } else if (name == "GLBUDGET_FIRST_SAVING_DISCOUNT") {
      // 1 would raise every unmeasured configuration to the one measured: nothing would fit, and
      // the selection could keep the measured one, so that the discount never lifts.
      if (const auto d = share(value, 0.0, 0.9))
        o.first_saving_discount = *d;
      else
        warn(warnings, "GLBUDGET_FIRST_SAVING_DISCOUNT='" + value + "' is not a share in [0, 0.9] (0.25 or 25%); 0");
    } else if (name == "GLBUDGET_SURPRISE_FLOOR") {
      if (value == "off") {
        o.surprise_floor = 0.0;
      } else if (const auto f = share(value, 0.0, 0.5)) {
        o.surprise_floor = *f;
      } else {
        warn(warnings, "GLBUDGET_SURPRISE_FLOOR='" + value +
                           "' is not a share in [0, 0.5] (0.02 or 2%) or off; the default, 0.02");
      }
    } else if (name == "GLBUDGET_PROBE_PERIOD") {
      if (const auto n = whole_number(value, 0, 1000000))
        o.probe_period = static_cast<int64_t>(*n);
      else
        warn(warnings, "GLBUDGET_PROBE_PERIOD='" + value + "' is not a number of frames in [0, 1000000]; ignored");
    } else if (name == "GLBUDGET_DUMP_PROBES") {
      o.dump_probes = value;
    } else if (name == "GLBUDGET_PROBE_SCALE") {
      if (value == "1" || value == "2" || value == "4")
        o.probe_scale = value[0] - '0';
      else
        warn(warnings, "GLBUDGET_PROBE_SCALE='" + value + "' is not 1, 2 or 4; Wang's rule");
    } else if (name == "GLBUDGET_PROBE_SSIM") {
      using S = Options::ProbeSsim;
      parse_choice<S>(name, value, {{"auto", S::kAuto}, {"gpu", S::kGpu}, {"cpu", S::kCpu}}, o.probe_ssim, warnings);
    } else if (name == "GLBUDGET_PROBE_LEVELS") {
      parse_choice<bool>(name, value, {{"cheapest", false}, {"all", true}}, o.probe_every_level, warnings);
    } else if (name == "GLBUDGET_PROBE_ORDER") {
      parse_choice<bool>(name, value, {{"weighted", true}, {"turn", false}}, o.probe_order_weighted, warnings);
    } else if (name == "GLBUDGET_PROBE_FOLLOW") {
      parse_switch(name, value, o.probe_follow, warnings);
    } else if (name == "GLBUDGET_PROBE_SWEEP") {
      parse_switch(name, value, o.probe_sweep, warnings);
      o.probe_sweep_set = true;
    } else if (name == "GLBUDGET_PROBE_PASSES") {
      if (const auto n = whole_number(value, 1, 64))
        o.probe_passes = static_cast<int>(*n);
      else
        warn(warnings, "GLBUDGET_PROBE_PASSES='" + value + "' is not a number of passes in [1, 64]; as many as fit");
    } else if (name == "GLBUDGET_FEEDBACK") {
      parse_switch(name, value, o.feedback, warnings);
    } else if (name == "GLBUDGET_TRANSITION_ORDER") {
      parse_switch(name, value, o.transition_order, warnings);
    } else if (name == "GLBUDGET_FEEDBACK_OWN") {
      parse_switch(name, value, o.feedback_own, warnings);
    } else if (name == "GLBUDGET_EXPLORE_HELD") {
      parse_switch(name, value, o.explore_held, warnings);
    } else if (name == "GLBUDGET_MEASURED_AT_WINDOWS") {
      parse_switch(name, value, o.measured_at_windows, warnings);
    } else if (name == "GLBUDGET_METER_WINDOWS") {
      parse_switch(name, value, o.meter_windows, warnings);
    } else if (name == "GLBUDGET_LEVEL_INTERACTIONS") {
      using L = loop::LevelInteractions;
      parse_choice<L>(
          name, value,
          {{"calibrated", L::calibrated}, {"additive", L::additive}, {"model", L::model}, {"scaled", L::scaled}},
          o.level_interactions, warnings);
    } else if (name == "GLBUDGET_ERROR_FEEDBACK") {
      parse_switch(name, value, o.error_feedback, warnings);
    } else if (name == "GLBUDGET_PROBE_STRETCH") {
      parse_switch(name, value, o.probe_stretch, warnings);
    } else if (name == "GLBUDGET_WARM_BLITS") {
      parse_switch(name, value, o.warm_blits, warnings);
    } else if (name == "GLBUDGET_TEST_HIDE_EXTENSIONS") {
      for (std::string item : comma_items(value)) {
        while (!item.empty() && item.front() == ' ') item.erase(item.begin());
        while (!item.empty() && item.back() == ' ') item.pop_back();
        if (!item.empty()) o.hide_extensions.push_back(item);
      }
    } else if (name == "GLBUDGET_TEST_OUT_OF_MEMORY") {
      for (const std::string& item : comma_items(value)) {
        if (item.empty()) continue;
        const size_t colon = item.rfind(':');
        char* end = nullptr;
        const unsigned long level = colon == std::string::npos ? 0 : std::strtoul(item.c_str() + colon + 1, &end, 10);
        if (colon == std::string::npos || colon == 0 || !end || end == item.c_str() + colon + 1 || *end != '\0')
          warn(warnings, "GLBUDGET_TEST_OUT_OF_MEMORY item '" + item + "' is not pass:level; ignored");
        else
          o.test_out_of_memory.emplace_back(item.substr(0, colon), level);
      }
    } else if (name == "GLBUDGET_TEST_MEASURE_DELAY_MS") {
      if (const auto n = whole_number(value, 0, 60000))
        o.test_measure_delay_ms = *n;
      else
        warn(warnings, "GLBUDGET_TEST_MEASURE_DELAY_MS='" + value + "' is not milliseconds in [0, 60000]; ignored");
    } else if (name == "GLBUDGET_FORCE_EVERY") {
      if (const auto n = whole_number(value, 1, ULLONG_MAX))
        o.force_every = *n;
      else
        warn(warnings, "GLBUDGET_FORCE_EVERY='" + value + "' is not a number of frames >= 1; ignored");
    } else if (name == "GLBUDGET_FPS") {
      if (value.empty() || value == "off" || value == "0") continue;
      errno = 0;
      char* end = nullptr;
      double fps = std::strtod(value.c_str(), &end);
      if (errno || end == value.c_str() || *end != '\0' || !std::isfinite(fps) || fps <= 0 || fps > 10000) {
        warn(warnings, "GLBUDGET_FPS='" + value + "' is not a frame rate in (0, 10000]; pacing off");
      } else {
        o.fps = fps;
      }
    }
  }
  // An explicit GLBUDGET_INSTRUMENT wins; a dump without it is measured (its point).
  o.instrument = instrument_switch >= 0 ? instrument_switch == 1 : !o.dump_dir.empty();
  return o;
}

const Options& options() {
  static Options parsed;
  static std::once_flag once;
  std::call_once(once, [] {
    std::string warnings;
    parsed = parse_options(environ, &warnings);
    if (!warnings.empty()) (void)!write(STDERR_FILENO, warnings.data(), warnings.size());
  });
  return parsed;
}

bool extension_hidden(const char* extension) {
  for (const std::string& hidden : options().hide_extensions)
    if (hidden == extension) return true;
  return false;
}

}  // namespace glbudget
