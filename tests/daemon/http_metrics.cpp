#include "tests/daemon/http_metrics.h"

#include <httplib.h>

#include <cstdlib>

namespace fq::test {

std::string http_get(const std::string& base, const std::string& path) {
  httplib::Client c(base);
  c.set_read_timeout(30, 0);
  auto r = c.Get(path.c_str());
  return r ? r->body : std::string();
}

double metric_value(const std::string& text, const std::string& series) {
  const std::string key = "\n" + series + " ";
  const size_t at = ("\n" + text).find(key);
  if (at == std::string::npos) return -1;
  return std::strtod(text.c_str() + at + key.size() - 1, nullptr);
}

}  // namespace fq::test
