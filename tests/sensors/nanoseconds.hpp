#pragma once
#include <cstdint>

// Sensor timestamps are nanoseconds; the tests write their times in milliseconds.
inline constexpr std::int64_t ms = 1'000'000;
