#include "daemon/pipeline/curve_auth.h"

#include <spdlog/spdlog.h>
#include <sys/socket.h>

#include <zmq_addon.hpp>

#include "daemon/pipeline/daemon_threads.h"

namespace fq::daemon {

Status load_curve_server_keys(const SecurityConfig& c, CurveServerKeys& out) {
  if (c.client_keys_file.empty())
    return invalid_argument(
        "security.curve_key_file is set but security.client_keys_file is not: "
        "with CURVE on, only listed client keys may connect");
  if (Status s = read_curve_key_file(c.curve_key_file, true, out.server); !s.ok()) return s;
  std::vector<std::string> keys;
  if (Status s = read_public_keys(c.client_keys_file, keys); !s.ok()) return s;
  if (keys.empty()) return invalid_argument("key file " + c.client_keys_file + ": no client keys");
  out.clients = {keys.begin(), keys.end()};
  out.control.clear();
  if (c.control_keys_file.empty()) return {};
  keys.clear();
  if (Status s = read_public_keys(c.control_keys_file, keys); !s.ok()) return s;
  if (keys.empty()) return invalid_argument("key file " + c.control_keys_file + ": no client keys");
  out.control = {keys.begin(), keys.end()};
  return {};
}

void make_curve_server(zmq::socket_t& s, const CurveKeyPair& server, const char* domain) {
  s.set(zmq::sockopt::curve_server, 1);
  s.set(zmq::sockopt::curve_secretkey, server.secret_key);
  s.set(zmq::sockopt::zap_domain, domain);
}

bool is_local_endpoint(const std::string& e) {
  if (e.rfind("ipc://", 0) == 0 || e.rfind("inproc://", 0) == 0) return true;
  const std::string tcp = "tcp://";
  if (e.rfind(tcp, 0) != 0) return false;
  return is_loopback_host(e.substr(tcp.size(), e.rfind(':') - tcp.size()));
}

bool is_loopback_host(const std::string& host) {
  return host == "localhost" || host == "[::1]" || host == "::1" || host.rfind("127.", 0) == 0 ||
         host == "lo";
}

bool ClientKeys::allowed(const std::string& key) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return keys_->count(key) > 0;
}

void ClientKeys::set(std::set<std::string> keys) {
  auto fresh = std::make_shared<const std::set<std::string>>(std::move(keys));
  std::lock_guard<std::mutex> lock(mutex_);
  keys_ = std::move(fresh);
  ++generation_;
}

std::string sender_key(const zmq::message_t& m) {
  const char* user = zmq_msg_gets(const_cast<zmq_msg_t*>(m.handle()), "User-Id");
  return user ? user : "";
}

void cut_sender(const zmq::message_t& m) {
  const int fd = zmq_msg_get(const_cast<zmq_msg_t*>(m.handle()), ZMQ_SRCFD);
  if (fd >= 0) ::shutdown(fd, SHUT_RDWR);
}

bool admit_sender(const zmq::message_t& m, const ClientKeys* keys, RefusalCounters& refusals) {
  if (!keys || keys->allowed(sender_key(m))) return true;
  refusals.add(Refusal::kUnauthenticated);
  cut_sender(m);
  return false;
}

ZapHandler::ZapHandler(zmq::context_t& context, const ClientKeys& allowed, RefusalCounters& refusals,
                       const ClientKeys* control)
    : allowed_(allowed), control_(control), refusals_(refusals) {
  zmq::socket_t s(context, zmq::socket_type::rep);
  s.set(zmq::sockopt::linger, 0);
  s.bind("inproc://zeromq.zap.01");  // before any CURVE socket accepts a connection
  thread_ = std::thread([this, s = std::move(s)]() mutable {
    name_this_thread("zap");  // its CPU counts in fq_cpu_seconds_total
    run(std::move(s));
  });
}

ZapHandler::~ZapHandler() { join(); }

void ZapHandler::join() {
  if (thread_.joinable()) thread_.join();
}

void ZapHandler::run(zmq::socket_t socket) {
  std::vector<zmq::message_t> req;
  for (;;) {
    req.clear();
    try {
      if (!zmq::recv_multipart(socket, std::back_inserter(req))) continue;
    } catch (const zmq::error_t& e) {
      if (e.num() == ETERM) break;
      continue;
    }
    // version, request id, domain, address, routing id, mechanism, credentials...
    std::string status = "400", text = "unknown client key";
    std::string user;
    if (req.size() >= 7 && req[5].to_string() == "CURVE" && req[6].size() == 32) {
      char z85[41];
      zmq_z85_encode(z85, req[6].data<uint8_t>(), 32);
      const bool control = control_ && req[2].to_string() == kControlZapDomain;
      if ((control ? *control_ : allowed_).allowed(z85)) {
        status = "200", text = "OK", user = z85;
      } else {
        refusals_.add(Refusal::kUnauthenticated);
        log_.log(spdlog::level::warn, "refused a connection from {}: client key {} is not in security.{}",
                 req[3].to_string(), z85, control ? "control_keys_file" : "client_keys_file");
      }
    } else {
      refusals_.add(Refusal::kUnauthenticated);
    }
    const std::string request_id = req.size() > 1 ? req[1].to_string() : std::string();
    std::vector<zmq::const_buffer> rep{zmq::str_buffer("1.0"), zmq::buffer(request_id), zmq::buffer(status),
                                       zmq::buffer(text),      zmq::buffer(user),       zmq::str_buffer("")};
    try {
      zmq::send_multipart(socket, rep);
    } catch (const zmq::error_t& e) {
      if (e.num() == ETERM) break;
    }
  }
  socket.close();
}

}  // namespace fq::daemon
