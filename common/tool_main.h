// The outermost frame of every command-line tool: bad input is reported through Status values
// by the tool itself; a fault that still escapes (out of memory, a ZeroMQ or filesystem error)
// ends the tool with one line and exit status 1 instead of std::terminate's abort.
#pragma once

#include <cstdio>
#include <exception>

namespace fq {

/// Returns body(argc, argv), or 1 after printing "<tool>: error: <what>" for an exception.
template <typename Body>
int tool_main(const char* tool, Body&& body, int argc, char** argv) noexcept {
  try {
    return body(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\n", tool, e.what());
  } catch (...) {
    std::fprintf(stderr, "%s: error: unknown exception\n", tool);
  }
  return 1;
}

}  // namespace fq
