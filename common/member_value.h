// A member of a struct, reached by a path of member pointers (&Params::filtering,
// &FilterParams::sigma_s), read and written as a double: the accessors of the rows of fq's
// tables (core/param_table.cpp, daemon/config/stream_setting_table.cpp), so that a row names
// its member once and the compiler checks the path. A double holds every float, uint32, int,
// bool and enum (as int) exactly.
#pragma once

#include <type_traits>

namespace fq {

/// The class a member pointer belongs to.
template <auto Member>
struct MemberOwner;
template <class C, class T, T C::*Member>
struct MemberOwner<Member> {
  using type = C;
};

/// The member at `First, Rest...` of `root`, as a double (an enum as its int).
template <auto First, auto... Rest>
double get_member(const typename MemberOwner<First>::type& root) {
  const auto& v = ((root.*First).*....*Rest);
  using T = std::remove_cvref_t<decltype(v)>;
  if constexpr (std::is_enum_v<T>)
    return static_cast<double>(static_cast<int>(v));
  else
    return static_cast<double>(v);
}

/// Sets the member at `First, Rest...` of `root` to `x` (a bool: x != 0; an enum: its int).
template <auto First, auto... Rest>
void set_member(typename MemberOwner<First>::type& root, double x) {
  auto& v = ((root.*First).*....*Rest);
  using T = std::remove_cvref_t<decltype(v)>;
  if constexpr (std::is_enum_v<T>)
    v = static_cast<T>(static_cast<int>(x));
  else if constexpr (std::is_same_v<T, bool>)
    v = x != 0.0;
  else
    v = static_cast<T>(x);
}

}  // namespace fq
