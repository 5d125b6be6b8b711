// Unit: GLBUDGET_INSTRUMENT and GLBUDGET_DUMP. Instrumentation perturbs timing: it is off
// unless asked for, and a dump asks for it unless GLBUDGET_INSTRUMENT says otherwise.
#include <algorithm>
#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "options.hpp"
#include "parse_env.hpp"

using namespace glbudget;

TEST_CASE("instrumentation is off unless GLBUDGET_INSTRUMENT or GLBUDGET_DUMP asks for it", "[unit]") {
  std::string w;
  CHECK_FALSE(parse_env({}, &w).instrument);
  CHECK_FALSE(parse_env({"GLBUDGET_LOG=/tmp/x.csv"}, &w).instrument);
  for (const char* on : {"GLBUDGET_INSTRUMENT=1", "GLBUDGET_INSTRUMENT=on"}) CHECK(parse_env({on}, &w).instrument);
  for (const char* off : {"GLBUDGET_INSTRUMENT=0", "GLBUDGET_INSTRUMENT=off", "GLBUDGET_INSTRUMENT="})
    CHECK_FALSE(parse_env({off}, &w).instrument);
  const Options dump = parse_env({"GLBUDGET_DUMP=/tmp/shaders"}, &w);
  CHECK(dump.instrument);
  CHECK(dump.dump_dir == "/tmp/shaders");
  // An explicit switch wins over the dump's implicit one, in either order.
  CHECK_FALSE(parse_env({"GLBUDGET_DUMP=/tmp/shaders", "GLBUDGET_INSTRUMENT=0"}, &w).instrument);
  CHECK_FALSE(parse_env({"GLBUDGET_INSTRUMENT=0", "GLBUDGET_DUMP=/tmp/shaders"}, &w).instrument);
  CHECK(w.empty());
}

TEST_CASE("a malformed GLBUDGET_INSTRUMENT is named once and leaves the default", "[unit]") {
  for (const char* bad : {"GLBUDGET_INSTRUMENT=yes please", "GLBUDGET_INSTRUMENT=2"}) {
    INFO(bad);
    std::string w;
    CHECK_FALSE(parse_env({bad}, &w).instrument);
    CHECK(w.rfind("glbudget: GLBUDGET_INSTRUMENT=", 0) == 0);
    CHECK(std::count(w.begin(), w.end(), '\n') == 1);
    w.clear();
    CHECK(parse_env({bad, "GLBUDGET_DUMP=/tmp/d"}, &w).instrument);  // the dump's default stands
  }
}
