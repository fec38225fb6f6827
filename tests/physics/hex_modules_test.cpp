// The paper's own modules (physics/pivot.h, physics/shapes.h): 2-D catoms standing in the x-z
// plane (hex2d_vertical, discs rolling about each other against gravity) and Hexanodes (hexagonal
// prisms on the ground turning about a shared edge): their shapes, their arcs, the rule that
// keeps a catom of a vertical plane from arriving unsupported, and the world carrying them out.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "physics/bullet_world.h"
#include "physics/contact_graph.h"
#include "physics/dynamics.h"
#include "physics/pivot.h"
#include "sim/session.h"
#include "sim/state.h"
#include "tests/physics/scripted_program.h"

namespace dw::physics {
namespace {

constexpr float kRow = 0.8660254f;  // sqrt(3)/2

float distance(const sim::Vec3& a, const sim::Vec3& b) { return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]); }

sim::Pose at(sim::Vec3 p) { return sim::Pose{.position = p}; }

// The shapes touch where the lattice's cells do: two discs one apart along x or up a row are at
// distance 0 (a disc's axis is y: two side by side along y overlap, two a size apart along z
// touch); two Hexanodes one apart face to face touch, and their corners reach 1/sqrt(3) from
// the centre (a hexagonal prism's, not a cylinder's 0.5).
TEST(HexModules, ShapesTouchAsTheirLatticeCellsDo) {
  const ContactGraph discs(ModuleShape::Disc, 0.01f);
  EXPECT_NEAR(discs.distance(at({0, 0, 0}), at({1, 0, 0})), 0, 2e-3f);
  EXPECT_NEAR(discs.distance(at({0, 0, 0}), at({0.5f, 0, kRow})), 0, 2e-3f);
  // Round in x-z: clear of each other 1.06 apart along a diagonal (where boxes would overlap), and
  // overlapping 0.99 apart.
  EXPECT_GT(discs.distance(at({0, 0, 0}), at({0.75f, 0, 0.75f})), 0.01f);
  EXPECT_LT(discs.distance(at({0, 0, 0}), at({0.7f, 0, 0.7f})), -0.005f);
  EXPECT_LT(discs.distance(at({0, 0, 0}), at({0, 0.9f, 0})), -0.05f);  // one across, along y
  const ContactGraph hexes(ModuleShape::HexPrism, 0.01f);
  for (int k = 0; k < 6; ++k) {
    const float a = float(k) * float(M_PI) / 3;
    EXPECT_NEAR(hexes.distance(at({0, 0, 0}), at({std::cos(a), std::sin(a), 0})), 0, 2e-3f) << k;
  }
  // Along a corner (30 degrees) two prisms 1.1 apart still overlap: corners reach 0.577 each.
  const float c = float(M_PI) / 6;
  EXPECT_LT(hexes.distance(at({0, 0, 0}), at({1.1f * std::cos(c), 1.1f * std::sin(c), 0})), -0.01f);
  // A cylinder of that size would be clear of it there.
  const ContactGraph cylinders(ModuleShape::Cylinder, 0.01f);
  EXPECT_GT(cylinders.distance(at({0, 0, 0}), at({1.1f * std::cos(c), 1.1f * std::sin(c), 0})), 0.05f);
  EXPECT_EQ(default_shape(sim::LatticeKind::Hex2dVertical), ModuleShape::Disc);
}

// A Hexanode turns by 120 degrees about the corner it shares with the neighbour and the cell it
// goes to, and lands exactly there; a disc rolls over the neighbour (60 degrees about its
// centre, the body turning twice as far) as the upright cylinders do, about y.
TEST(HexModules, HexanodesTurnAboutTheSharedCornerDiscsRollAboutY) {
  const sim::Vec3 from{1, 0, 0}, about{0, 0, 0}, offset{-0.5f, kRow, 0};
  const auto planned = pivot_arcs(ModuleShape::HexPrism, from, about, offset);
  ASSERT_TRUE(std::holds_alternative<std::vector<PivotArc>>(planned)) << std::get<std::string>(planned);
  const auto& arcs = std::get<std::vector<PivotArc>>(planned);
  ASSERT_EQ(arcs.size(), 1u);
  EXPECT_LT(distance(arcs[0].pivot, {0.5f, kRow / 3, 0}), 1e-5f);  // the three cells' shared corner
  EXPECT_NEAR(arcs[0].angle, 2 * M_PI / 3, 1e-5);
  EXPECT_EQ(arcs[0].spin, 1.0f);
  sim::Mover mover{.from = at(from), .pivot = arcs[0].pivot, .axis = arcs[0].axis, .angle = arcs[0].angle};
  EXPECT_LT(distance(turn(mover, 1).position, {0.5f, kRow, 0}), 1e-5f);
  // Halfway, the far corner is where the cell beside both lies: that cell must be free.
  EXPECT_LT(distance(turn(mover, 0.5f).position, arcs[0].pivot), 0.578f);

  const auto rolled = pivot_arcs(ModuleShape::Disc, {1, 0, 0}, {0, 0, 0}, {-0.5f, 0, kRow});
  ASSERT_TRUE(std::holds_alternative<std::vector<PivotArc>>(rolled));
  const auto& roll = std::get<std::vector<PivotArc>>(rolled);
  ASSERT_EQ(roll.size(), 1u);  // no groove: that is a sphere's
  EXPECT_LT(distance(roll[0].axis, {0, -1, 0}), 1e-5f);
  EXPECT_NEAR(roll[0].angle, M_PI / 3, 1e-5);
  EXPECT_EQ(roll[0].spin, 2.0f);
  // Across the neighbour, or two cells on: no pivot goes there.
  EXPECT_TRUE(std::holds_alternative<std::string>(pivot_arcs(ModuleShape::HexPrism, from, about, {-2, 0, 0})));
  EXPECT_TRUE(std::holds_alternative<std::string>(pivot_arcs(ModuleShape::HexPrism, from, about, {1, 0, 0})));
}

// In a vertical plane a catom arrives on the ground, on a module lower than it, or between two;
// hanging from one neighbour's side, or from nothing, it is refused, naming the neighbour.
TEST(HexModules, ACatomOfAVerticalPlaneArrivesSupported) {
  const float ground = -0.5f;
  EXPECT_FALSE(unsupported_in_vertical_plane({3, 0, 0}, ground, {}));  // on the ground
  const Holder below{7, {2.5f, 0, 0}}, beside{8, {2, 0, kRow}}, other_side{9, {4, 0, kRow}},
      above{10, {3.5f, 0, 2 * kRow}};
  EXPECT_FALSE(unsupported_in_vertical_plane({3, 0, kRow}, ground, std::vector<Holder>{below}));
  EXPECT_FALSE(unsupported_in_vertical_plane({3, 0, kRow}, ground, std::vector<Holder>{beside, other_side}));
  EXPECT_FALSE(unsupported_in_vertical_plane({3, 0, kRow}, ground, std::vector<Holder>{beside, above}));
  const auto hangs = unsupported_in_vertical_plane({3, 0, kRow}, ground, std::vector<Holder>{beside});
  ASSERT_TRUE(hangs);
  EXPECT_NE(hangs->find("it would hang from module 8 alone"), std::string::npos) << *hangs;
  EXPECT_TRUE(unsupported_in_vertical_plane({3, 0, kRow}, ground, std::vector<Holder>{above}));
  EXPECT_TRUE(unsupported_in_vertical_plane({3, 0, kRow}, ground, {}));
}

// What a pivot of module `mover` about `about` by `offset` at step 1 does to a hex2d_vertical
// lattice: the program error it ends in ("" when none), and the mover's place after 15 steps.
struct Outcome {
  std::string error;
  sim::Vec3 place{};
};
Outcome pivot_in(const sim::Lattice& lattice, sim::ModuleId mover, sim::ModuleId about, sim::Vec3 offset) {
  const auto model = test::scripted_model(lattice, [=](sim::ModuleContext& m) {
    if (m.id() == mover && m.step() == 1) m.pivot(about, offset);
  });
  PhysicsSettings s;
  s.move_steps = 10;
  BulletWorld world(s, model->lattice);
  sim::Session run(*model, world, {.threads = 1});
  try {
    run.run_until(15);
  } catch (const sim::ProgramError& e) {
    return {e.what(), {}};
  }
  return {"", run.state().bodies.poses[mover].position};
}

// Row 0 holds modules 0..3 (x = 0..3), row 1 modules 5..7 (x = 0.5..2.5, a row up). Rolling
// module 3 over module 2 into row 1 is a taken cell (module 7's); module 7 rolls over module 3's
// top into (3.5, row 1), resting on module 3: allowed, and it lands there; module 7 rolls over
// module 6 up into row 2, resting on module 6: allowed. On a column of one (module 3 of the
// second lattice, at x = 0.5 over modules 0 and 1), module 1 rolling up beside it would hang from
// its side: refused, naming it.
TEST(HexModules, VerticalCatomsRollOnlyWhereTheyArriveSupported) {
  sim::Lattice lattice = sim::make_lattice({sim::LatticeKind::Hex2dVertical, {5, 3, 1}});
  sim::leave_empty(lattice, {4, 0, 0}, {4, 0, 0});  // row 0: columns 0..3
  sim::leave_empty(lattice, {3, 1, 0}, {4, 1, 0});  // row 1: columns 0..2
  sim::leave_empty(lattice, {0, 2, 0}, {4, 2, 0});  // row 2: empty
  EXPECT_EQ(lattice.position(7), (std::array<float, 3>{2.5f, 0, kRow}));
  Outcome o = pivot_in(lattice, 3, 2, {-0.5f, 0, kRow});
  EXPECT_NE(o.error.find("the cell is taken by module 7"), std::string::npos) << o.error;
  o = pivot_in(lattice, 7, 3, {1, 0, 0});
  EXPECT_EQ(o.error, "");
  EXPECT_LT(distance(o.place, {3.5f, 0, kRow}), 1e-4f);
  o = pivot_in(lattice, 7, 6, {-0.5f, 0, kRow});
  EXPECT_EQ(o.error, "");
  EXPECT_LT(distance(o.place, {2, 0, 2 * kRow}), 1e-4f);

  sim::Lattice column = sim::make_lattice({sim::LatticeKind::Hex2dVertical, {3, 3, 1}});
  sim::leave_empty(column, {2, 0, 0}, {2, 0, 0});  // row 0: modules 0 and 1
  sim::leave_empty(column, {1, 1, 0}, {2, 1, 0});  // row 1: module 3 only
  sim::leave_empty(column, {0, 2, 0}, {2, 2, 0});
  o = pivot_in(column, 1, 3, {0.5f, 0, kRow});  // into (1.5, row 1): nothing below, module 3 beside
  EXPECT_NE(o.error.find("a pivot of module 1 at step 1 about module 3 to the cell at (0.5, 0, 0.866025) from it: "
                         "it would hang from module 3 alone"),
            std::string::npos)
      << o.error;
  // Rolling up beside one catom, the cell under the far side must be free (the disc bulges over
  // it as it rolls), so the cell it arrives in rests on nothing: it is held only when another
  // catom touches that cell, here module 6 (x = 2.5, row 1, standing on module 3 at x = 3).
  sim::Lattice held = sim::make_lattice({sim::LatticeKind::Hex2dVertical, {4, 3, 1}});
  sim::leave_empty(held, {2, 0, 0}, {2, 0, 0});  // row 0: modules 0, 1 and 3
  sim::leave_empty(held, {1, 1, 0}, {1, 1, 0});  // row 1: modules 4 (x = 0.5) and 6 (x = 2.5)
  sim::leave_empty(held, {3, 1, 0}, {3, 1, 0});
  sim::leave_empty(held, {0, 2, 0}, {3, 2, 0});
  o = pivot_in(held, 1, 4, {0.5f, 0, kRow});
  EXPECT_EQ(o.error, "");
  EXPECT_LT(distance(o.place, {1.5f, 0, kRow}), 1e-4f);
}

// The same rolls on 1 and 2 threads give the same hash at every step, and the catoms latched to
// the ground stand exactly still while two roll over them.
TEST(HexModules, VerticalCatomsAreDeterministicAndTheirStackStands) {
  sim::Lattice lattice = sim::make_lattice({sim::LatticeKind::Hex2dVertical, {5, 3, 1}});
  sim::leave_empty(lattice, {4, 0, 0}, {4, 0, 0});
  sim::leave_empty(lattice, {3, 1, 0}, {4, 1, 0});
  sim::leave_empty(lattice, {0, 2, 0}, {4, 2, 0});
  const auto model = test::scripted_model(lattice, [](sim::ModuleContext& m) {
    if (m.id() == 7 && m.step() == 1) m.pivot(3, {1, 0, 0});   // onto module 3
    if (m.id() == 6 && m.step() == 13) m.pivot(2, {1, 0, 0});  // into the cell module 7 left
  });
  PhysicsSettings s;
  s.move_steps = 10;
  std::vector<uint64_t> hashes[2];
  for (unsigned threads : {1u, 2u}) {
    BulletWorld world(s, model->lattice);
    sim::Session run(*model, world, {.threads = threads});
    run.run_until(60, [&](const sim::State& st, const sim::StepOutput&) {
      hashes[threads - 1].push_back(sim::hash_state(st).whole());
    });
    const sim::State& st = run.state();
    EXPECT_LT(distance(st.bodies.poses[7].position, {3.5f, 0, kRow}), 1e-4f);
    EXPECT_LT(distance(st.bodies.poses[6].position, {2.5f, 0, kRow}), 1e-4f);
    for (sim::ModuleId m : {0u, 1u, 2u, 3u, 5u}) {
      EXPECT_EQ(st.bodies.poses[m].position, lattice.position(m)) << m;
      EXPECT_EQ(st.bodies.poses[m].orientation, (std::array<float, 4>{0, 0, 0, 1})) << m;
    }
  }
  EXPECT_EQ(hashes[0], hashes[1]);
  EXPECT_EQ(hashes[0].size(), 60u);
}

// A Hexanode (a 3x3 hex2d patch on the ground, its centre module 4 left out) turns about the
// edge it shares with a neighbour into the next cell round it: module 3 (x = 0.5, row 1) about
// module 1 (x = 1, row 0) into the centre, 120 degrees about z, landing there turned by as much.
// With module 6, 7 or 8 (row 2) in place, its far edge would sweep through it: refused.
TEST(HexModules, AHexanodeTurnsAboutASharedEdgeIntoTheNextCell) {
  PhysicsSettings s;
  s.shape = ModuleShape::HexPrism;
  s.move_steps = 10;
  const auto run_pivot = [&](const sim::Lattice& lattice) -> std::pair<std::string, sim::Pose> {
    const auto model = test::scripted_model(lattice, [](sim::ModuleContext& m) {
      if (m.id() == 3 && m.step() == 1) m.pivot(1, {1, 0, 0});
    });
    BulletWorld world(s, model->lattice);
    EXPECT_EQ(world.shape(), ModuleShape::HexPrism);
    sim::Session run(*model, world, {.threads = 1});
    try {
      run.run_until(15);
    } catch (const sim::ProgramError& e) {
      return {e.what(), {}};
    }
    return {"", run.state().bodies.poses[3]};
  };
  sim::Lattice patch = sim::make_lattice({sim::LatticeKind::Hex2d, {3, 3, 1}});
  sim::leave_empty(patch, {1, 1, 0}, {1, 1, 0});
  // Its far edge sweeps a third of a circle twice its corners' reach about the turning edge, over
  // the three cells beyond: row 2's modules 6, 7 and 8 (x = 0, 1, 2).
  std::string blocked = run_pivot(patch).first;
  EXPECT_NE(blocked.find("its sweep passes through module 6"), std::string::npos) << blocked;
  sim::leave_empty(patch, {0, 2, 0}, {0, 2, 0});
  blocked = run_pivot(patch).first;
  EXPECT_NE(blocked.find("its sweep passes through module 7"), std::string::npos) << blocked;
  sim::leave_empty(patch, {1, 2, 0}, {1, 2, 0});
  blocked = run_pivot(patch).first;
  EXPECT_NE(blocked.find("its sweep passes through module 8"), std::string::npos) << blocked;
  sim::leave_empty(patch, {2, 2, 0}, {2, 2, 0});
  const auto [error, pose] = run_pivot(patch);
  EXPECT_EQ(error, "");
  EXPECT_LT(distance(pose.position, {1.5f, kRow, 0}), 1e-4f);
  const float half_turn_sin = std::sin(float(M_PI) / 3), half_turn_cos = std::cos(float(M_PI) / 3);
  EXPECT_NEAR(std::abs(pose.orientation[2]), half_turn_sin, 1e-4f);
  EXPECT_NEAR(std::abs(pose.orientation[3]), half_turn_cos, 1e-4f);
}

}  // namespace
}  // namespace dw::physics
