// The paper's benchmark host program (§V): every step each module draws x1..xk uniformly from
// 0..max_i-1. Parameter: the tuple [max_x1, ..., max_xk].
#include "scenarios/programs/programs.h"

namespace dw::scenarios {
namespace {

class RandomVars final : public sim::HostProgram {
 public:
  explicit RandomVars(std::vector<int64_t> maxima) : maxima_(std::move(maxima)) {}
  std::string_view name() const override { return "random_vars"; }
  std::vector<sim::VariableSpec> variables() const override {
    std::vector<sim::VariableSpec> v;
    for (size_t i = 0; i < maxima_.size(); ++i) v.push_back({"x" + std::to_string(i + 1), 0});
    return v;
  }
  void step(sim::ModuleContext& m) const override {
    // Stream i for x_{i+1}: the same numbers as the synthetic Table I trace.
    for (uint32_t i = 0; i < maxima_.size(); ++i) m.set(i, m.uniform(maxima_[i], i));
  }

 private:
  std::vector<int64_t> maxima_;
};

}  // namespace

std::unique_ptr<const sim::HostProgram> make_random_vars(TableReader& params, const ProgramSetup&) {
  auto tuple = params.integers("tuple", 1, int64_t{1} << 40, 1, 16);
  if (!tuple) {
    if (!params.has("tuple")) params.missing("tuple");
    return nullptr;
  }
  return std::make_unique<RandomVars>(std::move(*tuple));
}

}  // namespace dw::scenarios
