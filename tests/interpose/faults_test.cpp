// Integration (issue 16): faults the shim must live through without harming the app. The demo
// renderer runs under the shim while a power meter vanishes, stalls or writes garbage, while
// its log sits on a full disk, while it is killed with SIGKILL, and on a driver without the
// queries the shim uses (GLBUDGET_TEST_HIDE_EXTENSIONS). In each case, where it applies:
//   - the app ends with its own exit code (0);
//   - its images are byte-identical to those of the same run without the fault;
//   - the shim says what happened in a `glbudget:` line on stderr, once;
//   - the frame log is whole up to the fault: every row parses, frames run 1, 2, 3, ... and
//     the file ends with a whole row.
// A variant that does not compile (or link) is covered by shadowing_test.cpp, case 8.
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <atomic>
#include <catch2/catch.hpp>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <set>
#include <thread>

#include "probe_expectations.hpp"

namespace {

using Env = std::map<std::string, std::string>;
using Row = std::map<std::string, std::string>;

int64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

void sleep_ms(int ms) { std::this_thread::sleep_for(std::chrono::milliseconds(ms)); }

// ---- The app: the demo renderer, small, dumping a few of its frames ----

constexpr long kFrames = 30;     // unpaced: two or three seconds here
constexpr long kDumpEvery = 10;  // frames 0, 10, 20, ... are dumped

// Without `dump_dir`, no images.
std::vector<std::string> demo_args(long frames, const std::string& dump_dir = "") {
  // The shadow map at a quarter of its default side: the frames take half the time.
  std::vector<std::string> args = {
      DEMO_PATH, "--scene", "hall",     "--detail", "0.05",     "--shadow-size",       "512",
      "--width", "160",     "--height", "90",       "--frames", std::to_string(frames)};
  if (!dump_dir.empty()) args.insert(args.end(), {"--dump", dump_dir, "--dump-every", std::to_string(kDumpEvery)});
  return args;
}

// The PNG files in `dir`, by name, as bytes.
std::map<std::string, std::string> images_in(const std::string& dir) {
  std::map<std::string, std::string> images;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    images[entry.path().filename().string()] = read_file(entry.path().string());
  return images;
}

struct Run {
  ProcessResult result;
  std::map<std::string, std::string> images;
};

// The demo under the shim with `env`, its images dumped to a directory of their own.
Run run_demo(const Env& env, long frames = kFrames) {
  static int runs = 0;
  const std::string dir = temp_path("faults_images_" + std::to_string(runs++));
  std::filesystem::remove_all(dir);
  Env all = env;
  all["LD_PRELOAD"] = shim_path();
  Run run;
  run.result = run_process(demo_args(frames, dir), all);
  if (std::filesystem::exists(dir)) run.images = images_in(dir);
  std::filesystem::remove_all(dir);
  return run;
}

// The demo's images of `frames` frames under the shim, logging, with no fault (run once).
const std::map<std::string, std::string>& images_without_fault(long frames) {
  static std::map<long, std::map<std::string, std::string>> runs;
  if (!runs.count(frames)) {
    const std::string log = temp_path("faults_baseline.csv");
    const Run run = run_demo({{"GLBUDGET_LOG", log}, {"GLBUDGET_SENSOR", "cpu"}}, frames);
    unlink(log.c_str());
    INFO(run.result.err);
    REQUIRE(run.result.exit_code == 0);
    REQUIRE(run.images.size() == static_cast<size_t>((frames + kDumpEvery - 1) / kDumpEvery));
    runs[frames] = run.images;
  }
  return runs[frames];
}

// What a fault must leave alone: the app's exit code and its images, byte for byte.
void check_app_unchanged(const Run& run, long frames = kFrames) {
  CHECK(run.result.exit_code == 0);
  const auto& expected = images_without_fault(frames);
  CHECK(run.images.size() == expected.size());
  for (const auto& [name, bytes] : expected) {
    INFO("image " << name);
    CHECK((run.images.count(name) && run.images.at(name) == bytes));
  }
}

// ---- The frame log ----

std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> fields;
  for (size_t start = 0;;) {
    const size_t comma = line.find(',', start);
    fields.push_back(line.substr(start, comma - start));
    if (comma == std::string::npos) return fields;
    start = comma + 1;
  }
}

bool is_integer(const std::string& s) {
  if (s.empty()) return false;
  char* end = nullptr;
  errno = 0;
  (void)std::strtoll(s.c_str(), &end, 10);
  return errno == 0 && *end == '\0';
}

bool is_number(const std::string& s) {
  if (s.empty()) return false;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  return *end == '\0' && std::isfinite(v);
}

// The first thing wrong with the log's text, or "": it must end with a newline, and every row
// must have the header's fields, each of the right form, with frames numbered 1, 2, 3, ...
// (several rows per frame, one per pass).
std::string log_problem(const std::string& text) {
  if (text.rfind("frame,time_ns,context,pass,", 0) != 0) return "no header";
  if (text.back() != '\n') return "the last row is cut: '" + text.substr(text.rfind('\n') + 1) + "'";
  const auto csv_header = split_fields(text.substr(0, text.find('\n')));
  const size_t fields = csv_header.size();
  long previous_frame = 0;
  size_t line_no = 1;
  for (size_t at = text.find('\n') + 1; at < text.size(); at = text.find('\n', at) + 1, ++line_no) {
    const std::string line = text.substr(at, text.find('\n', at) - at);
    const auto f = split_fields(line);
    const std::string where = "row " + std::to_string(line_no) + " '" + line + "': ";
    if (f.size() != fields) return where + std::to_string(f.size()) + " fields";
    Row row;
    for (size_t i = 0; i < fields; ++i) row[csv_header[i]] = f[i];
    for (const char* name : {"frame", "time_ns", "context", "batches", "sensor_dropped"})
      if (!is_integer(row[name])) return where + name + " is not a number";
    for (const char* name : {"vertices", "fragments", "primitives", "gpu_ns"})
      if (!row[name].empty() && !is_integer(row[name])) return where + name + " is not a number";
    for (const char* name : {"power_w", "energy_j"})
      if (!row[name].empty() && !is_number(row[name])) return where + name + " is not a number";
    if (row["pass"].size() != 16 && row["pass"] != "fixed-function") return where + "bad pass";
    const long frame = std::stol(row["frame"]);
    if (frame != previous_frame + 1 && (frame != previous_frame || frame == 0))
      return where + "frame " + std::to_string(frame) + " after " + std::to_string(previous_frame);
    previous_frame = frame;
  }
  if (previous_frame == 0) return "no rows";
  return "";
}

// The log must be whole; returns its rows.
std::vector<Row> whole_log(const std::string& path) {
  const std::string text = read_file(path);
  INFO(path);
  CHECK(log_problem(text) == "");
  return read_csv_rows_by_name(path);
}

// One row per frame (the first pass's): power and the sensor's fields repeat on every pass row.
std::map<long, Row> by_frame(const std::vector<Row>& rows) {
  std::map<long, Row> frames;
  for (const Row& row : rows) frames.emplace(std::stol(row.at("frame")), row);
  return frames;
}

// ---- A power meter outside the process (GLBUDGET_SENSOR=file:PATH) ----

constexpr long kMeterFrames = 80;                        // at 20 fps: four seconds at least
constexpr double kMeterLowW = 11.0, kMeterHighW = 13.0;  // it alternates between the two

// Writes "timestamp,watts" lines to the meter's file or FIFO, as a meter would.
struct Meter {
  int fd = -1;
  double seconds = 1000.0;  // the meter's own clock
  int samples = 0;
  std::string good_line() {
    seconds += 0.01;
    return std::to_string(seconds) + "," + std::to_string(samples++ % 2 ? kMeterHighW : kMeterLowW) + "\n";
  }
  void write_text(const std::string& text) {
    if (fd >= 0) (void)!::write(fd, text.data(), text.size());
  }
  void close_it() {
    if (fd >= 0) ::close(fd);
    fd = -1;
  }
};

// What the meter does: good samples every 10 ms until the shim has logged frames with power;
// then `fault` once (the fault's time is taken there), then `after` every 10 ms (if given),
// with the seconds since the fault, until the app is done.
struct MeterScript {
  std::function<void(Meter&)> fault;
  std::function<void(Meter&, double)> after;
};

struct MeterRun {
  Run run;
  std::vector<Row> rows;
  int64_t fault_ns = 0;  // CLOCK_MONOTONIC, the clock of the log's time_ns
};

size_t frames_with_power(const std::string& log) {
  std::set<std::string> frames;
  for (const Row& row : read_csv_rows_by_name(log))
    if (row.count("power_w") && !row.at("power_w").empty()) frames.insert(row.at("frame"));
  return frames.size();
}

// The demo paced at 20 fps (kMeterFrames: four seconds at least, the fault early in them) with
// the meter at `path`, a file or a FIFO the meter opens once the shim has opened its end.
MeterRun run_with_meter(const std::string& path, bool fifo, const MeterScript& script) {
  unlink(path.c_str());
  if (fifo)
    REQUIRE(mkfifo(path.c_str(), 0600) == 0);
  else
    REQUIRE(close(open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600)) == 0);
  const std::string log = path + ".csv";
  unlink(log.c_str());
  std::atomic<bool> done{false};
  std::atomic<int64_t> fault_ns{0};
  std::thread meter_thread([&] {
    // Writing to a FIFO whose reader has gone: EPIPE, and a SIGPIPE kept pending on this
    // thread (blocked here only, so the app inherits no changed signal disposition).
    sigset_t pipe;
    sigemptyset(&pipe);
    sigaddset(&pipe, SIGPIPE);
    pthread_sigmask(SIG_BLOCK, &pipe, nullptr);
    Meter meter;
    while (!done) {
      if (meter.fd < 0 && !fault_ns)  // a FIFO opens once the shim has opened it for reading
        meter.fd = open(path.c_str(), O_WRONLY | O_NONBLOCK | O_APPEND | O_CLOEXEC);
      if (!fault_ns) {
        meter.write_text(meter.good_line());
        if (frames_with_power(log) >= 5) {
          fault_ns = monotonic_ns();
          script.fault(meter);
        }
      } else if (script.after) {
        script.after(meter, static_cast<double>(monotonic_ns() - fault_ns) * 1e-9);
      }
      sleep_ms(10);
    }
    meter.close_it();
  });
  MeterRun r;
  r.run = run_demo({{"GLBUDGET_SENSOR", "file:" + path}, {"GLBUDGET_LOG", log}, {"GLBUDGET_FPS", "20"}}, kMeterFrames);
  done = true;
  meter_thread.join();
  r.fault_ns = fault_ns;
  r.rows = whole_log(log);
  unlink(log.c_str());
  unlink(path.c_str());
  return r;
}

// Power in the log around a meter fault: frames before it carry the meter's power, and only
// ever the meter's (between its two levels: never a made-up or garbage figure); frames from
// `quiet_s` after it on carry no power (empty fields) but still name the sensor, and samples
// were counted as dropped after the fault.
void check_power_around_fault(const MeterRun& r, double quiet_s) {
  REQUIRE(r.fault_ns > 0);  // the meter saw frames with power
  size_t powered_before = 0, quiet_after = 0;
  uint64_t dropped_after = 0;
  for (const auto& [frame, row] : by_frame(r.rows)) {
    INFO("frame " << frame << " power " << row.at("power_w"));
    CHECK(row.at("sensor") == "file");
    const int64_t t = std::stoll(row.at("time_ns"));
    const bool has_power = !row.at("power_w").empty();
    CHECK(has_power == !row.at("energy_j").empty());
    if (has_power) {
      CHECK(std::stod(row.at("power_w")) >= kMeterLowW - 1e-6);
      CHECK(std::stod(row.at("power_w")) <= kMeterHighW + 1e-6);
    }
    if (t < r.fault_ns) powered_before += has_power;
    if (t > r.fault_ns) dropped_after += std::stoull(row.at("sensor_dropped"));
    if (t > r.fault_ns + static_cast<int64_t>(quiet_s * 1e9)) {
      ++quiet_after;
      CHECK(!has_power);
    }
  }
  CHECK(powered_before >= 3);
  CHECK(quiet_after >= 5);  // the run went on long enough to see it
  CHECK(dropped_after > 0);
}

// The sampler declares a source stalled after a second without data: the last frames it could
// still extrapolate end then.
constexpr double kStallS = 1.0, kQuietS = kStallS + 0.3;

// ---- Driver features (GLBUDGET_TEST_HIDE_EXTENSIONS) ----

size_t rows_with(const std::vector<Row>& rows, const char* column) {
  size_t n = 0;
  for (const Row& row : rows) n += !row.at(column).empty();
  return n;
}

}  // namespace

TEST_CASE("fault: the power meter vanishes mid-run (file deleted, FIFO closed)", "[integration][faults]") {
  // Asserts: the app and its images unchanged; power logged until the meter goes, no power
  // (empty fields) from a second after on, never a wrong figure; one glbudget: line saying the
  // sensor stalled; the log whole.
  const std::string path = temp_path("meter_vanishes");
  for (const bool fifo : {false, true}) {
    INFO((fifo ? "FIFO closed" : "file deleted"));
    const MeterRun r = run_with_meter(path, fifo,
                                      {[&](Meter& m) {
                                         m.close_it();
                                         if (!fifo) unlink(path.c_str());
                                       },
                                       {}});
    INFO(r.run.result.err);
    check_app_unchanged(r.run, kMeterFrames);
    check_power_around_fault(r, kQuietS);
    CHECK(count_lines_with(r.run.result.err, "glbudget:") == 1);
    CHECK(count_lines_with(r.run.result.err, "glbudget: sensor file: sample dropped (stalled") == 1);
  }
}

TEST_CASE("fault: the power meter stalls (stops writing, the file stays)", "[integration][faults]") {
  // Asserts: as for a vanished meter: power until the stall, none from a second after on.
  const MeterRun r = run_with_meter(temp_path("meter_stalls"), false, {[](Meter&) {}, {}});
  INFO(r.run.result.err);
  check_app_unchanged(r.run, kMeterFrames);
  check_power_around_fault(r, kQuietS);
  CHECK(count_lines_with(r.run.result.err, "glbudget:") == 1);
  CHECK(count_lines_with(r.run.result.err, "glbudget: sensor file: sample dropped (stalled") == 1);
}

TEST_CASE("fault: the power meter writes NaN and garbage lines", "[integration][faults]") {
  // For half a second garbage comes between good lines (written together, so that they reach
  // the shim in one read), then garbage only. Asserts: bad lines are dropped and counted and
  // never reach the power column (not even averaged with good ones: 6000 W is implausible on
  // its own); power goes on while good lines come, and ends a second after they stop; one
  // glbudget: line for the garbage, one for the stall; the app and the log unchanged.
  // Bad lines of every kind; the implausible one carries a fresh timestamp, as a good line would.
  const auto garbage = [](Meter& m) {
    m.seconds += 0.01;
    return "nan-time,12\n1.5,nan\n2.5,inf\n3.5,-4\nhello\n5.5,\n,7\n6.5,1e999\n\x01\x02\n" + std::to_string(m.seconds) +
           ",6000\n";
  };
  const MeterRun r = run_with_meter(temp_path("meter_garbage"), false,
                                    {[&](Meter& m) { m.write_text(garbage(m)); },
                                     [&](Meter& m, double since_fault) {
                                       if (since_fault < 0.5) {
                                         const std::string first = m.good_line();  // timestamps in order
                                         const std::string bad = garbage(m);
                                         m.write_text(first + bad + m.good_line());
                                       } else {
                                         m.write_text(garbage(m));
                                       }
                                     }});
  INFO(r.run.result.err);
  check_app_unchanged(r.run, kMeterFrames);
  check_power_around_fault(r, 0.5 + kQuietS);
  size_t powered_among_garbage = 0;
  for (const auto& [frame, row] : by_frame(r.rows)) {
    const int64_t t = std::stoll(row.at("time_ns"));
    if (t > r.fault_ns + 100'000'000 && t < r.fault_ns + 500'000'000)
      powered_among_garbage += !row.at("power_w").empty();
  }
  CHECK(powered_among_garbage >= 2);
  CHECK(count_lines_with(r.run.result.err, "glbudget:") == 2);
  CHECK(count_lines_with(r.run.result.err, "glbudget: sensor file: sample dropped (garbage value") == 1);
  CHECK(count_lines_with(r.run.result.err, "glbudget: sensor file: sample dropped (stalled") == 1);
}

TEST_CASE("fault: the log is on a full disk (GLBUDGET_LOG=/dev/full)", "[integration][faults]") {
  // Asserts: the app and its images unchanged, one glbudget: line saying the log cannot be
  // written and why.
  const Run run = run_demo({{"GLBUDGET_LOG", "/dev/full"}, {"GLBUDGET_SENSOR", "cpu"}});
  INFO(run.result.err);
  check_app_unchanged(run);
  CHECK(count_lines_with(run.result.err, "glbudget:") == 1);
  CHECK(count_lines_with(run.result.err,
                         "glbudget: cannot write GLBUDGET_LOG file '/dev/full' (No space left on device)") == 1);
}

TEST_CASE("fault: the app is killed with SIGKILL while its log is being written", "[integration][faults]") {
  // The demo unpaced, killed after different numbers of rows. Asserts: every row the file holds
  // is whole (the shim writes whole rows at once, never a part of one), frames 1, 2, 3, ...
  for (const size_t rows_before_kill : {10, 50, 150}) {
    INFO("killed after " << rows_before_kill << " rows");
    const std::string log = temp_path("killed.csv"), out = temp_path("killed.out"), err = temp_path("killed.err");
    unlink(log.c_str());
    const int pid = spawn_process(
        demo_args(100000), {{"LD_PRELOAD", shim_path()}, {"GLBUDGET_LOG", log}, {"GLBUDGET_SENSOR", "cpu"}}, out, err);
    REQUIRE(pid > 0);
    const int64_t deadline = monotonic_ns() + 15'000'000'000;
    while (read_csv(log).size() < rows_before_kill + 1 && monotonic_ns() < deadline) sleep_ms(2);
    kill(pid, SIGKILL);
    CHECK(wait_process(pid) == 128 + SIGKILL);
    INFO(read_file(err));
    CHECK(whole_log(log).size() >= rows_before_kill);
    unlink(log.c_str());
    unlink(out.c_str());
    unlink(err.c_str());
  }
}

TEST_CASE("fault: a driver without pipeline statistics, timer queries, compute shaders or parallel compile",
          "[integration][faults]") {
  // GLBUDGET_TEST_HIDE_EXTENSIONS makes the shim's capability probe take an extension (and
  // the feature, where the core version has it) as absent. Asserts: the app and its images
  // unchanged; the log written, whole, with the columns that need the feature empty and the
  // others filled; one glbudget: line naming what is missing where the shim needed it (the
  // shim uses neither compute shaders nor KHR_parallel_shader_compile: no line, no change).
  struct Case {
    std::string hidden;
    std::set<std::string> empty_columns;
    std::vector<const char*> lines;
  };
  const char* const kStats = "glbudget: the driver lacks GL_ARB_pipeline_statistics_query";
  const char* const kTimer = "glbudget: the driver lacks GL_ARB_timer_query";
  const Case cases[] = {
      {"GL_ARB_pipeline_statistics_query", {"vertices", "fragments", "primitives"}, {kStats}},
      {"GL_ARB_timer_query", {"gpu_ns"}, {kTimer}},
      {"GL_ARB_compute_shader", {}, {}},
      {"GL_KHR_parallel_shader_compile", {}, {}},
      {"GL_ARB_pipeline_statistics_query,GL_ARB_timer_query,GL_ARB_compute_shader,GL_KHR_parallel_shader_compile",
       {"vertices", "fragments", "primitives", "gpu_ns"},
       {kStats, kTimer}},
  };
  for (const Case& c : cases) {
    INFO("hidden: " << c.hidden);
    const std::string log = temp_path("hidden.csv");
    unlink(log.c_str());
    const Run run =
        run_demo({{"GLBUDGET_LOG", log}, {"GLBUDGET_SENSOR", "cpu"}, {"GLBUDGET_TEST_HIDE_EXTENSIONS", c.hidden}});
    INFO(run.result.err);
    check_app_unchanged(run);
    const std::vector<Row> rows = whole_log(log);
    CHECK(by_frame(rows).size() == static_cast<size_t>(kFrames));
    for (const char* column : {"vertices", "fragments", "primitives", "gpu_ns"}) {
      INFO(column);
      if (c.empty_columns.count(column))
        CHECK(rows_with(rows, column) == 0);
      else
        CHECK(rows_with(rows, column) >= rows.size() / 2);  // a frame's results may come too late
    }
    CHECK(count_lines_with(run.result.err, "glbudget:") == c.lines.size());
    for (const char* line : c.lines) CHECK(count_lines_with(run.result.err, line) == 1);
    unlink(log.c_str());
  }
}

TEST_CASE("fault: a context destroyed, current, in the middle of a probe frame", "[integration][faults]") {
  // probe_destroy_mid_frame draws its fourth frame and destroys the context without a swap; a
  // new context draws the frames left. With the window at its second render-scale level and
  // probes every other frame, the fourth frame is a probe frame: its shadow targets and
  // read-backs go with the context. The app must end as it would without probes: its exit
  // code, its last image byte for byte, no glbudget: line; the log whole for both contexts
  // (the first context's frames 1-3, the second's 1-4), the second's probe frame flagged and
  // measured.
  auto run = [](int probe_period, const std::string& image, const std::string& log) {
    unlink(log.c_str());
    return run_process({probe_path("probe_destroy_mid_frame"), "--frames", "8", "--out", image},
                       {{"LD_PRELOAD", shim_path()},
                        {"GLBUDGET_LOG", log},
                        {"GLBUDGET_SENSOR", "cpu"},
                        {"GLBUDGET_FORCE", "1"},
                        {"GLBUDGET_PROBE_PERIOD", std::to_string(probe_period)}});
  };
  const std::string image_off = temp_path("destroyed_off.ppm"), image_on = temp_path("destroyed_on.ppm");
  const std::string log_off = temp_path("destroyed_off.csv"), log_on = temp_path("destroyed_on.csv");
  const ProcessResult off = run(0, image_off, log_off);
  const ProcessResult on = run(2, image_on, log_on);
  INFO("without probes: " << off.err << "\nwith probes: " << on.err);
  REQUIRE(off.exit_code == 0);
  CHECK(on.exit_code == 0);
  const std::string expected = read_file(image_off);
  REQUIRE(!expected.empty());
  CHECK(read_file(image_on) == expected);
  CHECK(count_lines_with(on.err, "glbudget:") == 0);
  const std::string text = read_file(log_on);
  REQUIRE(!text.empty());
  CHECK(text.back() == '\n');
  std::map<std::string, std::set<long>> frames;  // by context
  std::set<long> probed;
  for (const Row& row : read_csv_rows_by_name(log_on)) {
    REQUIRE(is_integer(row.at("frame")));
    frames[row.at("context")].insert(std::stol(row.at("frame")));
    if (row.at("probe") == "1" && row.at("context") == "1") {
      probed.insert(std::stol(row.at("frame")));
      CHECK(is_number(row.at("probe_error")));
    }
  }
  CHECK(frames == std::map<std::string, std::set<long>>{{"0", {1, 2, 3}}, {"1", {1, 2, 3, 4}}});
  CHECK(probed == std::set<long>{4});
  for (const std::string& path : {image_off, image_on, log_off, log_on}) unlink(path.c_str());
}
