#pragma once
// Runs the real `cumulo` executable (CUMULO_EXE, set by CMake) and captures its exit code and output,
// so the tests check exactly what a user sees.
#include <array>
#include <cstdio>
#include <string>
#include <sys/wait.h>

namespace cumulo::test {

struct CliResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

// Any shell command line, stdout and stderr together.
inline CliResult run_command(const std::string& command) {
  const std::string cmd = command + " 2>&1";
  CliResult r;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.output.append(buf.data(), n);
  int status = pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
  return r;
}

// `env`: optional "NAME=value ..." assignments for this child only.
inline CliResult run_cumulo(const std::string& args, const std::string& env = "") {
  return run_command((env.empty() ? "" : "env " + env + " ") + std::string(CUMULO_EXE) + " " + args);
}

}  // namespace cumulo::test
