#include "configuration.hpp"
#include "messages.hpp"

#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>

#include "governing.hpp"
#include "options.hpp"

namespace glbudget {

std::string executable_name() {
  char path[4096];
  const ssize_t n = readlink("/proc/self/exe", path, sizeof path - 1);
  if (n <= 0) return {};
  path[n] = '\0';
  return std::filesystem::path(path).filename().string();
}

namespace {

// GLBUDGET_CONFIG, else $XDG_CONFIG_HOME/glbudget/<exe>.toml if it exists (~/.config when unset).
std::string manifest_path() {
  const Options& o = options();
  if (!o.config_path.empty()) return o.config_path;
  return manifest::default_manifest_path(executable_name());
}

struct State {
  manifest::Manifest manifest;
  std::vector<Levels> forced;  // empty: all passes at their best level
  uint64_t every = 0;          // frames per forced configuration when several are given
  bool has_programs = false, scales_targets = false, scales_window = false;
  std::atomic<uint64_t> matched{0};  // bit per pass
};

Levels to_levels(const std::vector<int>& v) {
  Levels l;
  l.count = static_cast<int>(std::min<size_t>(v.size(), kMaxPasses));
  for (int i = 0; i < l.count; ++i) l.level[i] = static_cast<int8_t>(v[static_cast<size_t>(i)]);
  return l;
}

State& state() {
  static State* s = [] {
    auto* st = new State;  // never destroyed: hooks may run during exit
    std::optional<manifest::Manifest> loaded;
    const std::string path = manifest_path();
    if (!path.empty()) {
      manifest::LoadResult r = manifest::load_manifest(path);
      for (const manifest::Problem& p : r.problems) say(p.text);
      if (!r.manifest) say("manifest " + path + " not used: the app runs with the render scale as its only knob");
      loaded = std::move(r.manifest);
    }
    st->manifest = manifest::with_resolution_pass(std::move(loaded));
    if (st->manifest.passes.size() > static_cast<size_t>(kMaxPasses)) {
      say("the manifest has " + std::to_string(st->manifest.passes.size()) + " passes; only the first " +
          std::to_string(kMaxPasses) + " are used");
      st->manifest.passes.resize(kMaxPasses);
    }
    for (const manifest::Pass& p : st->manifest.passes) {
      st->has_programs |= !p.match.empty();
      for (const manifest::Level& l : p.levels)
        for (const manifest::Target& t : l.targets)
          if (t.kind == manifest::Target::Kind::default_framebuffer)
            st->scales_window = true;
          else
            st->scales_targets = true;
    }
    const Options& o = options();
    if (!o.force.empty()) {
      size_t start = 0;
      for (;;) {
        const size_t end = o.force.find(';', start);
        const std::string one = o.force.substr(start, end == std::string::npos ? std::string::npos : end - start);
        std::string error;
        if (auto v = manifest::parse_force(one, st->manifest, &error)) {
          st->forced.push_back(to_levels(*v));
        } else {
          say(error + "; GLBUDGET_FORCE ignored");
          st->forced.clear();
          break;
        }
        if (end == std::string::npos) break;
        start = end + 1;
      }
    }
    st->every = o.force_every;
    return st;
  }();
  return *s;
}

}  // namespace

int format_levels(const Levels& levels, char* out, int size) {
  int n = 0;
  for (int i = 0; i < levels.count && n + 4 < size; ++i) {
    if (i) out[n++] = ':';
    n += std::snprintf(out + n, static_cast<size_t>(size - n), "%d", levels.level[i]);
  }
  if (n < size) out[n] = '\0';
  return n;
}

std::string format_levels(const Levels& levels) {
  char text[4 * kMaxPasses + 1];
  format_levels(levels, text, sizeof text);
  return text;
}

const manifest::Manifest& active_manifest() { return state().manifest; }
bool manifest_has_programs() { return state().has_programs; }
bool manifest_scales_targets() { return state().scales_targets; }
bool manifest_scales_window() { return state().scales_window; }
bool manifest_app_coordinates() { return state().manifest.app_coordinates; }

bool configuration_may_change() {
  const State& s = state();
  return governor_steering() || (s.forced.size() > 1 && s.every > 0);
}

Levels configuration_for_frame(uint64_t frame) {
  const State& s = state();
  Levels governed;
  if (governing() && governor_levels(&governed)) return governed;
  if (s.forced.empty()) {
    Levels best;
    best.count = static_cast<int>(s.manifest.passes.size());
    return best;
  }
  if (s.forced.size() == 1 || s.every == 0) return s.forced.front();
  const uint64_t step = (frame == 0 ? 0 : frame - 1) / s.every;
  return s.forced[static_cast<size_t>(step % s.forced.size())];
}

void note_pass_matched(int pass) {
  if (pass >= 0 && pass < 64) state().matched.fetch_or(uint64_t{1} << pass, std::memory_order_relaxed);
}

void report_unmatched_passes() {
  State& s = state();
  const uint64_t matched = s.matched.load();
  for (size_t i = 0; i < s.manifest.passes.size(); ++i) {
    const manifest::Pass& p = s.manifest.passes[i];
    if (p.match.empty() || (matched >> i) & 1) continue;
    say("manifest pass '" + p.name + "' (" + s.manifest.path + ") never matched a program of this app");
  }
}

}  // namespace glbudget
