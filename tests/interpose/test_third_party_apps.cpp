// Integration: programs nobody here wrote, run unmodified under the shim. glxgears (GLX,
// compatibility profile, gears in display lists) and es2gears_x11 (EGL on X11, GLES 2) come
// from Debian's mesa-utils (scripts/packages.txt). Neither ends by itself: each runs for
// three seconds under `timeout`, which stops it with SIGINT, so it must still be running then
// (exit 124), and every frame it logged must be whole.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <map>
#include <set>

#include "probe_expectations.h"

namespace {

struct AppLog {
  ProcessResult process;
  std::vector<std::map<std::string, std::string>> rows;  // data rows by column name
};

AppLog run_app(const std::string& app) {
  const std::string log = temp_path(app + ".csv");
  unlink(log.c_str());
  AppLog out;
  // Only the app is preloaded, not the X server or the wrappers around it.
  out.process = run_process({"xvfb-run", "-a", "-s", "-screen 0 320x240x24", "timeout", "-s", "INT", "3", "env",
                             "LD_PRELOAD=" + shim_path(), "GLBUDGET_LOG=" + log, app},
                            {});
  auto csv = read_csv(log);
  for (size_t i = 1; i < csv.size(); ++i) {
    std::map<std::string, std::string> row;
    for (size_t c = 0; c < csv[0].size() && c < csv[i].size(); ++c) row[csv[0][c]] = csv[i][c];
    out.rows.push_back(row);
  }
  unlink(log.c_str());
  return out;
}

// Frames seen, and each frame's rows whole: every field of the header is there.
std::set<long> frames_of(const AppLog& a, size_t columns) {
  std::set<long> frames;
  for (const auto& row : a.rows) {
    CHECK(row.size() == columns);
    frames.insert(std::stol(row.at("frame")));
  }
  return frames;
}

}  // namespace

TEST_CASE("glxgears under the shim: every frame counted, fixed-function pass measured", "[integration]") {
  AppLog a = run_app("glxgears");
  INFO(a.process.err);
  CHECK(a.process.exit_code == 124);  // still drawing when timeout stopped it
  // The shim says which power sensor it opened, and nothing else: no warning, no error.
  CHECK(count_lines_with(a.process.err, "glbudget:") == 1);
  CHECK(count_lines_with(a.process.err, "glbudget: power sensor ") == 1);
  std::set<long> frames = frames_of(a, 13);
  REQUIRE(frames.size() >= 20);
  CHECK(*frames.begin() == 1);
  CHECK(*frames.rbegin() == long(frames.size()));  // no frame missing between the first and the last logged
  size_t measured = 0;
  for (const auto& row : a.rows) {
    CHECK(row.at("pass") == "fixed-function");  // no program is ever bound
    CHECK(row.at("batches") == "3");            // three glCallList per frame, one per gear
    if (row.at("vertices").empty()) continue;   // the last frames' queries may be unread at exit
    ++measured;
    CHECK(std::stoll(row.at("vertices")) > 0);
    CHECK(std::stoll(row.at("fragments")) > 1000);
    CHECK(std::stoll(row.at("primitives")) > 0);
  }
  CHECK(measured + 8 >= a.rows.size());
}

TEST_CASE("es2gears_x11 under the shim: a GLES 2 context on X11, batches counted per frame", "[integration]") {
  AppLog a = run_app("es2gears_x11");
  INFO(a.process.err);
  CHECK(a.process.exit_code == 124);
  CHECK(count_lines_with(a.process.err, "glbudget:") == 1);
  CHECK(count_lines_with(a.process.err, "glbudget: power sensor ") == 1);
  std::set<long> frames = frames_of(a, 13);
  REQUIRE(frames.size() >= 20);
  CHECK(*frames.rbegin() == long(frames.size()));
  std::set<std::string> batches;
  for (const auto& row : a.rows) {
    batches.insert(row.at("batches"));
    // GLES has no statistics queries: these are "not measured", never a made-up zero.
    CHECK(row.at("vertices").empty());
    CHECK(row.at("fragments").empty());
  }
  CHECK(batches.size() == 1);  // the same gears every frame
  CHECK(std::stoll(*batches.begin()) > 0);
}
