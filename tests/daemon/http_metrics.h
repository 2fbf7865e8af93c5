// Reading fqd's HTTP answers in tests: a GET's body, and one sample of /metrics.
#pragma once

#include <string>

namespace fq::test {

/// The body of GET `path` from `base` ("http://127.0.0.1:PORT"); empty on failure.
std::string http_get(const std::string& base, const std::string& path);

/// The value of the sample `series` (name with labels, as printed) in Prometheus text; -1
/// when it is not there.
double metric_value(const std::string& text, const std::string& series);

}  // namespace fq::test
