#include "daemon/service/credentials.h"

#include <string_view>

namespace fq::daemon {
namespace {

// systemd's rule for a credential name: a file name, not a path.
bool valid_name(std::string_view name) {
  return !name.empty() && name != "." && name != ".." && name.find('/') == std::string_view::npos;
}

}  // namespace

void resolve_credentials(DaemonConfig& c, const char* credentials_dir) {
  if (credentials_dir == nullptr || *credentials_dir == '\0') return;
  const std::string_view prefix = kCredentialPrefix;
  for (std::string* value :
       {&c.security.curve_key_file, &c.security.client_keys_file, &c.security.control_keys_file,
        &c.http.token_file, &c.http.tls_cert_file, &c.http.tls_key_file}) {
    if (!value->starts_with(prefix) || !valid_name(std::string_view(*value).substr(prefix.size()))) continue;
    *value = std::string(credentials_dir) + "/" + value->substr(prefix.size());
  }
}

std::string credential_problem(const std::string& value) {
  const std::string_view prefix = kCredentialPrefix;
  if (!value.starts_with(prefix)) return "";
  if (!valid_name(std::string_view(value).substr(prefix.size())))
    return "is no credential name (a file name after \"credential:\", without '/')";
  return "names a credential, but $CREDENTIALS_DIRECTORY is not set (systemd sets it for a unit with "
         "LoadCredential=; docs/DAEMON.md)";
}

}  // namespace fq::daemon
