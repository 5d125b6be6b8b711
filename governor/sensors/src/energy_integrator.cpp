#include "glbudget/sensors/energy_integrator.hpp"

#include <cmath>

namespace glbudget::sensors {

const char* to_string(Fault fault) {
  switch (fault) {
    case Fault::read_error:
      return "read error";
    case Fault::garbage:
      return "garbage value";
    case Fault::backwards:
      return "went backwards";
    case Fault::stalled:
      return "stalled";
  }
  return "?";
}

EnergyIntegrator::Outcome EnergyIntegrator::drop(Fault fault, std::string detail) {
  switch (fault) {
    case Fault::read_error:
      ++faults_.read_error;
      break;
    case Fault::garbage:
      ++faults_.garbage;
      break;
    case Fault::backwards:
      ++faults_.backwards;
      break;
    case Fault::stalled:
      ++faults_.stalled;
      break;
  }
  return Outcome{std::nullopt, fault, std::move(detail)};
}

// Closes the current segment at once, so that frames stop being charged from a curve that can
// no longer be trusted. The returned marker is a segment of its own, a single point and so
// without a rate: no time past it has an energy until good samples resume in a new segment.
std::optional<EnergyPoint> EnergyIntegrator::break_continuity(std::int64_t t_ns) {
  const bool first_break = have_previous_ && !continuity_lost_;
  continuity_lost_ = true;
  if (!first_break) return std::nullopt;
  ++segment_;
  return EnergyPoint{t_ns, energy_j_, segment_};
}

EnergyIntegrator::Outcome EnergyIntegrator::drop_stalled(std::int64_t t_ns, const char* what) {
  auto outcome = drop(Fault::stalled,
                      std::string(what) + " for over " + std::to_string(limits_.stall_timeout_ns / 1'000'000) + " ms");
  outcome.point = break_continuity(t_ns);
  return outcome;
}

// The reading becomes the new reference; the energy curve carries on at the same level in a
// new segment, so no frame is ever charged with energy of unknown origin. After a break the
// new segment is not the marker's: sharing it, marker and first point would make a flat
// stretch, a rate of zero over the outage, and frames across it would be charged nothing.
EnergyIntegrator::Outcome EnergyIntegrator::start_segment(std::int64_t t_ns, double value) {
  if (have_previous_) ++segment_;
  have_previous_ = true;
  continuity_lost_ = false;
  previous_t_ns_ = t_ns;
  previous_value_ = value;
  return Outcome{EnergyPoint{t_ns, energy_j_, segment_}, std::nullopt, {}};
}

EnergyIntegrator::Outcome EnergyIntegrator::accept(std::int64_t t_ns, const Reading& reading) {
  const bool stalled = have_previous_ && t_ns - previous_t_ns_ >= limits_.stall_timeout_ns;
  const Outcome outcome = accept_reading(t_ns, reading, stalled);
  if (reading.discarded_garbage == 0 && reading.discarded_backwards == 0) return outcome;
  faults_.garbage += reading.discarded_garbage;
  faults_.backwards += reading.discarded_backwards;
  if (outcome.fault) return outcome;
  Outcome with_fault = outcome;
  with_fault.fault = reading.discarded_garbage > 0 ? Fault::garbage : Fault::backwards;
  with_fault.detail = reading.detail;
  return with_fault;
}

EnergyIntegrator::Outcome EnergyIntegrator::accept_reading(std::int64_t t_ns, const Reading& reading, bool stalled) {
  switch (reading.status) {
    case ReadStatus::read_error: {
      auto outcome = drop(Fault::read_error, reading.detail);
      outcome.point = break_continuity(t_ns);
      return outcome;
    }
    case ReadStatus::garbage:
      return drop(Fault::garbage, reading.detail);
    case ReadStatus::no_new_data:
      if (!stalled) return {};
      return drop_stalled(t_ns, "no new data");
    case ReadStatus::ok:
      break;
  }

  const double value = reading.value;
  if (!std::isfinite(value) || value < 0.0) return drop(Fault::garbage, "value " + std::to_string(value));
  if (reading.kind == ReadingKind::power_w && value > limits_.max_plausible_w)
    return drop(Fault::garbage, "implausible power " + std::to_string(value) + " W");

  if (!have_previous_ || continuity_lost_) return start_segment(t_ns, value);
  if (t_ns <= previous_t_ns_) return {};  // same instant twice: nothing to integrate
  // An unchanged counter has not been refreshed yet (drivers update every few ms): wait,
  // unless it has been unchanged for longer than the stall timeout.
  if (reading.kind == ReadingKind::energy_j && value == previous_value_) {
    if (!stalled) return {};
    return drop_stalled(t_ns, "energy counter unchanged");
  }
  // A long gap between good samples (the sampler was starved): do not integrate across it.
  if (stalled) return start_segment(t_ns, value);
  const double dt_s = static_cast<double>(t_ns - previous_t_ns_) * 1e-9;

  if (reading.kind == ReadingKind::energy_j) {
    const double delta_j = value - previous_value_;
    if (delta_j < 0.0) {
      auto outcome = start_segment(t_ns, value);
      ++faults_.backwards;
      outcome.fault = Fault::backwards;
      outcome.detail = "energy counter went backwards by " + std::to_string(-delta_j) + " J";
      return outcome;
    }
    if (delta_j / dt_s > limits_.max_plausible_w) {
      auto outcome = start_segment(t_ns, value);
      ++faults_.garbage;
      outcome.fault = Fault::garbage;
      outcome.detail =
          "energy counter jumped by " + std::to_string(delta_j) + " J in " + std::to_string(dt_s * 1e3) + " ms";
      return outcome;
    }
    energy_j_ += delta_j;
  } else {
    energy_j_ += 0.5 * (previous_value_ + value) * dt_s;  // trapezoid between samples
  }
  previous_t_ns_ = t_ns;
  previous_value_ = value;
  return Outcome{EnergyPoint{t_ns, energy_j_, segment_}, std::nullopt, {}};
}

}  // namespace glbudget::sensors
