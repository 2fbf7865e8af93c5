#include "daemon/http/web_root.h"

#include <filesystem>

namespace fq::daemon {

std::string installed_web_root(const std::string& exe) {
  return (std::filesystem::path(exe).parent_path() / ".." / "share" / "fq" / "web")
      .lexically_normal()
      .string();
}

void resolve_default_web_root(HttpConfig& http, const std::string& exe) {
  if (http.web_root != HttpConfig{}.web_root) return;
  std::error_code ec;  // a missing file is no error here: is_regular_file is then false
  if (std::filesystem::is_regular_file(std::filesystem::path(http.web_root) / "index.html", ec)) return;
  std::error_code link_ec;
  const std::filesystem::path self =
      exe.empty() ? std::filesystem::read_symlink("/proc/self/exe", link_ec) : std::filesystem::path(exe);
  if (link_ec || self.empty()) return;
  const std::string installed = installed_web_root(self.string());
  if (std::filesystem::is_regular_file(std::filesystem::path(installed) / "index.html", ec))
    http.web_root = installed;
}

}  // namespace fq::daemon
