#include "glbudget/loop/step_times.hpp"

#include <algorithm>
#include <cstdio>

namespace glbudget::loop {

void RunningStats::add(double us) {
  ++count;
  last_us = us;
  mean_us += (us - mean_us) / static_cast<double>(count);
  max_us = count == 1 ? us : std::max(max_us, us);
}

std::string describe(const StepTimes& times) {
  const std::pair<const char*, const RunningStats*> steps[] = {
      {"predict frame", &times.predict_frame},
      {"learn", &times.learn},
      {"fit", &times.fit},
      {"predict all", &times.predict_all},
      {"estimate errors", &times.estimate_errors},
      {"select", &times.select},
  };
  std::string text;
  char line[160];
  for (const auto& [name, stats] : steps) {
    std::snprintf(line, sizeof line, "%s%s %.1f/%.1f/%.1f us (%zu)", text.empty() ? "" : ", ", name, stats->last_us,
                  stats->mean_us, stats->max_us, stats->count);
    text += line;
  }
  return text + " (last/mean/max)";
}

}  // namespace glbudget::loop
