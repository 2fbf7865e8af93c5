#include "clients/fqfilter/progress.h"

#include <unistd.h>

#include <cstdio>

namespace fq::cli {

Progress::Progress(bool wanted, std::string file)
    : enabled_(wanted && isatty(STDERR_FILENO)), file_(std::move(file)) {}

Progress::~Progress() {
  if (watched_) watched_->set_pass_observer({});
  if (enabled_) std::fputs("\r\033[K", stderr);
}

void Progress::show(const std::string& what) {
  if (!enabled_) return;
  // \r and "erase to end of line": the next state overwrites this one.
  std::fprintf(stderr, "\r\033[K%s: %s", file_.c_str(), what.c_str());
  std::fflush(stderr);
}

void Progress::watch(Engine& engine, int run, int runs) {
  if (!enabled_) return;
  watched_ = &engine;
  const std::string prefix = runs > 1 ? "run " + std::to_string(run) + "/" + std::to_string(runs) + ", " : "";
  show(prefix + "engine running");
  engine.set_pass_observer([this, prefix](const PassTiming& p) {
    char ms[32];
    std::snprintf(ms, sizeof ms, "%.0f ms", p.ms);
    show(prefix + p.name + " done (" + ms + ")");
  });
}

}  // namespace fq::cli
