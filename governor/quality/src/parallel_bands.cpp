#include "parallel_bands.hpp"

#include <algorithm>
#include <exception>
#include <thread>
#include <vector>

namespace glbudget::quality {

unsigned resolve_threads(unsigned threads) {
  if (threads != 0) return threads;
  return std::max(1u, std::thread::hardware_concurrency());
}

void run_in_bands(int rows, unsigned threads, int min_rows, const std::function<void(int, int)>& band) {
  if (rows <= 0) return;
  const int most = std::max(1, rows / std::max(1, min_rows));
  const int bands = static_cast<int>(std::min<unsigned>(resolve_threads(threads), static_cast<unsigned>(most)));
  const auto start = [&](int i) { return static_cast<int>(static_cast<long long>(rows) * i / bands); };
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(bands));
  const auto run = [&](int i) {
    try {
      band(start(i), start(i + 1));
    } catch (...) {
      errors[static_cast<std::size_t>(i)] = std::current_exception();
    }
  };
  std::vector<std::thread> workers;
  workers.reserve(static_cast<std::size_t>(bands - 1));
  for (int i = 1; i < bands; ++i) workers.emplace_back(run, i);
  run(0);
  for (std::thread& worker : workers) worker.join();
  for (const std::exception_ptr& error : errors)
    if (error) std::rethrow_exception(error);
}

}  // namespace glbudget::quality
