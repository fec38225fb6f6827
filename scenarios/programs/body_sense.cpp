// What a module feels of its body, as variables a watchpoint can read: how many neighbours it
// has and the most it ever had, whether it is moving, how fast (mm/s) and how high (mm). The host for scenarios where
// modules are struck, fall and tumble (push_wall): the algorithm under test is physics itself.
#include <algorithm>
#include <cmath>

#include "scenarios/programs/programs.h"

namespace dw::scenarios {
namespace {

enum Var : uint32_t { kNbrs, kPeakNbrs, kMoving, kSpeed, kHeight };

class BodySense final : public sim::HostProgram {
 public:
  explicit BodySense(double moving_speed) : moving_speed_(moving_speed) {}
  std::string_view name() const override { return "body_sense"; }
  std::vector<sim::VariableSpec> variables() const override {
    return {{"nbrs", 0}, {"peak_nbrs", 0}, {"moving", 0}, {"speed", 0}, {"height", 0}};
  }

  void step(sim::ModuleContext& m) const override {
    const auto nbrs = static_cast<int64_t>(m.neighbors().size());
    m.set(kNbrs, nbrs);
    m.set(kPeakNbrs, std::max(nbrs, m.get(kPeakNbrs)));
    if (!m.has_body()) return;  // a static lattice: nothing moves
    const sim::Vec3& v = m.velocity().linear;
    const double speed = std::hypot(v[0], v[1], v[2]);
    m.set(kMoving, speed > moving_speed_ ? 1 : 0);
    m.set(kSpeed, std::llround(speed * 1000));
    m.set(kHeight, std::llround(double(m.pose().position[2]) * 1000));
  }

 private:
  double moving_speed_;
};

}  // namespace

std::unique_ptr<const sim::HostProgram> make_body_sense(TableReader& params, const ProgramSetup&) {
  const auto speed = params.number("moving_speed", 0, 1e6);
  if (params.has("moving_speed") && !speed) return nullptr;
  return std::make_unique<BodySense>(speed.value_or(0.2));
}

}  // namespace dw::scenarios
