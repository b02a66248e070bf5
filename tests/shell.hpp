// A shell command as the tests run the beadtwin program: its exit code and everything it printed.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace beadtwin::testing {

struct ShellResult {
  int code = -1;       // the exit code; -1 when it did not exit (killed by a signal) or did not start
  std::string output;  // what it wrote to the pipe (add 2>&1 to the command for stderr too)
};

inline ShellResult shell(const std::string& cmd) {
  ShellResult r;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  char buf[4096];
  for (std::size_t n; (n = fread(buf, 1, sizeof buf, p)) > 0;) r.output.append(buf, n);
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

}  // namespace beadtwin::testing
