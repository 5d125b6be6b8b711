// --bench: frame times of the best and the cheapest configuration, and of the best with each
// knob alone at its cheapest level, printed as Markdown tables (ratios against best, same run).
#pragma once
#include "context.h"
#include "options.h"
#include "renderer.h"
#include "scene.h"

namespace demo {

void run_bench(Renderer& renderer, GlContext& context, const Scene& scene, const Options& options);

}  // namespace demo
