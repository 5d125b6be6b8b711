// The file sensor: an external meter writing "timestamp,watts" lines into a FIFO or a file.
#include <catch2/catch.hpp>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <thread>

#include "fake_sysfs.hpp"
#include "glbudget/sensors/registry.hpp"
#include "glbudget/sensors/sensor.hpp"
#include "swap_until_valid.hpp"

using namespace glbudget::sensors;
using glbudget::sensors::testing::FakeSysfs;
using namespace std::chrono_literals;
using glbudget::sensors::testing::swap_until_valid;

namespace {

OpenResult open_file_sensor(const std::string& path) {
  std::string error;
  const auto spec = parse_sensor_spec("file:" + path, error);
  REQUIRE(spec);
  return open_source(*spec, SourceEnvironment{});
}

void write_all(int fd, const std::string& text) {
  REQUIRE(::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size()));
}

}  // namespace

TEST_CASE("the file sensor reads a FIFO without blocking, before and after the meter starts", "[file]") {
  FakeSysfs dir;  // just a temporary directory
  const std::string fifo = (dir.root() / "meter").string();
  REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);

  auto opened = open_file_sensor(fifo);
  REQUIRE(opened.source);
  Source& source = *opened.source;
  CHECK(source.read(0).status == ReadStatus::no_new_data);  // no writer yet: must not block

  const int writer = ::open(fifo.c_str(), O_WRONLY);
  REQUIRE(writer >= 0);
  write_all(writer, "timestamp,watts\n1.0,10\n1.1,20\n1.2,3");  // last line incomplete
  Reading r = source.read(0);
  CHECK(r.status == ReadStatus::ok);
  CHECK(r.kind == ReadingKind::power_w);
  CHECK(r.value == Approx(15.0));  // mean of the complete lines

  write_all(writer, "0\n");  // completes "1.2,30"
  r = source.read(0);
  CHECK(r.value == Approx(30.0));
  CHECK(source.read(0).status == ReadStatus::no_new_data);

  ::close(writer);  // the meter stops: silence, which the Sampler turns into a stall
  CHECK(source.read(0).status == ReadStatus::no_new_data);
}

TEST_CASE("bad lines and timestamps that go backwards are discarded and counted", "[file][faults]") {
  FakeSysfs dir;
  const std::string fifo = (dir.root() / "meter").string();
  REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);
  auto opened = open_file_sensor(fifo);
  REQUIRE(opened.source);
  const int writer = ::open(fifo.c_str(), O_WRONLY);
  REQUIRE(writer >= 0);

  write_all(writer, "2.0,12\nhello\n2.1,nan\n2.2,-4\n1.5,99\n# comment\n2.3,14\n");
  const Reading r = opened.source->read(0);
  CHECK(r.status == ReadStatus::ok);
  CHECK(r.value == Approx(13.0));
  CHECK(r.discarded_garbage == 3);
  CHECK(r.discarded_backwards == 1);

  write_all(writer, "junk\n");
  const Reading only_junk = opened.source->read(0);
  CHECK(only_junk.status == ReadStatus::no_new_data);
  CHECK(only_junk.discarded_garbage == 1);

  write_all(writer, std::string(5000, 'x'));  // a stream with no line breaks at all
  CHECK(opened.source->read(0).discarded_garbage == 1);
  ::close(writer);
}

TEST_CASE("an implausible line is dropped on its own, not averaged with good ones; bad bytes are escaped",
          "[file][faults]") {
  FakeSysfs dir;
  const std::string fifo = (dir.root() / "meter").string();
  REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);
  auto opened = open_file_sensor(fifo);
  REQUIRE(opened.source);
  const int writer = ::open(fifo.c_str(), O_WRONLY);
  REQUIRE(writer >= 0);

  // The mean of the three, 2008 W, would pass the Sampler's plausibility check (5000 W).
  write_all(writer, "1.0,12\n1.1,6000\n1.2,12\n");
  const Reading r = opened.source->read(0);
  CHECK(r.status == ReadStatus::ok);
  CHECK(r.value == Approx(12.0));
  CHECK(r.discarded_garbage == 1);
  CHECK(r.detail.find("implausible power in \"1.1,6000\"") != std::string::npos);

  write_all(writer, "\x1b[2J\x01," + std::string(100, '9') + "\n");
  const Reading binary = opened.source->read(0);
  CHECK(binary.discarded_garbage == 1);
  CHECK(binary.detail.find("bad line \"\\x1b[2J\\x01,999") != std::string::npos);
  CHECK(binary.detail.size() < 200);
  ::close(writer);
}

TEST_CASE("a meter's FIFO drives per-frame power through the sampling thread", "[file]") {
  FakeSysfs dir;
  const std::string fifo = (dir.root() / "meter").string();
  REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);
  auto opened = open_file_sensor(fifo);
  REQUIRE(opened.source);
  const int writer = ::open(fifo.c_str(), O_WRONLY);
  REQUIRE(writer >= 0);

  SamplerOptions options;
  options.period = 1ms;
  PowerSensor sensor(std::move(opened.source), options);
  CHECK_FALSE(sensor.is_estimate());
  std::atomic<bool> stop{false};
  std::thread meter([&] {
    for (int i = 0; !stop; ++i) {
      write_all(writer, std::to_string(i * 0.002) + ",25\n");
      std::this_thread::sleep_for(2ms);
    }
  });
  const bool started = swap_until_valid(sensor);
  std::this_thread::sleep_for(40ms);
  const FrameEnergy frame = sensor.on_swap(monotonic_now_ns());
  stop = true;
  meter.join();
  ::close(writer);
  REQUIRE(started);
  CHECK(frame.sensor == "file");
  REQUIRE(frame.valid);
  CHECK(frame.mean_power_w == Approx(25.0).epsilon(0.01));
}

TEST_CASE("the file sensor follows a regular file from its end", "[file]") {
  FakeSysfs dir;
  const auto path = dir.root() / "meter.csv";
  std::ofstream(path) << "0.5,1000\n";  // history from before glbudget started
  auto opened = open_file_sensor(path.string());
  REQUIRE(opened.source);
  CHECK(opened.source->read(0).status == ReadStatus::no_new_data);
  std::ofstream(path, std::ios::app) << "1.0,7.5\n";
  const Reading r = opened.source->read(0);
  CHECK(r.status == ReadStatus::ok);
  CHECK(r.value == Approx(7.5));
}

TEST_CASE("a missing meter file is unavailable, with the reason", "[file]") {
  const auto opened = open_file_sensor("/nonexistent/meter");
  CHECK_FALSE(opened.source);
  CHECK(opened.why_not.find("No such file") != std::string::npos);
}
