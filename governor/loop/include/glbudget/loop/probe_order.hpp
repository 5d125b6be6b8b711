#pragma once
// Which pass a probe frame measures next, once every pass in the scene has been measured
// (beyond the paper, issue 14). The estimates the governor selects by are each pass's latest
// probe (error_table.hpp), and the scene moves beneath them: what a stale pass costs the
// estimate is how far its error moved since, which grows with the error itself and with the
// frames since. A pass whose images barely change at its cheapest level hardly moves the
// ranking however old its probe is; the pass that dominates the errors does.
//
// So each probe takes the pass with the largest error × age. Where errors move like a random
// walk scaled by their size, probing pass i every T_i frames leaves a mean squared staleness
// proportional to e_i^2 T_i; for a given number of probes, the sum is least at T_i ∝ 1/e_i,
// the rate at which largest-(e_i × age) probing takes each pass. Errors under a tenth of the
// largest count as a tenth of it, so that every pass is still probed at least a tenth as often
// as the busiest (its error may grow where the camera goes).
#include <cstddef>
#include <cstdint>
#include <span>

namespace glbudget::loop {

struct ProbeCandidate {
  double error = 0.0;            // its last measured error (1 - SSIM); NaN or negative: none yet
  std::uint64_t last_frame = 0;  // the frame it was last probed at (0: never)
  bool in_scene = true;          // false: nothing of it is drawn, so it cannot be probed now
};

// The candidate to probe at frame `now`: one never probed first (the first in order), else the
// largest max(error, floor) × (now - last_frame), floor = max(kErrorFloor, largest error / 10);
// ties to the first. candidates.size() where none is in the scene.
inline constexpr double kErrorFloor = 0.002;  // SSIM's own scatter between frames of a still scene
std::size_t next_probe(std::span<const ProbeCandidate> candidates, std::uint64_t now);

}  // namespace glbudget::loop
