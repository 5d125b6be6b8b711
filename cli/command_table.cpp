// To add a subcommand: write <name>_command.cpp defining its CommandMain, then declare it
// and add its row below.
#include "command.hpp"

namespace glbudget::cli {

int sensors_main(std::span<char* const> args);
int replay_main(std::span<char* const> args);
int costs_main(std::span<char* const> args);
int run_main(std::span<char* const> args);
int ssim_main(std::span<char* const> args);
int calibrate_main(std::span<char* const> args);
int report_main(std::span<char* const> args);

namespace {
constexpr Command table[] = {
    {"run", "run a GL app under the shim: glbudget run [--power 40%|35W] [--error E] [--fps N] -- APP [ARGS...]",
     run_main},
    {"sensors", "list the power sensors this machine offers and what they read now", sensors_main},
    {"replay", "run a frame log through the power model and the baseline, print their errors", replay_main},
    {"costs", "fit this machine's per-batch, vertex, fragment, instruction and texel costs from frame logs",
     costs_main},
    {"ssim", "the SSIM of two images (same size), as the governor measures quality", ssim_main},
    {"calibrate", "measure this machine's platform profile (P_m, P_M, B, V, F) with a sensor, in under a minute",
     calibrate_main},
    {"report", "draw a governed run from its log: glbudget report run.csv [--html out.html] [--png DIR]", report_main},
};
}  // namespace

std::span<const Command> commands() { return table; }

}  // namespace glbudget::cli
