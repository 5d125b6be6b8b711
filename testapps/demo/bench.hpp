// --bench: frame times of the best and the cheapest configuration, and of the best with each
// knob alone at its cheapest level, printed as Markdown tables (ratios against best, same run).
#pragma once
#include "context.hpp"
#include "options.hpp"
#include "renderer.hpp"
#include "scene.hpp"

namespace demo {

void run_bench(Renderer& renderer, GlContext& context, const Scene& scene, const Options& options);

}  // namespace demo
