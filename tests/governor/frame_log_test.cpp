#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>

#include "glbudget/analysis/frame_log.hpp"

using namespace glbudget::model;
using namespace glbudget::analysis;

TEST_CASE("frame log groups rows by frame and reads empty fields as not measured", "[model][log]") {
  std::istringstream csv(
      "frame,time_ns,context,pass,batches,vertices,fragments,primitives,gpu_ns\n"
      "0,100,0xa,00000000000000aa,3,300,9000,100,5000\n"
      "0,100,0xa,fixed-function,1,4,,2,\n"
      "1,200,0xa,00000000000000aa,4,400,8000,,\n");
  const auto log = read_frame_log(csv, "inline");
  REQUIRE(log);
  REQUIRE(log->frames.size() == 2);
  CHECK(log->rows == 3);
  CHECK(log->rows_skipped == 0);
  const LoggedFrame& first = log->frames[0];
  CHECK(first.frame == 0);
  CHECK(first.time_ns == 100.0);
  CHECK(first.context == "0xa");
  REQUIRE(first.passes.size() == 2);
  CHECK(first.passes[0].counts.vertices == 300.0);
  CHECK(first.passes[0].gpu_ns == 5000.0);
  CHECK(std::isnan(first.passes[1].counts.fragments));
  CHECK(std::isnan(first.passes[1].gpu_ns));
  CHECK(std::isnan(first.power_w));  // the log has no power columns at all
  CHECK(std::isnan(log->frames[1].passes[0].primitives));
}

TEST_CASE("frame log reads power columns in any column order", "[model][log]") {
  std::istringstream csv(
      "pass,frame,fragments,vertices,batches,power_w,energy_j,sensor,extra\r\n"
      "p,7,10,20,30,41.5,2.5,cpu,ignored\r\n"
      "q,7,1,2,3,41.5,2.5,cpu,ignored\r\n");
  const auto log = read_frame_log(csv, "inline");
  REQUIRE(log);
  REQUIRE(log->frames.size() == 1);
  CHECK(log->frames[0].frame == 7);
  CHECK(log->frames[0].power_w == 41.5);
  CHECK(log->frames[0].energy_j == 2.5);
  CHECK(log->frames[0].sensor == "cpu");
  CHECK(log->frames[0].passes[1].counts.batches == 3.0);
}

TEST_CASE("frame log skips malformed rows and refuses a log without the needed columns", "[model][log]") {
  std::istringstream csv(
      "frame,pass,batches,vertices,fragments,power_w\n"
      "0,p,1,2,3,30\n"
      "x,p,1,2,3,30\n"
      "1,p,1,two,3,30\n"
      "-1,p,1,2,3,30\n"
      "2,,1,2,3,30\n"
      "\n"
      "3,p,1,2,3,\n");
  const auto log = read_frame_log(csv, "inline");
  REQUIRE(log);
  CHECK(log->rows_skipped == 4);
  REQUIRE(log->frames.size() == 2);
  CHECK(std::isnan(log->frames[1].power_w));

  std::istringstream wrong("frame,time_ns,pass\n0,1,p\n");
  CHECK(!read_frame_log(wrong, "inline"));
  std::istringstream empty("");
  CHECK(!read_frame_log(empty, "inline"));
  CHECK(!read_frame_log_file("/nonexistent/glbudget.csv"));
}

TEST_CASE("frame log keeps contexts apart and replays the busiest", "[model][log]") {
  std::istringstream csv(
      "frame,context,pass,batches,vertices,fragments\n"
      "0,1,p,1,1,1\n0,2,p,1,1,1\n1,2,p,1,1,1\n2,2,p,1,1,1\n1,1,p,1,1,1\n");
  const auto log = read_frame_log(csv, "inline");
  REQUIRE(log);
  CHECK(log->frames.size() == 5);
  const auto busiest = frames_of_busiest_context(*log);
  REQUIRE(busiest.size() == 3);
  CHECK(busiest[2].context == "2");
  CHECK(busiest[2].frame == 2);
}

TEST_CASE("the committed synthetic log reads completely", "[model][log]") {
  const auto log = read_frame_log_file(GLBUDGET_SOURCE_DIR "/tests/data/logs/synthetic_six_pass.csv");
  REQUIRE(log);
  CHECK(log->frames.size() == 300);
  CHECK(log->rows == 300 * 7);
  CHECK(log->rows_skipped == 0);
  for (const LoggedFrame& frame : log->frames) {
    CHECK(frame.passes.size() == 7);
    CHECK(std::isfinite(frame.power_w));
  }
}
