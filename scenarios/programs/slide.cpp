// Modules sliding along the top of a row (the paper's §I example): each top module moves one
// cell along +x by a lattice move when the cell ahead is free or being vacated, so a row of them
// travels like a train until its head reaches `stop`. Neighbours tell each other where they are
// and whether they are setting off; a module only knows what touches it.
//
// `gap` is how many steps the cell ahead must have been free (or its occupant setting off) before
// a module sets off itself. With gap < 4, adjacent modules initiate motion within four steps of
// each other, which is what the §I watchpoint catches; with gap >= 4 they never do.
#include <cmath>

#include "scenarios/programs/programs.h"

namespace dw::scenarios {
namespace {

enum Var : uint32_t { kCellX, kStarted, kMoving, kFreeFor };
enum Word : uint32_t { kWX, kWZ, kWStarting };

class Slide final : public sim::HostProgram {
 public:
  Slide(int64_t gap, int64_t layer, int64_t stop) : gap_(gap), layer_(layer), stop_(stop) {}
  std::string_view name() const override { return "slide"; }
  std::vector<sim::VariableSpec> variables() const override {
    return {{"cell_x", 0}, {"started", 0}, {"moving", 0}, {"_free_for", 0}};
  }

  void step(sim::ModuleContext& m) const override {
    if (!m.has_body()) return;
    const int64_t x = std::lround(m.pose().position[0]), z = std::lround(m.pose().position[2]);
    m.set(kCellX, x);
    m.set(kMoving, m.moving() ? 1 : 0);
    bool starting = false;
    if (z == layer_ && !m.moving()) {
      // The cell ahead is free when no neighbour says it is there, or its occupant sets off. At
      // step 0 nothing has been heard yet, so nothing is known to be free: without this, every
      // slider would set off at once instead of one step after the one ahead.
      bool free = x < stop_ && m.step() > 0;
      for (const sim::Message& msg : m.inbox())
        if (msg[kWX] == x + 1 && msg[kWZ] == z && msg[kWStarting] == 0) free = false;
      const int64_t free_for = free ? m.get(kFreeFor) + 1 : 0;
      starting = free_for > gap_;
      m.set(kFreeFor, starting ? 0 : free_for);
      if (starting) m.move({1, 0, 0});
    } else {
      m.set(kFreeFor, 0);
    }
    m.set(kStarted, starting ? 1 : 0);
    m.broadcast({x, z, starting ? 1 : 0});
  }

 private:
  int64_t gap_, layer_, stop_;
};

}  // namespace

std::unique_ptr<const sim::HostProgram> make_slide(TableReader& params, const ProgramSetup& setup) {
  const int64_t nx = setup.lattice.size[0];
  const auto gap = params.integer("gap", 0, 1'000'000);
  const auto layer = params.integer("layer", 0, 1'000'000);
  const auto stop = params.integer("stop", 0, 1'000'000);
  if ((params.has("gap") && !gap) || (params.has("layer") && !layer) || (params.has("stop") && !stop)) return nullptr;
  return std::make_unique<Slide>(gap.value_or(0), layer.value_or(1), stop.value_or(nx - 1));
}

}  // namespace dw::scenarios
