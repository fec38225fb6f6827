// A host program that runs a test's lambda on every module, with one variable (`side`), and the
// model of a lattice running it: for the physics tests that script a module's moves step by step.
#pragma once

#include <functional>
#include <memory>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "sim/host_program.h"
#include "sim/model.h"

namespace dw::physics::test {

class Scripted final : public sim::HostProgram {
 public:
  explicit Scripted(std::function<void(sim::ModuleContext&)> f) : f_(std::move(f)) {}
  std::string_view name() const override { return "scripted"; }
  std::vector<sim::VariableSpec> variables() const override { return {{"side", 0}}; }
  void step(sim::ModuleContext& m) const override { f_(m); }

 private:
  std::function<void(sim::ModuleContext&)> f_;
};

inline std::unique_ptr<sim::Model> scripted_model(sim::Lattice lattice, std::function<void(sim::ModuleContext&)> f) {
  std::vector<std::unique_ptr<const sim::HostProgram>> programs;
  programs.push_back(std::make_unique<Scripted>(std::move(f)));
  auto built = sim::build_model(std::move(lattice), std::move(programs), {}, 1);
  return std::move(std::get<std::unique_ptr<sim::Model>>(built));
}

}  // namespace dw::physics::test
