// Programs started as child processes for the tests (fqd, fqpub, fqsub), stdout on a pipe.
#pragma once

#include <sys/types.h>

#include <cstdio>
#include <string>
#include <vector>

namespace fq::test {

struct Child {
  pid_t pid = -1;
  FILE* out = nullptr;  ///< the child's stdout
};

/// Starts `path` with `args`; stdout on a pipe (read it through Child::out).
Child spawn(const std::string& path, const std::vector<std::string>& args);

/// Waits up to `seconds` for the child; its exit status, or -1 when it was killed by a
/// signal or had to be killed because it did not exit in time.
int wait_exit(pid_t pid, int seconds = 60);

/// Everything the child still writes on stdout until it closes it.
std::string read_all(FILE* out);

/// An fqd config for child-process tests: CPU engine on one thread, every endpoint
/// tcp://127.0.0.1:*, log level warn, a 60 s budget; `defaults` (TOML lines) is appended to
/// the [defaults] table and may open its sub-tables.
std::string child_fqd_config(const std::string& defaults = "");

}  // namespace fq::test
