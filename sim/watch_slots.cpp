#include "sim/watch_slots.h"

#include <algorithm>

namespace dw::sim {

std::pair<size_t, size_t> MatchList::at(int64_t step) const {
  const auto [first, last] = std::equal_range(t.begin(), t.end(), step);
  return {static_cast<size_t>(first - t.begin()), static_cast<size_t>(last - t.begin())};
}

uint64_t MatchList::counted_at(int64_t step) const {
  uint64_t n = 0;
  for (const Counted& c : counted) n += c.t == step ? c.matches : 0;
  return n;
}

uint64_t MatchList::counted_total() const {
  uint64_t n = 0;
  for (const Counted& c : counted) n += c.matches;
  return n;
}

void MatchList::drop_after(int64_t through, size_t k, size_t a) {
  const size_t keep =
      static_cast<size_t>(std::upper_bound(detected.begin(), detected.end(), through) - detected.begin());
  t.resize(keep);
  detected.resize(keep);
  slots.resize(keep * k);
  actions.resize(keep * a);
  std::erase_if(counted, [through](const Counted& c) { return c.detected > through; });
}

WatchSlots::WatchSlots(std::span<const HostedWatchpoint> initial) {
  for (const HostedWatchpoint& h : initial) add(h);
}

std::optional<uint32_t> WatchSlots::position(WatchId id) const {
  if (id.index >= generations_.size() || generations_[id.index] != id.generation) return std::nullopt;
  const auto at = std::find(order_.begin(), order_.end(), id.index);
  if (at == order_.end()) return std::nullopt;
  return static_cast<uint32_t>(at - order_.begin());
}

std::optional<uint32_t> WatchSlots::find(std::string_view name) const {
  for (uint32_t w = 0; w < size(); ++w)
    if ((*this)[w].hosted.watchpoint.name == name) return w;
  return std::nullopt;
}

WatchId WatchSlots::add(HostedWatchpoint hosted) {
  uint32_t index;
  if (free_.empty()) {
    index = static_cast<uint32_t>(slots_.size());
    slots_.emplace_back();
    generations_.push_back(0);
  } else {
    index = free_.back();
    free_.pop_back();
  }
  slots_[index] = WatchSlot{std::move(hosted)};
  order_.push_back(index);
  return {index, generations_[index]};
}

void WatchSlots::free_slot(uint32_t index) {
  slots_[index].reset();  // its watchpoint and findings go now, not when the slot is taken again
  ++generations_[index];
  free_.push_back(index);
}

void WatchSlots::move_last_to(uint32_t w) {
  free_slot(order_[w]);
  order_[w] = order_.back();
  order_.pop_back();
}

void WatchSlots::erase(uint32_t w) {
  free_slot(order_[w]);
  order_.erase(order_.begin() + static_cast<std::ptrdiff_t>(w));
}

HostedWatches WatchSlots::hosted() const {
  std::vector<const HostedWatchpoint*> each;
  for (uint32_t index : order_) each.push_back(&slots_[index]->hosted);
  return HostedWatches(std::move(each));
}

}  // namespace dw::sim
