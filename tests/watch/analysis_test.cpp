#include "watch/analysis.h"

#include <gtest/gtest.h>

#include "watch/parser.h"
#include "watch/program.h"

namespace dw::watch {
namespace {

Analysis analyze_text(const std::string& text, Ast* keep = nullptr) {
  auto r = parse(SourceText("t", text));
  EXPECT_TRUE(r.ok()) << text;
  Analysis a = analyze(r.ast);
  if (keep) *keep = r.ast;
  return a;
}

TEST(Analysis, TemporalSpanIsTheWidestGapBetweenUsesOfAVariable) {
  // Paper §IV-A: token used at -1 and 0: span 1.
  Analysis a = analyze_text("modules(a x b); (x.token = 1) and ((a.last.token = 1) or (b.last.token = 0))");
  ASSERT_EQ(a.variables.size(), 1u);
  EXPECT_EQ(a.variables[0].name, "token");
  EXPECT_EQ(a.variables[0].offsets, (std::vector<int>{-1, 0}));
  EXPECT_EQ(a.variables[0].span(), 1);
  EXPECT_EQ(a.extent_plus, 0);
  EXPECT_EQ(a.min_offset, -1);
}

TEST(Analysis, ExtentPlusIsTheLargestForwardOffset) {
  Analysis a = analyze_text("modules(a b); (a.x = 0) and (b.next.next.y = 1) and (a.last.last.last.x = 2)");
  EXPECT_EQ(a.extent_plus, 2);
  EXPECT_EQ(a.min_offset, -3);
  EXPECT_EQ(a.variables[a.variable_index("x")].span(), 3);
  EXPECT_EQ(a.variables[a.variable_index("y")].span(), 0);
}

TEST(Analysis, ExtentPlusIsNeverNegative) {
  Analysis a = analyze_text("modules(a); (a.last.x = 0)");
  EXPECT_EQ(a.extent_plus, 0);
}

TEST(Analysis, SlotReadsListWhatEachSlotContributes) {
  Analysis a = analyze_text("modules(a b c); (a.x < b.last.y) and (c.next.x >= a.y)");
  const int x = a.variable_index("x"), y = a.variable_index("y");
  ASSERT_EQ(a.slot_reads[0].size(), 2u);
  EXPECT_EQ(a.slot_reads[0][0].variable, x);
  EXPECT_EQ(a.slot_reads[0][1].variable, y);
  ASSERT_EQ(a.slot_reads[1].size(), 1u);
  EXPECT_EQ(a.slot_reads[1][0].offset, -1);
  ASSERT_EQ(a.slot_reads[2].size(), 1u);
  EXPECT_EQ(a.slot_reads[2][0].offset, 1);
}

TEST(Analysis, NeighborConstraintsAndTheirOffsets) {
  Analysis a = analyze_text("modules(a b c); neighbor(a.last c.last) and neighbor(c b)");
  ASSERT_EQ(a.neighbors.size(), 2u);
  EXPECT_EQ(a.neighbors[0].x, 0);
  EXPECT_EQ(a.neighbors[0].y, 2);
  EXPECT_EQ(a.neighbors[0].offset, -1);
  EXPECT_EQ(a.min_neighbor_offset, -1);
}

TEST(Program, CarriesOnlyValuesComparedWithALaterSlot) {
  Ast ast;
  Analysis a = analyze_text("modules(a b c d e); (a.v != -1) and (b.v = 0) and (e.v = a.v)", &ast);
  Program p(ast, a);
  // a.v is needed when e fills; every other term is decided by its own slot.
  ASSERT_EQ(p.cells.size(), 1u);
  EXPECT_EQ(p.cells[0].slot, 0);
  EXPECT_EQ(p.leaves[2].decide_slot, 4);
  EXPECT_EQ(p.leaves[0].decide_slot, 0);
}

TEST(Program, NeighborCarriesTheEarlierSlotsSetAndCullsTheLaterSlot) {
  Ast ast;
  Analysis a = analyze_text("modules(a b c); neighbor(a c) and neighbor(c b)", &ast);
  Program p(ast, a);
  ASSERT_EQ(p.sets.size(), 1u);  // only neighbor(a c) has its x filled first
  EXPECT_EQ(p.sets[0].slot, 0);
  EXPECT_EQ(p.slots[2].cull_leaves.size(), 1u);
  EXPECT_EQ(p.leaves[1].set, -1);  // neighbor(c b): c checks its own set for b
}

TEST(Program, EvaluatesInKleeneLogic) {
  Ast ast;
  Analysis a = analyze_text("modules(a); not ((a.x = 1) or (a.y = 1)) and (a.z = 1)", &ast);
  Program p(ast, a);
  std::vector<Truth> stack(static_cast<size_t>(p.max_stack));
  auto eval = [&](Truth x, Truth y, Truth z) {
    Truth leaves[3] = {x, y, z};
    return p.evaluate(leaves, stack.data());
  };
  EXPECT_EQ(eval(kFalse, kFalse, kTrue), kTrue);
  EXPECT_EQ(eval(kTrue, kUnknown, kTrue), kFalse);
  EXPECT_EQ(eval(kFalse, kUnknown, kTrue), kUnknown);
  EXPECT_EQ(eval(kFalse, kFalse, kFalse), kFalse);
  EXPECT_EQ(eval(kUnknown, kUnknown, kFalse), kFalse);
}

}  // namespace
}  // namespace dw::watch
