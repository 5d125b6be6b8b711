// The governor in the shim (GLBUDGET_POWER, GLBUDGET_ERROR): a thread of its own runs the
// decision loop (governor/loop) on every frame's record and publishes the configuration to
// draw; the render thread hands frames over without ever waiting for it and picks the
// decision up at its swap. When governing, the frame log's rows pass through the governor
// thread, which fills in their predicted power, budget, estimated error and decision.
#pragma once
#include "configuration.hpp"
#include "frame_row.hpp"

namespace glbudget {

// Reads the budgets, the platform profile and the manifest, and starts the thread; false
// (after one `glbudget:` line saying why, when a budget was asked for) when it cannot govern.
// Called once, when the first context is made current.
bool governor_start();
bool governing();          // frame rows pass through the governor thread
bool governor_steering();  // and it chooses the configuration (a budget is in force)

// Render thread: one row of a finished frame; rows of a frame arrive together, and
// governor_rows_done() follows the last of them.
void governor_push(const FrameRow& row);
void governor_rows_done();

// The configuration the governor chose for the frames to come; false before its first decision.
bool governor_levels(Levels* out);

// Exit: every queued frame is decided and logged, then the thread stops.
void governor_stop();
// A signal that ends the process, from its handler: the frames handed over are decided and
// logged, held rows too, waiting at most 2 s (async-signal-safe: polls, takes no lock).
void governor_drain_from_signal();

// A program of the app (by its hash in the frame log) belongs to this manifest pass.
void note_program_pass(PassId program, int pass);

// Render thread: a probe frame's images, read back (apply/probes.hpp). The governor thread
// measures the errors, updates its estimates and logs the shown frame's error with its rows.
struct ProbeCapture;
void governor_probe(ProbeCapture&& capture);
// Render thread: how many times a probe found a pass's error far from its previous probe (the
// scene changed, so every pass's error is stale). Settled probes, rare, go back to their first
// period whenever it grows, until each pass in the scene is probed again.
uint64_t probe_drift_count();
// Render thread: whether probe frames handed over and not yet measured are as many as may
// wait: kProbeBacklog of them, or kProbeBacklogBytes of images (read back for the CPU's SSIM).
// A new probe waits until then: where the governor's SSIM is slower than the probes come (a big
// window, a fast app, a slow CPU), probing slows to what it can measure, rather than queueing
// images without bound and deciding on ever staler frames.
bool governor_probes_backlogged();
inline constexpr size_t kProbeBacklog = 8;
inline constexpr size_t kProbeBacklogBytes = size_t{64} << 20;

}  // namespace glbudget
