#include "sim/trace.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <unordered_map>

namespace dw::sim {

Trace Trace::build(std::vector<Entry> entries, std::vector<std::string> variable_names) {
  Trace trace;
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

  // Lines sorted by (step, module): each step's lines then come out in module order.
  std::sort(entries.begin(), entries.end(),
            [](const Entry& a, const Entry& b) { return a.t != b.t ? a.t < b.t : a.m < b.m; });
  // Only the steps with lines are indexed: a trace whose one line is at step 9,999,999 is small.
  trace.step_count_ = last_step + 1;
  std::vector<uint8_t> has_line(ids.size(), 0);
  size_t values = 0, nbrs = 0;
  for (size_t i = 0; i < entries.size(); ++i) {
    if (i == 0 || entries[i].t != entries[i - 1].t) {
      trace.busy_steps_.push_back(entries[i].t);
      trace.busy_begin_.push_back(i);
    }
    values += entries[i].vars.size();
    nbrs += entries[i].nbrs.size();
  }
  trace.busy_begin_.push_back(entries.size());
  trace.line_module_.reserve(entries.size());
  trace.value_begin_.reserve(entries.size() + 1);
  trace.nbr_begin_.reserve(entries.size() + 1);
  trace.value_var_.reserve(values);
  trace.value_.reserve(values);
  trace.nbrs_.reserve(nbrs);
  for (Entry& e : entries) {
    const uint32_t m = dense(e.m);
    has_line[m] = 1;
    trace.line_module_.push_back(m);
    trace.value_begin_.push_back(trace.value_.size());
    for (const auto& [var, value] : e.vars) {
      trace.value_var_.push_back(var);
      trace.value_.push_back(value);
    }
    trace.nbr_begin_.push_back(trace.nbrs_.size());
    for (watch::ModuleId n : e.nbrs) trace.nbrs_.push_back(dense(n));
    e = Entry{};  // its memory goes back as the flat arrays grow
  }
  trace.value_begin_.push_back(trace.value_.size());
  trace.nbr_begin_.push_back(trace.nbrs_.size());
  trace.modules_with_lines_ = static_cast<uint32_t>(std::count(has_line.begin(), has_line.end(), 1));
  return trace;
}

double default_frame_budget() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return 2.0 * (1ull << 30);
  return static_cast<double>(pages) * static_cast<double>(page) / 4;
}

std::variant<FrameReader, std::string> FrameReader::make(const Trace& trace,
                                                         const std::optional<std::vector<std::string>>& variables,
                                                         double max_frame_bytes) {
  FrameReader reader(trace);
  reader.universe_.module_ids = trace.universe_.module_ids;
  const std::vector<std::string>& all = trace.universe_.variables;
  reader.column_of_.assign(all.size(), -1);
  for (size_t v = 0; v < all.size(); ++v) {
    if (variables && std::find(variables->begin(), variables->end(), all[v]) == variables->end()) continue;
    reader.column_of_[v] = static_cast<int32_t>(reader.universe_.variables.size());
    reader.universe_.variables.push_back(all[v]);
  }
  const double modules = static_cast<double>(reader.universe_.module_ids.size());
  const double vars = static_cast<double>(reader.universe_.variables.size());
  const double frame_bytes = modules * (9.0 * vars + 5.0);
  if (frame_bytes > max_frame_bytes) {
    char need[32], most[32];
    std::snprintf(need, sizeof need, "%.2f", frame_bytes / (1u << 30));
    std::snprintf(most, sizeof most, "%.2f", max_frame_bytes / (1u << 30));
    return "one frame of the trace needs " + std::string(need) + " GiB (" + std::to_string(modules) + " modules x " +
           std::to_string(reader.universe_.variables.size()) + " variables); at most " + most +
           " GiB is allowed (--max-frame-memory)";
  }
  return reader;
}

watch::Frame FrameReader::frame(int64_t step, FrameBuffer& b) const {
  const Trace& t = *trace_;
  const size_t modules = universe_.module_ids.size(), vars = universe_.variables.size();
  b.present.assign(modules, 0);
  b.values.assign(modules * vars, 0);
  b.has_value.assign(modules * vars, 0);
  b.nbr_begin.assign(modules + 1, 0);
  b.nbrs.clear();
  uint64_t first = 0, last = 0;  // the step's lines, none when it has no line
  const auto busy = std::lower_bound(t.busy_steps_.begin(), t.busy_steps_.end(), step);
  if (busy != t.busy_steps_.end() && *busy == step) {
    const size_t i = static_cast<size_t>(busy - t.busy_steps_.begin());
    first = t.busy_begin_[i];
    last = t.busy_begin_[i + 1];
  }
  // Lines are in module order: the neighbour lists are laid out in that order too.
  for (uint64_t line = first; line < last; ++line) {
    const uint32_t m = t.line_module_[line];
    b.present[m] = 1;
    for (uint64_t i = t.value_begin_[line]; i < t.value_begin_[line + 1]; ++i) {
      const int32_t c = column_of_[t.value_var_[i]];
      if (c < 0) continue;
      b.values[m * vars + static_cast<size_t>(c)] = t.value_[i];
      b.has_value[m * vars + static_cast<size_t>(c)] = 1;
    }
    b.nbr_begin[m + 1] = static_cast<uint32_t>(t.nbr_begin_[line + 1] - t.nbr_begin_[line]);
    b.nbrs.insert(b.nbrs.end(), t.nbrs_.begin() + static_cast<ptrdiff_t>(t.nbr_begin_[line]),
                  t.nbrs_.begin() + static_cast<ptrdiff_t>(t.nbr_begin_[line + 1]));
  }
  for (size_t m = 0; m < modules; ++m) b.nbr_begin[m + 1] += b.nbr_begin[m];
  watch::Frame f;
  f.step = step;
  f.present = b.present;
  f.values = b.values;
  f.has_value = b.has_value;
  f.nbr_begin = b.nbr_begin;
  f.nbrs = b.nbrs;
  f.variable_count = static_cast<uint32_t>(vars);
  return f;
}

}  // namespace dw::sim
