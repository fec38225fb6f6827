#include "sim/bond_set.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <vector>

namespace dw::sim {
namespace {

std::vector<Bond> all_of(const BondSet& bonds) {
  std::vector<Bond> all;
  bonds.for_each([&](const Bond& x) { all.push_back(x); });
  return all;
}

// Latched by default, a set holds every pair of lattice neighbours, as the lattice's graph
// has them; not latched, none.
TEST(BondSet, LatchedByDefaultItHoldsTheLatticesPairs) {
  for (const LatticeSpec& spec :
       {LatticeSpec{LatticeKind::Cubic, {10, 10, 10}}, LatticeSpec{LatticeKind::Fcc, {5, 4, 6}},
        LatticeSpec{LatticeKind::Hex2d, {7, 6, 1}}}) {
    const auto n = static_cast<uint32_t>(spec.module_count());
    const BondSet latched(spec, true, n);
    std::vector<Bond> pairs;
    for_lattice_pairs(spec, {}, [&](ModuleId a, ModuleId b) { pairs.push_back({a, b}); });
    EXPECT_EQ(all_of(latched), pairs);
    EXPECT_EQ(latched.size(), pairs.size());
    if (spec.kind == LatticeKind::Cubic) {
      EXPECT_EQ(pairs.size(), 2700u);
    }
    EXPECT_TRUE(BondSet(spec, false, n).empty());
  }
}

// Bonds of every kind (to lattice neighbours, listed, to the ground) go in and out, and the set
// says what a sorted list of them would: a model list kept beside it.
TEST(BondSet, InsertsAndErasesAsASortedListWould) {
  const LatticeSpec spec{LatticeKind::Fcc, {6, 5, 4}};
  const auto n = static_cast<ModuleId>(spec.module_count());
  for (const bool latched : {false, true}) {
    BondSet bonds(spec, latched, n);
    std::set<Bond> model;
    if (latched) bonds.for_each([&](const Bond& x) { model.insert(x); });
    std::mt19937 random(11);
    for (int i = 0; i < 20000; ++i) {
      const ModuleId a = random() % n;
      ModuleId b = random() % 3 == 0 ? kGround : static_cast<ModuleId>(random() % n);
      if (random() % 2 == 0) for_links_above(spec, a, [&](int slot, ModuleId o) { b = slot == 1 ? o : b; });
      if (a == b) continue;
      const Bond x{std::min(a, b), std::max(a, b)};
      if (random() % 2) {
        EXPECT_EQ(bonds.insert(x), model.insert(x).second);
      } else {
        EXPECT_EQ(bonds.erase(x), model.erase(x) == 1);
      }
      EXPECT_EQ(bonds.contains(x), model.count(x) == 1);
    }
    EXPECT_EQ(all_of(bonds), std::vector<Bond>(model.begin(), model.end()));
    EXPECT_EQ(bonds.size(), model.size());
    EXPECT_FALSE(bonds.listed().empty());
    // Each module's bonds to smaller lattice neighbours, from their bytes.
    for (ModuleId m = 0; m < n; ++m) {
      std::vector<ModuleId> below;
      bonds.linked_below(m, [&](ModuleId o) { below.push_back(o); });
      std::sort(below.begin(), below.end());
      std::vector<ModuleId> expected;
      for (const Bond& x : model)
        if (x.b == m && bonds.bit(x) != 0) expected.push_back(x.a);
      EXPECT_EQ(below, expected) << "module " << m;
    }
    // The same bonds put in one by one into a set that latches nothing: equal.
    BondSet again(spec, !latched, n);
    again.erase(all_of(again));
    again.insert(std::vector<Bond>(model.begin(), model.end()));
    EXPECT_EQ(again, bonds);
  }
}

// A still latched lattice of a million keeps a byte a module only where its bonds differ from
// the default: none but the bottom layer's, latched to the ground, where a list took 24 MB.
TEST(BondSet, ALatchedMillionKeepsOnlyItsGroundedLayer) {
  const LatticeSpec spec{LatticeKind::Cubic, {100, 100, 100}};
  BondSet bonds(spec, true, 1000000);
  for (ModuleId m = 0; m < 100 * 100; ++m) bonds.set_links(m, bonds.links(m) | kGroundBit);
  EXPECT_LT(bonds.bytes(), 64u << 10);
  EXPECT_EQ(bonds.size(), 3 * 100u * 100 * 99 + 100 * 100);
  EXPECT_TRUE(bonds.contains({5, kGround}));
  EXPECT_FALSE(bonds.contains({20000, kGround}));
  EXPECT_TRUE(bonds.contains({20000, 30000}));
}

}  // namespace
}  // namespace dw::sim
