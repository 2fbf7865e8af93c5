// Runs the built fqfilter binary as a user would, capturing exit code, stdout and stderr.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "tests/io/io_test_util.h"

namespace fq::test {

struct RunResult {
  int exit_code = -1;
  std::string out, err;
};

/// Single-quoted for the shell (built with append: GCC 12 gives a false -Wrestrict
/// warning on "literal" + std::string).
inline std::string quote(const std::string& s) {
  std::string q = "'";
  q.append(s).append("'");
  return q;
}

/// Exit code of a std::system status.
inline int exit_code_of(int status) {
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

/// Runs fqfilter with `args` (each passed as one shell word), capturing both streams.
inline RunResult run_fqfilter(const std::vector<std::string>& args, const ScratchDir& dir) {
  const std::string out = dir.file("stdout.txt"), err = dir.file("stderr.txt");
  std::string cmd = quote(FQFILTER_BIN);
  for (const std::string& a : args) cmd.append(" ").append(quote(a));
  cmd.append(" >").append(quote(out)).append(" 2>").append(quote(err));
  RunResult r;
  r.exit_code = exit_code_of(std::system(cmd.c_str()));
  r.out = read_bytes(out);
  r.err = read_bytes(err);
  return r;
}

}  // namespace fq::test
