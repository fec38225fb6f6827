// Small host programs for the runtime's own tests: they use every part of the API (randomness,
// messages, variables kept across steps) so that a mistake in the runtime changes their states.
#pragma once

#include <algorithm>
#include <memory>

#include "sim/host_program.h"
#include "sim/model.h"
#include "sim/world.h"
#include "watch/watchpoint.h"

namespace dw::sim::test_programs {

// Every module keeps a random value `v` and a running `mix`; each step it sends v, mix and up to
// two more words (1 + v % 3 words in all, so that messages differ in size) to a random neighbour,
// and folds every word it receives (in inbox order) into mix. `count` counts received messages.
class Gossip final : public HostProgram {
 public:
  std::string_view name() const override { return "gossip"; }
  std::vector<VariableSpec> variables() const override { return {{"v", 0}, {"mix", 1}, {"count", 0}}; }
  void step(ModuleContext& m) const override {
    int64_t mix = m.get(1);
    for (const Message& msg : m.inbox()) {
      mix = (mix * 31 + msg.from) % 1000003;
      for (int64_t w : msg.payload()) mix = (mix * 31 + w) % 1000003;
    }
    m.set(1, mix);
    m.set(2, m.get(2) + static_cast<int64_t>(m.inbox().size()));
    m.set(0, m.uniform(4, 0));
    const auto n = m.neighbors();
    const int64_t words[] = {m.get(0), mix, m.id(), m.step()};
    if (!n.empty())
      m.send(n[static_cast<size_t>(m.uniform(static_cast<int64_t>(n.size()), 1))],
             std::span(words, static_cast<size_t>(1 + m.get(0) % 3)));
  }
};

// At step 2, each of `modules` sends to the module two ids on, which is no neighbour on a line:
// a misuse the runtime must stop.
class SendsToStranger final : public HostProgram {
 public:
  explicit SendsToStranger(std::vector<ModuleId> modules = {5}) : modules_(std::move(modules)) {}
  std::string_view name() const override { return "stranger"; }
  std::vector<VariableSpec> variables() const override { return {{"s", 0}}; }
  void step(ModuleContext& m) const override {
    if (m.step() == 2 && std::ranges::find(modules_, m.id()) != modules_.end()) m.send(m.id() + 2, {1});
  }

 private:
  std::vector<ModuleId> modules_;
};

inline watch::Watchpoint compile(const std::string& text) {
  auto r = watch::compile_watchpoint("w", watch::SourceText("<test>", text));
  return std::get<watch::Watchpoint>(std::move(r));
}

inline std::unique_ptr<Model> gossip_model(LatticeSpec spec,
                                           std::vector<std::pair<std::string, watch::Algorithm>> watches,
                                           uint64_t seed = 1) {
  std::vector<std::unique_ptr<const HostProgram>> programs;
  programs.push_back(std::make_unique<Gossip>());
  std::vector<HostedWatchpoint> hosted;
  for (auto& [text, algorithm] : watches) {
    watch::DetectorOptions options;
    hosted.push_back(HostedWatchpoint{compile(text), algorithm, MatchAction::Log, options});
  }
  return std::get<std::unique_ptr<Model>>(
      build_model(make_lattice(spec), std::move(programs), std::move(hosted), seed));
}

}  // namespace dw::sim::test_programs
