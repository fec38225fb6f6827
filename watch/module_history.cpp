#include "watch/module_history.h"

namespace dw::watch {

void ModuleHistory::configure(const Program& p, bool temporal_spans) {
  values_.resize(p.variables.size());
  for (size_t v = 0; v < values_.size(); ++v)
    values_[v].configure(temporal_spans ? p.extent_plus - p.variable_min_offset[v] + 1 : 0);
  // Neighbour sets (and presence) are read at the fill step, to spread, and at neighbor() offsets.
  neighbors_.configure(temporal_spans ? p.extent_plus - p.min_neighbor_offset + 1 : 0);
}

void ModuleHistory::record(int64_t step, bool present, const int64_t* values, const uint8_t* has_value,
                           std::span<const uint32_t> neighbors) {
  for (size_t v = 0; v < values_.size(); ++v) {
    Value& slot = values_[v].write(step);
    slot.known = present && has_value[v];
    slot.value = slot.known ? values[v] : 0;
  }
  Neighbors& n = neighbors_.write(step);
  n.present = present;
  if (present) n.ids.assign(neighbors.begin(), neighbors.end());
  else n.ids.clear();
}

uint64_t ModuleHistory::held() const {
  uint64_t total = 0;
  for (const auto& ring : values_) total += static_cast<uint64_t>(ring.held());
  return total + static_cast<uint64_t>(neighbors_.held());
}

size_t ModuleHistory::bytes() const {
  constexpr size_t kBlock = 16;  // the allocator's own per heap block
  size_t n = values_.capacity() * sizeof(StepRing<Value>) + kBlock;
  for (const auto& ring : values_) n += ring.capacity() * sizeof(Value) + kBlock;
  n += neighbors_.capacity() * sizeof(Neighbors) + kBlock;
  for (const Neighbors& ns : neighbors_.items())
    n += ns.ids.capacity() * sizeof(uint32_t) + (ns.ids.capacity() ? kBlock : 0);
  return n;
}

}  // namespace dw::watch
