// The bonds of a physical world (sim/bodies.h), as a set of Bond {a < b}. A latched 100^3
// lattice has three million, 24 MB as a list, held by every rank and copied into every state. Most
// join lattice neighbours, so a bond to a lattice neighbour is a bit: each module keeps a byte,
// a bit for each of its links to larger ids (sim/lattice.h: for_links_above) and one for the
// ground, paged with "latched to every lattice neighbour" as the default when the world latches
// its modules at the start. A still latched lattice keeps no page but those of its bottom layer;
// the bonds between modules that are not lattice neighbours (a module that made a lattice move
// latches to its new neighbours) are listed.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "sim/lattice.h"
#include "sim/neighbor_graph.h"
#include "sim/paged_array.h"

namespace dw::sim {

// The ground, as the other end of a bond.
inline constexpr ModuleId kGround = std::numeric_limits<ModuleId>::max();

// A latch between two touching modules (a < b), or between a module and the ground (b = kGround).
struct Bond {
  ModuleId a = 0, b = 0;
  auto operator<=>(const Bond&) const = default;
};
static_assert(sizeof(Bond) == 2 * sizeof(ModuleId));

// A module's byte: bit `slot` for its link in that slot, and the ground's.
inline constexpr uint8_t kGroundBit = 0x80;
static_assert(kMaxLinkSlots < 7);

// Every link a lattice cell has, when `latched`; none otherwise.
struct LinkDefault {
  LatticeSpec lattice{};
  uint32_t latched = 0;  // not a bool: serialized bit for bit, it leaves no padding
  uint8_t operator()(size_t m) const {
    uint8_t bits = 0;
    if (latched) for_links_above(lattice, static_cast<ModuleId>(m), [&](int slot, ModuleId) { bits |= 1u << slot; });
    return bits;
  }
  bool operator==(const LinkDefault&) const = default;
};
static_assert(sizeof(LinkDefault) == sizeof(LatticeSpec) + sizeof(uint32_t));

class BondSet {
 public:
  BondSet() = default;
  // `modules` modules on `lattice` (whose ids are its cells'), latched to every lattice neighbour
  // or to none.
  BondSet(const LatticeSpec& lattice, bool latched, size_t modules) : links_(LinkDefault{lattice, latched ? 1u : 0u}) {
    links_.resize(modules);
  }

  const LatticeSpec& lattice() const { return links_.defaults().lattice; }
  // The bit of `x` in its lower end's byte, or 0 when it is listed.
  uint8_t bit(const Bond& x) const {
    if (x.b == kGround) return kGroundBit;
    uint8_t found = 0;
    for_links_above(lattice(), x.a, [&](int slot, ModuleId o) {
      if (o == x.b) found = static_cast<uint8_t>(1u << slot);
    });
    return found;
  }
  // A module's byte, and setting it (over ranks, the owners' bytes are swapped whole).
  uint8_t links(ModuleId m) const { return links_[m]; }
  void set_links(ModuleId m, uint8_t bits) { links_.set(m, bits); }
  uint8_t default_links(ModuleId m) const { return links_.defaults()(m); }

  bool contains(const Bond& x) const {
    if (const uint8_t b = bit(x)) return (links_[x.a] & b) != 0;
    return std::binary_search(listed_.begin(), listed_.end(), x);
  }
  // Whether it was not there.
  bool insert(const Bond& x) {
    if (const uint8_t b = bit(x)) {
      const uint8_t had = links_[x.a];
      links_.set(x.a, had | b);
      return (had & b) == 0;
    }
    const auto at = std::lower_bound(listed_.begin(), listed_.end(), x);
    if (at != listed_.end() && *at == x) return false;
    listed_.insert(at, x);
    return true;
  }
  // Whether it was there.
  bool erase(const Bond& x) {
    if (const uint8_t b = bit(x)) {
      const uint8_t had = links_[x.a];
      links_.set(x.a, had & ~b);
      return (had & b) != 0;
    }
    const auto at = std::lower_bound(listed_.begin(), listed_.end(), x);
    if (at == listed_.end() || !(*at == x)) return false;
    listed_.erase(at);
    return true;
  }
  // Adds many, sorted (in one pass over the list, not one each).
  void insert(std::span<const Bond> sorted);
  // Removes many, sorted.
  void erase(std::span<const Bond> sorted);

  // Calls f(b) for every bond {m, b}, b ascending (the ground last).
  template <typename F>
  void above(ModuleId m, F&& f) const {
    const uint8_t bits = links_[m];
    ModuleId linked[kMaxLinkSlots];
    int n = 0;
    if (bits & ~kGroundBit)
      for_links_above(lattice(), m, [&](int slot, ModuleId o) {
        if (bits & (1u << slot)) linked[n++] = o;
      });
    auto listed = std::lower_bound(listed_.begin(), listed_.end(), Bond{m, 0});
    for (int i = 0; i < n; ++i) {
      for (; listed != listed_.end() && listed->a == m && listed->b < linked[i]; ++listed) f(listed->b);
      f(linked[i]);
    }
    for (; listed != listed_.end() && listed->a == m; ++listed) f(listed->b);
    if (bits & kGroundBit) f(kGround);
  }
  // Calls f(o) for every lattice neighbour o < m bonded to m (those listed are not searched: see
  // physics/regroup.h, BondIndex).
  template <typename F>
  void linked_below(ModuleId m, F&& f) const {
    for_links_below(lattice(), m, [&](int slot, ModuleId o) {
      if (links_[o] & (1u << slot)) f(o);
    });
  }
  // Calls f(bond) for every bond, ascending.
  template <typename F>
  void for_each(F&& f) const {
    for (ModuleId m = 0; m < links_.size(); ++m) above(m, [&](ModuleId b) { f(Bond{m, b}); });
  }
  // The bonds that are not between lattice neighbours (nor to the ground), sorted.
  std::span<const Bond> listed() const { return listed_; }
  // How many there are (a pass over every module's byte).
  size_t size() const {
    size_t n = listed_.size();
    for (ModuleId m = 0; m < links_.size(); ++m) n += static_cast<size_t>(std::popcount(links_[m]));
    return n;
  }
  bool empty() const { return size() == 0; }
  size_t bytes() const { return links_.bytes() + listed_.capacity() * sizeof(Bond); }

  // Its parts, for serializing (sim/body_slices.cpp): the bytes, then the list.
  template <typename F>
  void each_part(F&& f) const {
    f(links_);
    f(listed_);
  }
  template <typename F>
  void each_part(F&& f) {
    f(links_);
    f(listed_);
  }
  bool operator==(const BondSet&) const = default;

 private:
  PagedArray<uint8_t, LinkDefault> links_;
  std::vector<Bond> listed_;  // sorted
};

}  // namespace dw::sim
