// Running a command from a test: its exit code and its output.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace furnace::testing_support {

struct CommandResult {
  int exit_code;       // -1 when the command could not be started or did not exit normally
  std::string output;  // what it wrote to stdout (and stderr, unless `command` redirects it)
};

// Runs `command` through the shell and waits for it.
inline CommandResult run_command(const std::string& command) {
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return {-1, "popen failed: " + command};
  std::string out;
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, pipe)) out.append(buf, n);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

}  // namespace furnace::testing_support
