// The tools' convention for an option with a meaningful default: --help shows the default;
// a bounded one also refuses values outside its range (CLI11's message, before the tool runs).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace fq::client {

/// `name` into `value`, whose current value --help shows as the default.
template <class T>
CLI::Option* add_defaulted(CLI::App& app, const std::string& name, T& value, const std::string& help) {
  return app.add_option(name, value, help)->capture_default_str();
}

/// add_defaulted, refusing values outside [lo, hi].
template <class T, class Bound>
CLI::Option* add_ranged(CLI::App& app, const std::string& name, T& value, const std::string& help, Bound lo,
                        Bound hi) {
  return add_defaulted(app, name, value, help)->check(CLI::Range(lo, hi));
}

}  // namespace fq::client
