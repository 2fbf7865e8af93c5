// The command line the tools share: a CLI11 app with the tool's description, --help and
// --version (fq::version_line), and the main() of a tool whose options all fill one struct.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <utility>

#include "common/tool_main.h"
#include "common/version.h"

namespace fq::client {

/// A tool's CLI::App: its description, --help, and --version printing fq::version_line(tool).
class ToolApp : public CLI::App {
 public:
  ToolApp(std::string description, const std::string& tool) : CLI::App(std::move(description)) {
    set_version_flag("--version", version_line(tool));
  }
};

/// main() of a tool whose options all go into one Args: `add_options` registers them on the
/// tool's app, `run` gets them parsed. --help, --version and a bad command line end the tool
/// before `run`, as CLI11_PARSE does; an exception ends it as fq::tool_main says.
template <class Args>
int args_main(const char* tool, const char* description, void (*add_options)(CLI::App&, Args&),
              int (*run)(Args&), int argc, char** argv) {
  return tool_main(
      tool,
      [&](int argc, char** argv) {
        ToolApp app{description, tool};
        Args args;
        add_options(app, args);
        CLI11_PARSE(app, argc, argv);
        return run(args);
      },
      argc, argv);
}

}  // namespace fq::client
