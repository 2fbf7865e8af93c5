#include "daemon/http/http_access.h"

#include <arpa/inet.h>
#include <openssl/crypto.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>

#include "daemon/config/echo_value.h"

namespace fq::daemon {
namespace {

constexpr const char* kCookie = "fq_session";
constexpr size_t kMinTokenChars = 16;

// A token must be usable in a header and a cookie as it is: visible ASCII without ; , " \.
bool token_chars_ok(const std::string& t) {
  return std::all_of(t.begin(), t.end(), [](unsigned char c) {
    return c > 0x20 && c < 0x7f && c != ';' && c != ',' && c != '"' && c != '\\';
  });
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// "name:port", "[v6]:port", "name" -> the name (lower case), brackets removed.
std::string host_name(const std::string& host) {
  if (!host.empty() && host.front() == '[') {
    const size_t close = host.find(']');
    return close == std::string::npos ? std::string() : lower(host.substr(1, close - 1));
  }
  const size_t colon = host.find(':');
  return lower(colon == std::string::npos || host.find(':', colon + 1) != std::string::npos
                   ? host
                   : host.substr(0, colon));
}

bool ip_literal(const std::string& name) {
  unsigned char addr[16];
  return inet_pton(AF_INET, name.c_str(), addr) == 1 || inet_pton(AF_INET6, name.c_str(), addr) == 1;
}

bool same_token(const std::string& given, const std::string& token) {
  return given.size() == token.size() && CRYPTO_memcmp(given.data(), token.data(), token.size()) == 0;
}

// The bearer token a request carries; empty when none.
std::string bearer_token(const httplib::Request& req) {
  const std::string auth = req.get_header_value("Authorization");
  const std::string bearer = "Bearer ";
  if (auth.size() > bearer.size() &&
      std::equal(bearer.begin(), bearer.end(), auth.begin(),
                 [](char a, char b) { return std::tolower(a) == std::tolower(b); }))
    return auth.substr(bearer.size());
  return {};
}

// The login session cookie a request carries; empty when none.
std::string session_cookie(const httplib::Request& req) {
  const std::string cookies = req.get_header_value("Cookie");
  const std::string key = std::string(kCookie) + "=";
  for (size_t at = 0; at < cookies.size();) {
    while (at < cookies.size() && (cookies[at] == ' ' || cookies[at] == ';')) ++at;
    const size_t end = std::min(cookies.find(';', at), cookies.size());
    if (cookies.compare(at, key.size(), key) == 0)
      return cookies.substr(at + key.size(), end - at - key.size());
    at = end;
  }
  return {};
}

httplib::Server::HandlerResponse refuse(httplib::Response& res, int status, const std::string& text) {
  res.status = status;
  res.set_content(text, "text/plain");
  return httplib::Server::HandlerResponse::Handled;
}

int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

Status load_http_access(const HttpConfig& http, bool curve_on, HttpAccessRules& out) {
  HttpAccessRules r;
  r.allowed_hosts = http.allowed_hosts;
  r.curve_on = curve_on;
  r.tls = !http.tls_cert_file.empty();
  int port = 0;
  split_host_port(http.listen, r.listen_host, port);
  if (!http.token_file.empty()) {
    if (Status s = read_http_token(http.token_file, r.token); !s.ok())
      return invalid_argument("http.token_file " + http.token_file + ": " + s.message());
  }
  out = std::move(r);
  return {};
}

Status read_http_token(const std::string& path, std::string& token) {
  std::ifstream in(path);
  if (!in) return invalid_argument(std::string("cannot be read: ") + std::strerror(errno));
  token.clear();
  std::getline(in, token);
  while (!token.empty() && std::isspace(static_cast<unsigned char>(token.back()))) token.pop_back();
  if (token.size() < kMinTokenChars || !token_chars_ok(token))
    return invalid_argument("the token (first line) must be at least " + std::to_string(kMinTokenChars) +
                            " visible ASCII characters without ; , \" or \\ (e.g. openssl rand -hex 32)");
  return {};
}

bool host_allowed(const std::string& host, const HttpAccessRules& rules) {
  const std::string name = host_name(host);
  if (name.empty()) return false;
  if (rules.allowed_hosts.empty())
    return name == "localhost" || ip_literal(name) || name == lower(rules.listen_host);
  for (const std::string& a : rules.allowed_hosts) {
    const std::string allowed = lower(a);
    if (allowed == "*" || allowed == name) return true;
    // "*.example.com" names every host below example.com.
    if (allowed.rfind("*.", 0) == 0 && name.size() > allowed.size() - 1 &&
        name.compare(name.size() - (allowed.size() - 1), allowed.size() - 1, allowed, 1) == 0)
      return true;
  }
  return false;
}

void HttpAccess::set(HttpAccessRules rules) {
  auto fresh = std::make_shared<const HttpAccessRules>(std::move(rules));
  std::lock_guard<std::mutex> lock(mutex_);
  if (fresh->token != rules_->token) sessions_.clear();  // a new token ends what the old one opened
  rules_ = std::move(fresh);
}

std::shared_ptr<const HttpAccessRules> HttpAccess::rules() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return rules_;
}

httplib::Server::HandlerResponse HttpAccess::login(const httplib::Request& req, httplib::Response& res,
                                                   const HttpAccessRules& rules,
                                                   HttpRefusalCounters& refusals) {
  int retry_after_s = 1;
  if (!login_rate_.allow_now(req.remote_addr, retry_after_s)) {
    refusals.add(HttpRefusal::kLoginRate);
    login_log_.log(spdlog::level::warn, "http: /login from {} refused: over {} attempts a second",
                   echo_value(req.remote_addr), kLoginPerSecond);
    res.set_header("Retry-After", std::to_string(retry_after_s));
    return refuse(
        res, 429,
        "too many login attempts from this address; retry after " + std::to_string(retry_after_s) + " s\n");
  }
  if (rules.token.empty() || !same_token(req.get_param_value("token"), rules.token)) {
    refusals.add(HttpRefusal::kUnauthenticated);
    login_log_.log(spdlog::level::warn, "http: failed /login from {}", echo_value(req.remote_addr));
    return refuse(res, 401, "wrong token\n");
  }
  const std::string session = sessions_.open(steady_ns());
  if (session.empty()) return refuse(res, 503, "no session could be opened (no random bytes)\n");
  res.status = 303;
  res.set_header("Location", "./");
  res.set_header("Set-Cookie", std::string(kCookie) + "=" + session + "; Path=/; HttpOnly; SameSite=Strict" +
                                   (rules.tls ? "; Secure" : ""));
  return httplib::Server::HandlerResponse::Handled;
}

bool HttpAccess::authorized(const httplib::Request& req, const HttpAccessRules& rules) const {
  if (const std::string bearer = bearer_token(req); !bearer.empty()) return same_token(bearer, rules.token);
  const std::string session = session_cookie(req);
  return !session.empty() && sessions_.valid(session, steady_ns());
}

httplib::Server::HandlerResponse HttpAccess::check(const httplib::Request& req, httplib::Response& res,
                                                   HttpRefusalCounters& refusals) {
  using R = httplib::Server::HandlerResponse;
  if (req.path == "/healthz") return R::Unhandled;  // probes: nothing to read there
  const std::shared_ptr<const HttpAccessRules> rules = this->rules();
  if (!host_allowed(req.get_header_value("Host"), *rules)) {
    refusals.add(HttpRefusal::kBadHost);
    return refuse(res, 421, "Host not allowed (http.allowed_hosts)\n");
  }
  if (req.path == "/login") return login(req, res, *rules, refusals);
  if (!rules->token.empty()) {
    if (authorized(req, *rules)) return R::Unhandled;
    refusals.add(HttpRefusal::kUnauthenticated);
    res.set_header("WWW-Authenticate", "Bearer realm=\"fqd\"");
    return refuse(res, 401,
                  "authentication required: send \"Authorization: Bearer TOKEN\" (http.token_file), or open "
                  "/login?token=TOKEN once in a browser\n");
  }
  if (rules->curve_on && req.path != "/metrics") {
    refusals.add(HttpRefusal::kUnauthenticated);
    return refuse(
        res, 403,
        "fqd runs with [security] (CURVE) on: streams, results and the viewer need HTTP authentication; "
        "set [http] token_file\n");
  }
  return R::Unhandled;
}

}  // namespace fq::daemon
