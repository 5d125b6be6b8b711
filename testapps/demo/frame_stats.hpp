// The scene statistics table (paper, Table 3, plus draw calls per pass) as Markdown.
#pragma once
#include <ostream>

#include "renderer.hpp"
#include "scene.hpp"

namespace demo {

void print_stats_header(std::ostream& out);
void print_stats_row(std::ostream& out, const Scene& scene, const FrameDraws& draws);

}  // namespace demo
