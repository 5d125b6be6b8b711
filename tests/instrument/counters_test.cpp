// Readback arithmetic at its extremes: carries into the high word, zero invocations,
// totals beyond 2^53 (where doubles stop being exact), layout of the words.
#include "glbudget/instrument/instrument.hpp"

#include <catch2/catch.hpp>

#include <set>

using namespace glbudget::instrument;

TEST_CASE("every (stage, quantity) has its own low and high word", "[counters]") {
  std::set<int> words;
  for (int s = 0; s < kStageCount; ++s)
    for (int q = 0; q < kQuantityCount; ++q) {
      const int low = word_index(static_cast<Stage>(s), static_cast<Quantity>(q));
      CHECK(low % 2 == 0);
      CHECK(low + 1 < kCounterWords);
      words.insert(low);
      words.insert(low + 1);
    }
  CHECK(words.size() == static_cast<std::size_t>(kCounterWords));
  CHECK(kCounterBytes == 144);
}

TEST_CASE("64-bit totals from word pairs", "[counters]") {
  CounterWords w{};
  w[word_index(Stage::fragment, Quantity::instructions)] = 0xFFFFFFFFu;
  w[word_index(Stage::fragment, Quantity::instructions) + 1] = 2;
  w[word_index(Stage::fragment, Quantity::invocations)] = 5;
  const StageCounts c = read_stage_counts(w, Stage::fragment);
  CHECK(c.instructions == 0x2FFFFFFFFull);
  CHECK(c.texel_accesses == 0);
  CHECK(c.invocations == 5);
  CHECK(read_stage_counts(w, Stage::vertex).instructions == 0);  // stages do not mix
}

TEST_CASE("averages per invocation", "[counters]") {
  SECTION("ordinary") {
    const StageAverages a = averages({103, 6, 2});
    CHECK(a.invocations == 2);
    CHECK(*a.instructions_per_invocation == Approx(51.5).epsilon(0));
    CHECK(*a.texel_accesses_per_invocation == 3.0);
  }
  SECTION("no invocation: no average, not NaN") {
    const StageAverages a = averages({0, 0, 0});
    CHECK(a.invocations == 0);
    CHECK_FALSE(a.instructions_per_invocation);
    CHECK_FALSE(a.texel_accesses_per_invocation);
    CHECK_FALSE(averages({10, 3, 0}).instructions_per_invocation);
  }
  SECTION("huge totals keep their ratio") {
    const std::uint64_t n = 1ull << 40;
    const StageAverages a = averages({n * 1000 + n / 2, 0, n});
    CHECK(*a.instructions_per_invocation == Approx(1000.5).epsilon(1e-12));
    CHECK(*averages({~0ull, ~0ull, ~0ull}).instructions_per_invocation == 1.0);
  }
  SECTION("readbacks add up") {
    const StageCounts sum = StageCounts{1, 2, 3} + StageCounts{10, 20, 30};
    CHECK(sum.instructions == 11);
    CHECK(sum.texel_accesses == 22);
    CHECK(sum.invocations == 33);
  }
}
