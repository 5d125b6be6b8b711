#include "frame_stats.hpp"

#include <cstdio>

namespace demo {

void print_stats_header(std::ostream& out) {
  out << "| scene | triangles | objects | size (MB) |";
  for (int p = 0; p < kPassCount; ++p) out << ' ' << pass_name(static_cast<Pass>(p)) << " |";
  out << " draws/frame |\n|---|---:|---:|---:|";
  for (int p = 0; p < kPassCount; ++p) out << "---:|";
  out << "---:|\n";
}

void print_stats_row(std::ostream& out, const Scene& scene, const FrameDraws& draws) {
  char numbers[96];
  std::snprintf(numbers, sizeof numbers, "| %.1fk | %zu | %.2f |", static_cast<double>(scene.triangle_count()) / 1000.0,
                scene.objects.size(), static_cast<double>(scene.size_bytes()) / (1024.0 * 1024.0));
  out << "| " << scene.name << ' ' << numbers;
  for (int d : draws.draws) out << ' ' << d << " |";
  out << ' ' << draws.total() << " |\n";
}

}  // namespace demo
