#include "watch/agent_history.h"

#include <algorithm>

namespace dw::watch {

void AgentHistory::configure(const Program& p, bool temporal_spans, uint32_t first, uint32_t modules) {
  first_ = first;
  modules_ = modules;
  values_.assign(p.column_count(), {});  // the program's variables, then its kept windows' columns
  for (size_t v = 0; v < values_.size(); ++v)
    values_[v].configure(temporal_spans ? p.agent_delay() - p.variable_min_offset[v] + 1 : 0);
  // Neighbour sets (and presence) are read at the fill step, to spread, and at neighbor() offsets.
  topology_.configure(temporal_spans ? p.agent_delay() - p.min_neighbor_offset + 1 : 0);
}

void AgentHistory::begin_record(const Frame& frame) {
  for (StepRing<Values>& ring : values_) {
    Values& row = ring.write(frame.step);
    row.values.resize(modules_);
    row.known.resize(modules_);
  }
  // A graph copied for an earlier step serves again while the frames' graph stays the same (a
  // trace of a static lattice). Taken before the write, which may reuse its ring entry.
  Topology last;
  if (const Topology* t = topology_.find(frame.step - 1); t != nullptr && !frame.topology && !t->shared) last = *t;
  Topology& t = topology_.write(frame.step);
  // Presence is whole in every frame: kept for every module this history holds, its host's own
  // or not (a rank's agents whose aggregates read other ranks' modules).
  t.present.assign(frame.present.begin() + first_, frame.present.begin() + first_ + modules_);
  if (frame.topology) {
    t.owner = frame.topology;
    t.begin = frame.nbr_begin;
    t.ids = frame.nbrs;
    t.shared = true;
    return;
  }
  t.shared = false;
  if (last.owner && std::ranges::equal(last.begin, frame.nbr_begin) && std::ranges::equal(last.ids, frame.nbrs)) {
    t.owner = std::move(last.owner);
    t.begin = last.begin;
    t.ids = last.ids;
    return;
  }
  auto copy = std::make_shared<Graph>(
      Graph{{frame.nbr_begin.begin(), frame.nbr_begin.end()}, {frame.nbrs.begin(), frame.nbrs.end()}});
  t.begin = copy->begin;
  t.ids = copy->ids;
  t.owner = std::move(copy);
}

void AgentHistory::record(const Frame& frame, uint32_t begin, uint32_t end, std::span<const int> columns) {
  Topology& t = *topology_.find(frame.step);
  for (uint32_t m = begin; m < end; ++m) t.present[m - first_] = frame.present[m];
  for (size_t v = 0; v < values_.size(); ++v) {
    Values& row = *values_[v].find(frame.step);
    if (v >= columns.size() || columns[v] < 0) {  // frames never carry it (a kept window's column is worked out after)
      std::fill(row.known.begin() + (begin - first_), row.known.begin() + (end - first_), 0);
      std::fill(row.values.begin() + (begin - first_), row.values.begin() + (end - first_), 0);
      continue;
    }
    const size_t c = static_cast<size_t>(columns[v]);
    for (uint32_t m = begin; m < end; ++m) {
      const size_t at = size_t{m - frame.first_module} * frame.variable_count + c;
      const bool known = frame.present[m] && frame.has(at);
      row.known[m - first_] = known;
      row.values[m - first_] = known ? frame.values[at] : 0;
    }
  }
}

uint64_t AgentHistory::held() const {
  uint64_t steps = static_cast<uint64_t>(topology_.held());
  for (const auto& ring : values_) steps += static_cast<uint64_t>(ring.held());
  return steps * modules_;
}

size_t AgentHistory::bytes() const {
  constexpr size_t kBlock = 16;  // the allocator's own per heap block
  size_t n = 0;
  for (const auto& ring : values_) n += ring.capacity() * (sizeof(Values) + modules_ * 9 + 2 * kBlock);
  const void* counted = nullptr;  // copied graphs serve consecutive steps: each is counted once
  for (const Topology& t : topology_.items()) {
    n += sizeof(Topology) + t.present.capacity() + kBlock;
    if (t.owner && !t.shared && t.owner.get() != counted) {
      n += (t.begin.size() + t.ids.size()) * sizeof(uint32_t) + 3 * kBlock;
      counted = t.owner.get();
    }
  }
  return n;
}

}  // namespace dw::watch
