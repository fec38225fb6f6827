// Holes flowing through the surface layer of a large latched block (issue: reconfiguration at
// scale): a module of the layer whose cell at +x or +y is free moves into it by a lattice move,
// now and then (`chance` percent of the steps it could), so the holes wander towards -x and -y
// and the modules towards +x and +y. Neighbours tell each other which cell they are in; a module
// only knows what touches it, so a cell is free when no neighbour said it is there.
//
// The bug: two modules may pick the same free cell at the same step, one from -x and one from -y
// of it. The World carries out the first request in module order and refuses the other, but the
// algorithm never meant either to give way. `target` holds the cell a module asked for at this
// step (x + size_x * y, or -1), so two modules heading for one cell are a watchpoint away: they
// are diagonal to each other and both touch the module at (x - 1, y - 1) of the cell.
// With `alternate = 1` moves along +x happen only on even steps and along +y only on odd ones:
// two modules never ask for one cell at once.
#include <cmath>

#include "scenarios/programs/programs.h"

namespace dw::scenarios {
namespace {

enum Var : uint32_t { kTarget, kMoving };
enum Word : uint32_t { kWX, kWY, kWZ };

class SurfaceFlow final : public sim::HostProgram {
 public:
  SurfaceFlow(int64_t layer, int64_t chance, bool alternate, int64_t size_x, int64_t size_y)
      : layer_(layer), chance_(chance), alternate_(alternate), size_x_(size_x), size_y_(size_y) {}
  std::string_view name() const override { return "surface_flow"; }
  std::vector<sim::VariableSpec> variables() const override { return {{"target", -1}, {"moving", 0}}; }

  void step(sim::ModuleContext& m) const override {
    if (!m.has_body()) return;
    const sim::Vec3& at = m.pose().position;
    const int64_t x = std::lround(at[0]), y = std::lround(at[1]), z = std::lround(at[2]);
    int64_t target = -1;
    // Nothing has been heard at step 0: no cell is known to be free yet.
    if (z == layer_ && !m.moving() && m.step() > 0) {
      bool free_x = x + 1 < size_x_, free_y = y + 1 < size_y_;
      for (const sim::Message& msg : m.inbox()) {
        if (msg[kWZ] != z) continue;
        if (msg[kWX] == x + 1 && msg[kWY] == y) free_x = false;
        if (msg[kWX] == x && msg[kWY] == y + 1) free_y = false;
      }
      if (alternate_) {
        free_x = free_x && m.step() % 2 == 0;
        free_y = free_y && m.step() % 2 == 1;
      }
      if ((free_x || free_y) && m.uniform(100, 0) < chance_) {
        const bool along_x = free_x && (!free_y || m.uniform(2, 1) == 0);
        m.move(along_x ? sim::Vec3{1, 0, 0} : sim::Vec3{0, 1, 0});
        target = along_x ? x + 1 + size_x_ * y : x + size_x_ * (y + 1);
      }
    }
    m.set(kTarget, target);
    m.set(kMoving, m.moving() ? 1 : 0);
    m.broadcast({x, y, z});
  }

 private:
  int64_t layer_, chance_;
  bool alternate_;
  int64_t size_x_, size_y_;
};

}  // namespace

std::unique_ptr<const sim::HostProgram> make_surface_flow(TableReader& params, const ProgramSetup& setup) {
  const auto layer = params.integer("layer", 0, 1'000'000);
  const auto chance = params.integer("chance", 0, 100);
  const auto alternate = params.integer("alternate", 0, 1);
  if ((params.has("layer") && !layer) || (params.has("chance") && !chance) || (params.has("alternate") && !alternate))
    return nullptr;
  const auto& size = setup.lattice.size;
  return std::make_unique<SurfaceFlow>(layer.value_or(int64_t{size[2]} - 1), chance.value_or(100),
                                       alternate.value_or(0) == 1, size[0], size[1]);
}

}  // namespace dw::scenarios
