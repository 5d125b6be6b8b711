// What the shim tells the user: one line on stderr prefixed "glbudget: ", written with
// write(2) (no stdio buffer shared with the app); say_once() says a thing once per key per
// process, however often the app repeats what caused it.
#pragma once
#include <string>

namespace glbudget {

void say(const std::string& text);
void say_once(const std::string& key, const std::string& text);

}  // namespace glbudget
