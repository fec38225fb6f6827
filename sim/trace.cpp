#include "sim/trace.h"

#include <algorithm>
#include <unordered_map>

namespace dw::sim {

Trace Trace::build(const std::vector<Entry>& entries, std::vector<std::string> variable_names) {
  Trace trace;
  trace.lines_ = entries.size();
  trace.universe_.variables = std::move(variable_names);
  std::vector<watch::ModuleId>& ids = trace.universe_.module_ids;
  int64_t last_step = -1;
  watch::ModuleId largest = 0;
  for (const Entry& e : entries) {
    largest = std::max(largest, e.m);
    for (watch::ModuleId n : e.nbrs) largest = std::max(largest, n);
    last_step = std::max(last_step, e.t);
  }
  // Every module that has a line or is someone's neighbour (it may never have a line of its own),
  // in id order: marked in a table when ids are compact, sorted otherwise.
  auto each_id = [&](auto&& fn) {
    for (const Entry& e : entries) {
      fn(e.m);
      for (watch::ModuleId n : e.nbrs) fn(n);
    }
  };
  const bool compact = largest < 4 * entries.size() + 1024;
  std::vector<uint32_t> dense_table;  // id -> dense index, when ids are compact
  std::unordered_map<watch::ModuleId, uint32_t> dense_map;
  if (compact) {
    constexpr uint32_t kUnseen = UINT32_MAX;
    dense_table.assign(static_cast<size_t>(largest) + 1, kUnseen);
    each_id([&](watch::ModuleId m) { dense_table[m] = 0; });
    for (size_t m = 0; m < dense_table.size(); ++m)
      if (dense_table[m] != kUnseen) {
        dense_table[m] = static_cast<uint32_t>(ids.size());
        ids.push_back(static_cast<watch::ModuleId>(m));
      }
  } else {
    each_id([&](watch::ModuleId m) { ids.push_back(m); });
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    dense_map.reserve(ids.size());
    for (uint32_t i = 0; i < ids.size(); ++i) dense_map.emplace(ids[i], i);
  }
  auto dense = [&](watch::ModuleId m) { return compact ? dense_table[m] : dense_map.at(m); };

  const size_t modules = ids.size();
  const size_t vars = trace.universe_.variables.size();
  trace.steps_.resize(static_cast<size_t>(last_step + 1));
  // Per step, each module's entry (or none), so that neighbour lists come out in module order.
  std::vector<std::vector<const Entry*>> by_step(trace.steps_.size(), std::vector<const Entry*>());
  for (const Entry& e : entries) by_step[static_cast<size_t>(e.t)].push_back(&e);
  for (size_t t = 0; t < trace.steps_.size(); ++t) {
    Step& s = trace.steps_[t];
    s.present.assign(modules, 0);
    s.values.assign(modules * vars, 0);
    s.has_value.assign(modules * vars, 0);
    std::vector<const Entry*>& row = by_step[t];
    std::sort(row.begin(), row.end(), [&](const Entry* a, const Entry* b) { return a->m < b->m; });
    s.nbr_begin.assign(modules + 1, 0);
    size_t r = 0;
    for (uint32_t m = 0; m < modules; ++m) {
      s.nbr_begin[m] = static_cast<uint32_t>(s.nbrs.size());
      if (r < row.size() && row[r]->m == ids[m]) {
        const Entry& e = *row[r++];
        s.present[m] = 1;
        for (const auto& [var, value] : e.vars) {
          s.values[m * vars + var] = value;
          s.has_value[m * vars + var] = 1;
        }
        for (watch::ModuleId n : e.nbrs) s.nbrs.push_back(dense(n));
      }
    }
    s.nbr_begin[modules] = static_cast<uint32_t>(s.nbrs.size());
  }
  return trace;
}

watch::Frame Trace::frame(int64_t step) const {
  const Step& s = steps_[static_cast<size_t>(step)];
  watch::Frame f;
  f.step = step;
  f.present = s.present;
  f.values = s.values;
  f.has_value = s.has_value;
  f.nbr_begin = s.nbr_begin;
  f.nbrs = s.nbrs;
  f.variable_count = static_cast<uint32_t>(universe_.variables.size());
  return f;
}

}  // namespace dw::sim
