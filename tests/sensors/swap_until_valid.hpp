#pragma once
#include <chrono>
#include <thread>

#include "glbudget/sensors/sensor.hpp"

namespace glbudget::sensors::testing {

// Swaps every millisecond until a frame is valid (the sampler has two samples of the current
// segment), for at most two seconds: fixed sleeps would fail on an overloaded machine.
inline bool swap_until_valid(PowerSensor& sensor) {
  using namespace std::chrono_literals;
  const auto deadline = std::chrono::steady_clock::now() + 2s;
  while (std::chrono::steady_clock::now() < deadline) {
    if (sensor.on_swap(monotonic_now_ns()).valid) return true;
    std::this_thread::sleep_for(1ms);
  }
  return false;
}

}  // namespace glbudget::sensors::testing
