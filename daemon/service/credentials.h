// Files handed to fqd by its service manager: a configuration value `credential:NAME` (any key
// naming a key, token or certificate file) means the file NAME in $CREDENTIALS_DIRECTORY, where
// systemd puts what the unit's `LoadCredential=NAME:/etc/fq/...` names (readable by the unit's
// DynamicUser although the source is root's, 0600). Every other value is a path as before.
#pragma once

#include <string>

#include "daemon/config/config.h"

namespace fq::daemon {

inline constexpr const char* kCredentialPrefix = "credential:";

/// Replaces each `credential:NAME` among the file keys of `config` by `credentials_dir`/NAME
/// (fqd passes $CREDENTIALS_DIRECTORY). A value left as it was (no directory, a NAME that is no
/// file name) is a problem config_problems() names with credential_problem().
void resolve_credentials(DaemonConfig& config, const char* credentials_dir);

/// Why `value` is an unresolved `credential:NAME`; empty for any other value.
std::string credential_problem(const std::string& value);

}  // namespace fq::daemon
