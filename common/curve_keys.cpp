#include "common/curve_keys.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zmq.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

namespace fq {
namespace {

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return {};
  return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

// "name = \"value\"" or "name = value", split at the first '=' (a Z85 value may hold more);
// false for other lines.
bool key_line(const std::string& line, std::string& name, std::string& value) {
  const size_t eq = line.find('=');
  if (eq == std::string::npos) return false;
  name = trim(line.substr(0, eq));
  value = trim(line.substr(eq + 1));
  if (value.size() >= 2 && value.front() == '"' && value.back() == '"')
    value = value.substr(1, value.size() - 2);
  return true;
}

Status io_error(const std::string& path, const std::string& what) {
  return invalid_argument("key file " + path + ": " + what);
}

}  // namespace

bool valid_z85_key(const std::string& key) {
  if (key.size() != 40) return false;
  uint8_t raw[32];
  return zmq_z85_decode(raw, key.c_str()) != nullptr;
}

Status make_curve_key_pair(CurveKeyPair& out) {
  char pub[41], sec[41];
  if (zmq_curve_keypair(pub, sec) != 0)
    return {StatusCode::kUnavailable, "this libzmq was built without CURVE support"};
  out = {pub, sec};
  return {};
}

Status read_curve_key_file(const std::string& path, bool need_secret, CurveKeyPair& out) {
  std::ifstream in(path);
  if (!in) return io_error(path, "cannot be read");
  out = {};
  std::string line, name, value;
  for (int n = 1; std::getline(in, line); ++n) {
    line = trim(line);
    if (line.empty() || line[0] == '#') continue;
    if (!key_line(line, name, value) || (name != "public" && name != "secret"))
      return io_error(path, "line " + std::to_string(n) + ": expected public = \"...\" or secret = \"...\"");
    if (!valid_z85_key(value))
      return io_error(path, "line " + std::to_string(n) + ": not a 40-character Z85 key");
    (name == "public" ? out.public_key : out.secret_key) = value;
  }
  if (out.public_key.empty()) return io_error(path, "no public key");
  if (need_secret && out.secret_key.empty()) return io_error(path, "no secret key (a public-key file?)");
  return {};
}

Status write_curve_key_file(const std::string& path, const CurveKeyPair& keys) {
  std::ostringstream text;
  text << "# ZeroMQ CURVE keys (Z85)" << (keys.secret_key.empty() ? "" : ": keep this file secret") << "\n";
  text << "public = \"" << keys.public_key << "\"\n";
  if (!keys.secret_key.empty()) text << "secret = \"" << keys.secret_key << "\"\n";
  // A secret key file is created owner-only (never readable for a moment under the umask) and
  // made so again if it existed with a wider mode; a failure to do either is an error.
  const mode_t mode = keys.secret_key.empty() ? 0644 : 0600;
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, mode);
  if (fd < 0) return io_error(path, std::string("cannot be written: ") + std::strerror(errno));
  if (!keys.secret_key.empty() && ::fchmod(fd, S_IRUSR | S_IWUSR) != 0) {
    const int err = errno;
    ::close(fd);
    return io_error(path, std::string("cannot be made owner-only: ") + std::strerror(err));
  }
  const std::string bytes = text.str();
  for (size_t done = 0; done < bytes.size();) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int err = errno;
      ::close(fd);
      return io_error(path, std::string("write failed: ") + std::strerror(err));
    }
    done += size_t(n);
  }
  if (::close(fd) != 0) return io_error(path, std::string("write failed: ") + std::strerror(errno));
  return {};
}

Status read_public_keys(const std::string& path, std::vector<std::string>& out) {
  std::ifstream in(path);
  if (!in) return io_error(path, "cannot be read");
  std::string line, name, value;
  for (int n = 1; std::getline(in, line); ++n) {
    line = trim(line);
    if (line.empty() || line[0] == '#') continue;
    // A bare key first: '=' is one of Z85's characters, so about 38 % of keys hold one and
    // would read as "name = value".
    if (!valid_z85_key(line) && key_line(line, name, value)) {
      if (name == "secret") continue;
      if (name != "public")
        return io_error(path, "line " + std::to_string(n) + ": unknown entry '" + name + "'");
      line = value;
    }
    if (!valid_z85_key(line))
      return io_error(path, "line " + std::to_string(n) + ": not a 40-character Z85 key");
    out.push_back(line);
  }
  return {};
}

}  // namespace fq
