// Readback arithmetic: 64-bit totals from (low, high) word pairs, per-invocation averages.
#include "glbudget/instrument/instrument.hpp"

namespace glbudget::instrument {

namespace {

std::uint64_t total(const CounterWords& words, Stage stage, Quantity quantity) {
  const int low = word_index(stage, quantity);
  return static_cast<std::uint64_t>(words[low + 1]) << 32 | words[low];
}

}  // namespace

StageCounts read_stage_counts(const CounterWords& words, Stage stage) {
  return {total(words, stage, Quantity::instructions), total(words, stage, Quantity::texel_accesses),
          total(words, stage, Quantity::invocations)};
}

StageAverages averages(const StageCounts& counts) {
  StageAverages a;
  a.invocations = counts.invocations;
  if (counts.invocations == 0) return a;
  const double n = static_cast<double>(counts.invocations);
  a.instructions_per_invocation = static_cast<double>(counts.instructions) / n;
  a.texel_accesses_per_invocation = static_cast<double>(counts.texel_accesses) / n;
  return a;
}

StageCounts operator+(const StageCounts& a, const StageCounts& b) {
  return {a.instructions + b.instructions, a.texel_accesses + b.texel_accesses, a.invocations + b.invocations};
}

}  // namespace glbudget::instrument
