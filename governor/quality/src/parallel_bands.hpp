#pragma once
// Splitting rows into contiguous bands run on std::threads.
#include <functional>

namespace glbudget::quality {

// 0 means std::thread::hardware_concurrency() (at least 1).
unsigned resolve_threads(unsigned threads);

// Calls band(first, end) over [0, rows) split into at most `threads` bands of at least
// `min_rows` rows each; the calling thread runs the first band. If a band throws, the first
// exception is rethrown here once every band has finished.
void run_in_bands(int rows, unsigned threads, int min_rows, const std::function<void(int, int)>& band);

}  // namespace glbudget::quality
