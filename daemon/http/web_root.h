// Where fqd finds its live viewer when the configuration names no http.web_root: `web` in the
// working directory when it holds the viewer (fqd run from a source tree, as before), else the
// viewer installed with this fqd (`cmake --install`: <prefix>/share/fq/web beside
// <prefix>/bin/fqd), so that an installed fqd serves its viewer from any directory.
#pragma once

#include <string>

#include "daemon/config/service_config.h"

namespace fq::daemon {

/// The folder of the viewer installed with the executable at `exe` (<exe dir>/../share/fq/web).
std::string installed_web_root(const std::string& exe);

/// Replaces the built-in default web_root as described above (a value from a file stays).
/// `exe` is this process's executable (default: /proc/self/exe).
void resolve_default_web_root(HttpConfig& http, const std::string& exe = "");

}  // namespace fq::daemon
