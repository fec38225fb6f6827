// Three-valued (Kleene) logic (docs/design.md §4). A truth value is two bits: "may be true" and "may be
// false", so and/or/not are branch-free bit operations and "not yet known" is simply Unknown.
#pragma once

#include <cstdint>

namespace dw::watch {

using Truth = uint8_t;
constexpr Truth kTrue = 1;
constexpr Truth kFalse = 2;
constexpr Truth kUnknown = 3;

constexpr Truth truth_of(bool b) { return b ? kTrue : kFalse; }
// F and x = F; T and x = x.
constexpr Truth kleene_and(Truth a, Truth b) { return static_cast<Truth>((a & b & 1) | ((a | b) & 2)); }
// T or x = T; F or x = x.
constexpr Truth kleene_or(Truth a, Truth b) { return static_cast<Truth>(((a | b) & 1) | (a & b & 2)); }
// not U = U.
constexpr Truth kleene_not(Truth a) { return static_cast<Truth>(((a & 1) << 1) | ((a & 2) >> 1)); }

}  // namespace dw::watch
