#include "xvfb_server.hpp"

#include <signal.h>
#include <sys/wait.h>

#include <chrono>
#include <thread>

#include "run_process.hpp"

namespace {

enum class Start { listening, exited, silent };

// Waits up to five seconds for the server's socket. A server that exits first found its
// display taken after all (it has been reaped then).
Start wait_for_socket(pid_t pid, const std::string& socket) {
  for (int i = 0; i < 100; ++i) {
    if (file_exists(socket)) return Start::listening;
    int status = 0;
    if (waitpid(pid, &status, WNOHANG) == pid) return Start::exited;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return file_exists(socket) ? Start::listening : Start::silent;
}

void stop(pid_t pid) {
  kill(pid, SIGTERM);
  waitpid(pid, nullptr, 0);
}

}  // namespace

XvfbServer::XvfbServer(int first_display, const std::string& screen) {
  for (int n = first_display; n < first_display + 40; ++n) {
    const std::string number = std::to_string(n);
    if (file_exists("/tmp/.X" + number + "-lock") || file_exists("/tmp/.X11-unix/X" + number)) continue;
    const pid_t pid =
        spawn_process({"Xvfb", ":" + number, "-screen", "0", screen, "-nolisten", "tcp"}, {}, "/dev/null", "/dev/null");
    if (pid < 0) return;
    const Start start = wait_for_socket(pid, "/tmp/.X11-unix/X" + number);
    if (start == Start::listening) {
      pid_ = pid;
      display_ = ":" + number;
      return;
    }
    if (start == Start::silent) stop(pid);
  }
}

XvfbServer::~XvfbServer() {
  if (pid_ > 0) stop(pid_);
}
