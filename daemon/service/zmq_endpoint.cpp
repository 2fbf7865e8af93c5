#include "daemon/service/zmq_endpoint.h"

#include <charconv>

namespace fq::daemon {
namespace {

// sockaddr_un's sun_path is 108 bytes with its terminating NUL (Linux).
constexpr size_t kMaxIpcPath = 107;

std::string tcp_problem(std::string address, EndpointUse use) {
  if (const size_t source = address.find(';'); use == EndpointUse::kConnect && source != std::string::npos)
    address.erase(0, source + 1);
  const size_t colon = address.rfind(':');
  if (colon == std::string::npos) return "has no port: tcp://HOST:PORT";
  const std::string host = address.substr(0, colon), port = address.substr(colon + 1);
  if (host.empty()) return "has no host (tcp://*:PORT binds every interface)";
  if (host == "*" && use == EndpointUse::kConnect) return "connects to host *: name the peer";
  if ((host.front() == '[') != (host.back() == ']')) return "has an unclosed [IPv6] address";
  if (host.find_first_of("[]", 1) < host.size() - 1) return "has a host with stray brackets";
  if (port == "*") return use == EndpointUse::kBind ? "" : "connects to port *: name the peer's port";
  int number = -1;
  const auto [end, ec] = std::from_chars(port.data(), port.data() + port.size(), number);
  if (port.empty() || ec != std::errc() || end != port.data() + port.size() || number < 0 || number > 65535)
    return "has port '" + port + "', not a number in 0..65535" + (use == EndpointUse::kBind ? " or *" : "");
  if (number == 0 && use == EndpointUse::kConnect) return "connects to port 0: name the peer's port";
  return {};
}

}  // namespace

std::string endpoint_problem(const std::string& endpoint, EndpointUse use) {
  const size_t scheme_end = endpoint.find("://");
  if (scheme_end == std::string::npos) return "is not a ZeroMQ address like tcp://127.0.0.1:5555";
  const std::string scheme = endpoint.substr(0, scheme_end), rest = endpoint.substr(scheme_end + 3);
  if (scheme == "tcp") return tcp_problem(rest, use);
  if (scheme == "ipc") {
    if (rest.empty()) return "has no path: ipc://PATH";
    if (rest.size() > kMaxIpcPath)
      return "has a path of " + std::to_string(rest.size()) + " bytes, over the " +
             std::to_string(kMaxIpcPath) + " of a unix socket address";
    return {};
  }
  if (scheme == "inproc") return rest.empty() ? "has no name: inproc://NAME" : "";
  return "has transport '" + scheme + "': fqd's sockets take tcp://, ipc:// or inproc://";
}

}  // namespace fq::daemon
