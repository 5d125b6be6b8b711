// next_probe (governor/loop/probe_order.hpp): which pass a settled probe frame takes.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <vector>

#include "glbudget/loop/probe_order.hpp"

using glbudget::loop::next_probe;
using glbudget::loop::ProbeCandidate;

TEST_CASE("probe order: never probed first, then the largest error times age", "[loop][probe-order]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<ProbeCandidate> c{{0.04, 100, true}, {nan, 0, false}, {0.01, 0, true}, {0.02, 50, true}};
  // The first never probed that is in the scene (the second is not in it).
  CHECK(next_probe(c, 200) == 2);
  c[2].last_frame = 150;
  // 0.04 × 100 = 4 against 0.02 × 150 = 3 and 0.01 × 50.
  CHECK(next_probe(c, 200) == 0);
  c[0].last_frame = 200;
  CHECK(next_probe(c, 260) == 3);
  // No error yet (NaN, negative) counts as never probed.
  c[3].error = -1.0;
  CHECK(next_probe(c, 260) == 3);
  c[3].error = nan;
  CHECK(next_probe(c, 260) == 3);
  // Nothing in the scene: none.
  for (ProbeCandidate& k : c) k.in_scene = false;
  CHECK(next_probe(c, 300) == c.size());
  CHECK(next_probe(std::vector<ProbeCandidate>{}, 300) == 0);
}

TEST_CASE(
    "probe order: errors under a tenth of the largest count as a tenth, ties go to the first, a frame "
    "before the last probe is no age",
    "[loop][probe-order]") {
  // 0.05's tenth is 0.005: the zero-error pass goes first once it is over 10 times older.
  std::vector<ProbeCandidate> c{{0.0, 1, true}, {0.05, 1001, true}};
  CHECK(next_probe(c, 1101) == 0);  // 0.005 × 1100 against 0.05 × 100
  c[0].last_frame = 201;
  CHECK(next_probe(c, 1101) == 1);  // 0.005 × 900
  std::vector<ProbeCandidate> tie{{0.25, 10, true}, {0.25, 10, true}};
  CHECK(next_probe(tie, 30) == 0);
  // All errors 0: the floor (kErrorFloor) for all, so the oldest.
  std::vector<ProbeCandidate> zero{{0.0, 30, true}, {0.0, 10, true}, {0.0, 20, true}};
  CHECK(next_probe(zero, 40) == 1);
  // Frames counted back (a frame before a candidate's last probe): age 0, not a wrapped number.
  std::vector<ProbeCandidate> back{{0.04, 500, true}, {0.001, 90, true}};
  CHECK(next_probe(back, 100) == 1);
  // Infinite errors are not numbers of SSIM: never probed, so first.
  std::vector<ProbeCandidate> inf{{0.01, 10, true}, {std::numeric_limits<double>::infinity(), 5, true}};
  CHECK(next_probe(inf, 100) == 1);
}

TEST_CASE("probe order: over many probes each pass is taken at a rate proportional to its error",
          "[loop][probe-order]") {
  // Errors 0.04, 0.02, 0.01 and 0 (floor 0.004): rates 4 : 2 : 1 : 0.4 of the probes.
  std::vector<ProbeCandidate> c{{0.04, 0, true}, {0.02, 0, true}, {0.01, 0, true}, {0.0, 0, true}};
  std::vector<int> taken(c.size(), 0);
  for (std::uint64_t frame = 60; frame <= 60 * 7400; frame += 60) {
    const std::size_t k = next_probe(c, frame);
    REQUIRE(k < c.size());
    c[k].last_frame = frame;
    ++taken[k];
  }
  // Probes come whole: each pass's period rounds up to whole probes, the rarest most.
  const double total = 7400.0, weights = 0.04 + 0.02 + 0.01 + 0.004;
  CHECK(taken[0] > taken[1]);
  CHECK(taken[1] > taken[2]);
  CHECK(taken[2] > taken[3]);
  CHECK(taken[0] / total == Approx(0.04 / weights).margin(0.02));
  CHECK(taken[1] / total == Approx(0.02 / weights).margin(0.02));
  CHECK(taken[2] / total == Approx(0.01 / weights).margin(0.02));
  CHECK(taken[3] / total == Approx(0.004 / weights).margin(0.02));
}
