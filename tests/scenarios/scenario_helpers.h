// Scenarios written inline for the host-program tests, and what a run of them saw.
#pragma once

#include <gtest/gtest.h>

#include <queue>
#include <string>

#include "scenarios/scenario.h"
#include "sim/session.h"

namespace dw::scenarios::test {

inline Scenario load(const std::string& toml, ScenarioOverrides overrides = {}) {
  auto loaded = load_scenario_text("inline.toml", toml, overrides);
  if (auto* e = std::get_if<std::string>(&loaded)) ADD_FAILURE() << *e;
  return std::move(std::get<Scenario>(loaded));
}

// One variable of every module at every step of a run.
struct History {
  std::vector<std::vector<int64_t>> at;  // [step][module]
  int64_t operator()(int64_t t, sim::ModuleId m) const { return at[size_t(t)][m]; }
};

inline sim::Session::StepObserver record(const sim::Model& model, const std::string& variable, History& h) {
  const int column = model.column(variable);
  EXPECT_GE(column, 0) << variable;
  return [&model, column, &h](const sim::State& s, const sim::StepOutput&) {
    std::vector<int64_t> row(model.module_count());
    for (uint32_t m = 0; m < row.size(); ++m) row[m] = s.values[size_t(m) * model.variable_count() + size_t(column)];
    h.at.push_back(std::move(row));
  };
}

// Hop distances from `from` over the lattice graph.
inline std::vector<int> bfs(const sim::NeighborGraph& g, sim::ModuleId from) {
  std::vector<int> d(g.module_count(), -1);
  std::queue<sim::ModuleId> q;
  d[from] = 0;
  q.push(from);
  while (!q.empty()) {
    const sim::ModuleId m = q.front();
    q.pop();
    for (sim::ModuleId n : g.neighbors(m))
      if (d[n] < 0) {
        d[n] = d[m] + 1;
        q.push(n);
      }
  }
  return d;
}

}  // namespace dw::scenarios::test
