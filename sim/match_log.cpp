#include "sim/match_log.h"

#include <algorithm>
#include <charconv>
#include <nlohmann/json.hpp>
#include <numeric>

namespace dw::sim {

MatchLog::MatchLog(std::vector<WatchInfo> watches, std::ostream* out, size_t keep) : out_(out), keep_(keep) {
  for (WatchInfo& w : watches) {
    Watch entry;
    // nlohmann escapes the names once; numbers are formatted per match.
    entry.prefix = "{\"watch\":" + nlohmann::json(w.name).dump() + ",\"t\":";
    for (const std::string& s : w.slots) entry.slot_keys.push_back(nlohmann::json(s).dump() + ":");
    entry.info = std::move(w);
    watches_.push_back(std::move(entry));
  }
}

watch::MatchSink MatchLog::sink(size_t index) {
  return [this, index](int64_t t, std::span<const watch::ModuleId> ids) {
    Watch& w = watches_[index];
    const size_t k = w.info.slots.size();
    const size_t n = ids.size() / k;
    w.count += n;
    if (out_ == nullptr && w.kept.size() >= keep_) return;
    std::vector<size_t> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
      return std::lexicographical_compare(ids.begin() + a * k, ids.begin() + (a + 1) * k, ids.begin() + b * k,
                                          ids.begin() + (b + 1) * k);
    });
    for (size_t i = 0; i < n && w.kept.size() < keep_; ++i)
      w.kept.push_back({t, std::vector<watch::ModuleId>(ids.begin() + order[i] * k, ids.begin() + (order[i] + 1) * k)});
    if (out_ == nullptr) return;
    Batch batch{t, index, {}};
    batch.ids.reserve(ids.size());
    for (size_t i : order) batch.ids.insert(batch.ids.end(), ids.begin() + i * k, ids.begin() + (i + 1) * k);
    pending_.push_back(std::move(batch));
  };
}

void MatchLog::release(int64_t t) {
  if (out_ == nullptr || pending_.empty()) return;
  std::stable_sort(pending_.begin(), pending_.end(),
                   [](const Batch& a, const Batch& b) { return a.t != b.t ? a.t < b.t : a.watch < b.watch; });
  size_t done = 0;
  while (done < pending_.size() && pending_[done].t <= t) write(pending_[done++]);
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<ptrdiff_t>(done));
  out_->flush();
}

void MatchLog::write(const Batch& b) {
  const Watch& w = watches_[b.watch];
  const size_t k = w.slot_keys.size();
  std::string line;
  char number[24];
  auto append_number = [&](int64_t v) {
    const auto r = std::to_chars(number, number + sizeof number, v);
    line.append(number, r.ptr);
  };
  for (size_t i = 0; i < b.ids.size(); i += k) {
    line.clear();
    line += w.prefix;
    append_number(b.t);
    line += ",\"slots\":{";
    for (size_t s = 0; s < k; ++s) {
      if (s) line += ',';
      line += w.slot_keys[s];
      append_number(b.ids[i + s]);
    }
    line += "}}\n";
    out_->write(line.data(), static_cast<std::streamsize>(line.size()));
  }
}

}  // namespace dw::sim
