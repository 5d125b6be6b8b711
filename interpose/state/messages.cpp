#include "messages.hpp"

#include <unistd.h>

#include <mutex>
#include <set>

namespace glbudget {

void say(const std::string& text) {
  const std::string line = "glbudget: " + text + "\n";
  (void)!write(STDERR_FILENO, line.data(), line.size());
}

void say_once(const std::string& key, const std::string& text) {
  static std::mutex* mu = new std::mutex;  // never destroyed: hooks may run during exit
  static std::set<std::string>* said = new std::set<std::string>;
  std::lock_guard lock(*mu);
  if (said->insert(key).second) say(text);
}

}  // namespace glbudget
