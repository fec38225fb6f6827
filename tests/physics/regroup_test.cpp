#include "physics/regroup.h"

#include <random>

#include <gtest/gtest.h>

#include "physics/clusters.h"
#include "physics/dynamics.h"
#include "tests/physics/latched_block.h"

namespace dw::physics {
namespace {

// A block and the changes made to it, regrouped both ways: by Regrouper and by form_clusters.
struct Block {
  Dynamics dynamics{PhysicsSettings{}, ModuleShape::Box, -0.5f};  // holds the box shape clusters are made of
  btCollisionShape& shape = dynamics.module_shape();
  sim::Bodies b;
  std::vector<uint8_t> present;
  BondIndex index;
  BondChanges changes;
  Regrouper regroup;

  Block(int side, bool anchored) : b(test::latched_block(side, anchored, shape)), present(b.poses.size(), 1) {
    index.rebuild(b.bonds);
  }
  bool touching(sim::ModuleId m, sim::ModuleId o) const {
    const auto &p = b.poses[m].position, &q = b.poses[o].position;
    return std::abs(p[0] - q[0]) + std::abs(p[1] - q[1]) + std::abs(p[2] - q[2]) < 1.01f;
  }
  void erase(const sim::Bond& x) {
    if (!b.bonds.erase(x)) return;
    index.apply(b.bonds, std::vector{x}, {});
    changes.removed.push_back(x);
  }
  void add(const sim::Bond& x) {
    if (!b.bonds.insert(x)) return;
    index.apply(b.bonds, {}, std::vector{x});
    changes.added.push_back(x);
  }
  std::vector<sim::Bond> all_bonds() const {
    std::vector<sim::Bond> all;
    b.bonds.for_each([&](const sim::Bond& x) { all.push_back(x); });
    return all;
  }
  // m sets off on a lattice move: its bonds go.
  void set_off(sim::ModuleId m) {
    std::vector<sim::Bond> gone;
    for (const sim::Bond& x : all_bonds())
      if (x.a == m || x.b == m) gone.push_back(x);
    for (const sim::Bond& x : gone) erase(x);
    sim::Mover mover{.module = m};
    b.movers.insert(std::lower_bound(b.movers.begin(), b.movers.end(), mover,
                                     [](const sim::Mover& x, const sim::Mover& y) { return x.module < y.module; }),
                    mover);
    changes.stopped.push_back(m);
  }
  // m arrives where it was: it latches to the still modules it touches (and the ground).
  void arrive(sim::ModuleId m, bool ground) {
    std::erase_if(b.movers, [&](const sim::Mover& x) { return x.module == m; });
    changes.started.push_back(m);
    for (sim::ModuleId o = 0; o < b.poses.size(); ++o)
      if (o != m && !b.moving(o) && touching(m, o)) add({std::min(m, o), std::max(m, o)});
    if (ground && b.poses[m].position[2] == 0) add({m, sim::kGround});
  }
  // Regroups both ways; the results must be equal to the bit.
  void check(const char* what) {
    sim::Bodies whole = b;
    form_clusters(whole, present, shape);
    changes.normalize();
    regroup(b, present, changes, index, shape);
    changes.clear();
    ASSERT_EQ(b.clusters.size(), whole.clusters.size()) << what;
    ASSERT_EQ(b.clusters, whole.clusters) << what;
    ASSERT_EQ(b.members, whole.members) << what;
    ASSERT_EQ(b.cluster_of, whole.cluster_of) << what;
    ASSERT_TRUE(b == whole) << what;
  }
};

sim::ModuleId at(int side, int x, int y, int z) { return sim::ModuleId(x + side * (y + side * z)); }

TEST(Regrouper, AModuleLeavingASurfaceKeepsTheBlockAndSearchesLittle) {
  Block k(12, true);
  k.set_off(at(12, 5, 5, 11));
  k.check("a top module sets off");
  EXPECT_EQ(k.b.clusters.size(), 1u);
  EXPECT_EQ(k.b.clusters[0].count, 12u * 12 * 12 - 1);
  EXPECT_TRUE(k.b.clusters[0].anchored);
  // Its five neighbours' searches meet around the hole in a few steps each.
  EXPECT_LT(k.regroup.searched(), 60u);
  k.arrive(at(12, 5, 5, 11), true);
  k.check("it comes back");
  EXPECT_EQ(k.b.clusters.size(), 1u);
}

TEST(Regrouper, ACutSplitsABarIntoPiecesAndTheGroundLetsGo) {
  Block k(6, true);
  // Cut the top two layers off the rest: every bond between z = 3 and z = 4 goes.
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 6; ++x) k.erase({at(6, x, y, 3), at(6, x, y, 4)});
  k.check("the top cut off");
  ASSERT_EQ(k.b.clusters.size(), 2u);
  EXPECT_TRUE(k.b.clusters[0].anchored);
  EXPECT_FALSE(k.b.clusters[1].anchored);  // the top floats: its own principal frame
  EXPECT_EQ(k.b.clusters[1].count, 72u);
  // The ground lets go of the rest too.
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 6; ++x) k.erase({at(6, x, y, 0), sim::kGround});
  k.check("the ground lets go");
  EXPECT_FALSE(k.b.clusters[0].anchored);
  // A corner module leaves, and one bond joins the two again.
  k.set_off(at(6, 0, 0, 0));
  k.add({at(6, 2, 2, 3), at(6, 2, 2, 4)});
  k.check("joined again");
  ASSERT_EQ(k.b.clusters.size(), 1u);
  EXPECT_EQ(k.b.clusters[0].count, 6u * 6 * 6 - 1);
}

// Random changes, many at once, both ways; floating and anchored blocks.
TEST(Regrouper, RandomChangesGiveFormClustersResult) {
  for (const bool anchored : {true, false}) {
    Block k(7, anchored);
    std::mt19937 random(anchored ? 7 : 11);
    const auto n = static_cast<sim::ModuleId>(k.b.poses.size());
    for (int round = 0; round < 60; ++round) {
      const int changes = 1 + int(random() % 12);
      std::vector<sim::ModuleId> arriving;
      for (int i = 0; i < changes; ++i) {
        const sim::ModuleId m = random() % n;
        switch (random() % 5) {
          case 0:
            if (!k.b.moving(m)) k.set_off(m);
            break;
          case 1:
            if (k.b.moving(m)) arriving.push_back(m);
            break;
          case 2: {  // a bond released
            const std::vector<sim::Bond> all = k.all_bonds();
            if (all.empty()) break;
            k.erase(all[random() % all.size()]);
            break;
          }
          case 3: {  // a bond made to a touching still module
            const sim::ModuleId o = random() % n;
            if (o != m && !k.b.moving(m) && !k.b.moving(o) && k.touching(m, o)) k.add({std::min(m, o), std::max(m, o)});
            break;
          }
          case 4:
            if (anchored && !k.b.moving(m) && k.b.poses[m].position[2] == 0) k.add({m, sim::kGround});
            break;
        }
      }
      // Requests first, then the arrivals, as a step does: two regroupings.
      k.check("after the requests");
      std::sort(arriving.begin(), arriving.end());
      arriving.erase(std::unique(arriving.begin(), arriving.end()), arriving.end());
      for (sim::ModuleId m : arriving) k.arrive(m, anchored);
      k.check("after the arrivals");
    }
    EXPECT_GT(k.b.clusters.size(), 1u);  // the block was broken up on the way
  }
}

// Requests on one bond within one step: released, made again and released is released; made and
// released is nothing; released and made again is nothing.
TEST(BondChanges, ABondChangedSeveralTimesEndsAsItsLastChange) {
  const sim::Bond x{1, 2}, y{3, 4}, z{5, 6};
  BondChanges c;
  c.removed = {x, y, x};
  c.added = {x, y, z};
  c.stopped = {7, 7};
  c.normalize();
  EXPECT_EQ(c.removed, (std::vector<sim::Bond>{x}));
  EXPECT_EQ(c.added, (std::vector<sim::Bond>{z}));
  EXPECT_EQ(c.stopped, (std::vector<sim::ModuleId>{7}));
}

}  // namespace
}  // namespace dw::physics
