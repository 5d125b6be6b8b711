// A private X server for one test, started directly rather than through xvfb-run: xvfb-run's
// own exit paths (its temporary authority directory's cleanup failing now and then under a
// loaded machine) turned into a test failure unrelated to the program under test.
#pragma once
#include <sys/types.h>

#include <string>

class XvfbServer {
 public:
  // Starts Xvfb on the first free display from first_display on (a display whose lock file
  // exists, or whose server exits before its socket appears, is passed over), with one screen
  // of the given geometry ("320x240x24"), listening on its local socket only.
  XvfbServer(int first_display, const std::string& screen);
  ~XvfbServer();  // stops the server, however the test ended
  XvfbServer(const XvfbServer&) = delete;
  XvfbServer& operator=(const XvfbServer&) = delete;

  bool running() const { return pid_ > 0; }
  // ":N", the value DISPLAY must hold; empty when no server could be started.
  const std::string& display() const { return display_; }

 private:
  pid_t pid_ = -1;
  std::string display_;
};
