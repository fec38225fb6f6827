#include "sim/trace.h"

#include <algorithm>
#include <cstdio>
#include <unordered_map>

namespace dw::sim {

std::variant<Trace, std::string> Trace::build(const std::vector<Entry>& entries,
                                              std::vector<std::string> variable_names) {
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
  // Lines sorted by (step, module): each step's neighbour lists then come out in module order.
  std::vector<const Entry*> order(entries.size());
  for (size_t i = 0; i < entries.size(); ++i) order[i] = &entries[i];
  std::sort(order.begin(), order.end(),
            [](const Entry* a, const Entry* b) { return a->t != b->t ? a->t < b->t : a->m < b->m; });

  // Frames are dense (every module, every variable), but a step with no line shares one empty
  // frame, so a sparse trace costs what its lines cost. Refuse what memory cannot hold.
  size_t busy_steps = 0;
  for (size_t i = 0; i < order.size(); ++i) busy_steps += i == 0 || order[i]->t != order[i - 1]->t;
  const double frame_bytes = static_cast<double>(modules) * (9.0 * static_cast<double>(vars) + 5.0);
  const double total_bytes = frame_bytes * static_cast<double>(busy_steps + 1);
  if (total_bytes > kMaxTraceBytes) {
    char gib[32];
    std::snprintf(gib, sizeof gib, "%.1f", total_bytes / (1024.0 * 1024 * 1024));
    return "the trace needs " + std::string(gib) + " GiB in memory (" + std::to_string(busy_steps) + " steps x " +
           std::to_string(modules) + " modules x " + std::to_string(vars) + " variables); at most " +
           std::to_string(static_cast<int>(kMaxTraceBytes / (1ull << 30))) + " GiB is allowed";
  }

  auto empty_frame = [&](Step& s) {
    s.present.assign(modules, 0);
    s.values.assign(modules * vars, 0);
    s.has_value.assign(modules * vars, 0);
    s.nbr_begin.assign(modules + 1, 0);
  };
  trace.step_frame_.assign(static_cast<size_t>(last_step + 1), 0);
  trace.steps_.reserve(busy_steps + 1);
  empty_frame(trace.steps_.emplace_back());  // frame 0: everyone absent
  for (size_t i = 0; i < order.size();) {
    const int64_t t = order[i]->t;
    trace.step_frame_[static_cast<size_t>(t)] = static_cast<uint32_t>(trace.steps_.size());
    Step& s = trace.steps_.emplace_back();
    empty_frame(s);
    for (uint32_t m = 0; m < modules; ++m) {
      s.nbr_begin[m] = static_cast<uint32_t>(s.nbrs.size());
      if (i < order.size() && order[i]->t == t && order[i]->m == ids[m]) {
        const Entry& e = *order[i++];
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
  const Step& s = steps_[step_frame_[static_cast<size_t>(step)]];
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
