// fqfilter's progress line: what it is doing on the current mesh (reading, each engine pass,
// writing), redrawn in place on stderr. Only on a terminal and without --json, so logs and
// pipes stay clean.
#pragma once

#include <string>

#include "common/non_copyable.h"
#include "kernels/engine.h"

namespace fq::cli {

class Progress : NonCopyable {
 public:
  /// Enabled when `wanted` and stderr is a terminal.
  Progress(bool wanted, std::string file);
  ~Progress();  ///< clears the line

  bool enabled() const { return enabled_; }
  /// Shows "<file>: <what>".
  void show(const std::string& what);
  /// Has `engine` report each pass here (run `run` of `runs`); detached by the destructor.
  void watch(Engine& engine, int run, int runs);

 private:
  bool enabled_;
  std::string file_;
  Engine* watched_ = nullptr;
};

}  // namespace fq::cli
