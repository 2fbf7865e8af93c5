// Numeric options that each set one member of a parameter struct, written as a table of
// {flag, member, help} rows: a long list of such options reads as data, and the code that
// registers them is written once.
#pragma once

#include <CLI/CLI.hpp>
#include <cstddef>
#include <variant>

namespace fq::client {

/// One row: `flag` sets `member` of P.
template <class P>
struct MemberOption {
  const char* flag;
  std::variant<int P::*, float P::*> member;
  const char* help;
};

/// Registers every row of `table` on `app`, in the table's order, writing into `p`. The
/// options take the app's option_defaults() (group, captured default) like any other.
template <class P, std::size_t N>
void add_member_options(CLI::App& app, P& p, const MemberOption<P> (&table)[N]) {
  for (const MemberOption<P>& row : table)
    std::visit([&](auto member) { app.add_option(row.flag, p.*member, row.help); }, row.member);
}

}  // namespace fq::client
