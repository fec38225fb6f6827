#include "sim/match_log.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <nlohmann/json.hpp>
#include <numeric>

namespace dw::sim {

MatchLog::MatchLog(std::vector<WatchInfo> watches, std::ostream* out, size_t keep) : out_(out), keep_(keep) {
  for (WatchInfo& w : watches) {
    Watch entry;
    // nlohmann escapes the names once; numbers are formatted per match.
    entry.prefix =
        "{\"watch\":" + nlohmann::json(w.name).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) +
        ",\"t\":";
    for (const std::string& s : w.slots)
      entry.slot_keys.push_back(nlohmann::json(s).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + ":");
    entry.info = std::move(w);
    watches_.push_back(std::move(entry));
  }
}

// The groups of k ids in `ids`, sorted lexicographically. When a whole group fits in 64 bits it is
// packed into one integer, so that sorting compares integers (ten times faster on 100,000 groups).
std::vector<watch::ModuleId> MatchLog::sorted_groups(std::span<const watch::ModuleId> ids, size_t k) {
  if (k == 0) return {};  // a zero-slot watchpoint's rows hold no id
  const size_t n = ids.size() / k;
  std::vector<watch::ModuleId> out;
  out.reserve(ids.size());
  const watch::ModuleId largest = ids.empty() ? 0 : *std::max_element(ids.begin(), ids.end());
  const unsigned bits = std::max(1u, static_cast<unsigned>(std::bit_width(largest)));
  if (bits * k <= 64) {
    std::vector<uint64_t> keys(n);
    for (size_t i = 0; i < n; ++i)
      for (size_t s = 0; s < k; ++s) keys[i] = (keys[i] << bits) | ids[i * k + s];
    std::sort(keys.begin(), keys.end());
    const uint64_t mask = bits == 64 ? ~uint64_t{0} : (uint64_t{1} << bits) - 1;
    for (uint64_t key : keys)
      for (size_t s = 0; s < k; ++s) out.push_back(static_cast<watch::ModuleId>((key >> (bits * (k - 1 - s))) & mask));
    return out;
  }
  for (size_t i : group_order(ids, k)) out.insert(out.end(), ids.begin() + i * k, ids.begin() + (i + 1) * k);
  return out;
}

// The groups of k ids in `ids` in sorted order, as their indices.
std::vector<size_t> MatchLog::group_order(std::span<const watch::ModuleId> ids, size_t k) {
  std::vector<size_t> order(k == 0 ? 0 : ids.size() / k);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return std::lexicographical_compare(ids.begin() + a * k, ids.begin() + (a + 1) * k, ids.begin() + b * k,
                                        ids.begin() + (b + 1) * k);
  });
  return order;
}

MatchLog::WatchInfo MatchLog::info(const watch::Watchpoint& w) {
  WatchInfo info{w.name, w.program.slot_names};
  for (const watch::ActionCode& a : w.program.actions) info.actions.push_back({a.slot, a.variable});
  return info;
}

nlohmann::ordered_json MatchLog::then_json(const WatchInfo& w, std::span<const watch::ModuleId> ids,
                                           std::span<const watch::Value> values) {
  nlohmann::ordered_json then = nlohmann::ordered_json::array();
  for (size_t j = 0; j < w.actions.size(); ++j) {
    const auto& [slot, variable] = w.actions[j];
    const std::string& name = w.slots[static_cast<size_t>(slot)];
    nlohmann::ordered_json act;
    if (variable.empty()) {
      act["remove"] = name;
      act["module"] = ids[static_cast<size_t>(slot)];
    } else {
      act["set"] = name + "." + variable;
      act["module"] = ids[static_cast<size_t>(slot)];
      act["value"] = values[j].known ? nlohmann::ordered_json(values[j].value) : nlohmann::ordered_json(nullptr);
    }
    then.push_back(std::move(act));
  }
  return then;
}

watch::MatchSink MatchLog::sink(size_t index) {
  return [this, index](int64_t t, std::span<const watch::ModuleId> ids, std::span<const watch::Value> actions) {
    Watch& w = watches_[index];
    const size_t k = w.info.slots.size();
    const size_t n = watch::match_rows(ids.size(), k);
    w.count += n;
    if (out_ == nullptr && w.kept.size() >= keep_) return;
    Batch batch{t, index, n, {}, {}};
    if (const size_t a = w.info.actions.size(); a > 0 && actions.size() == n * a) {
      for (size_t i : group_order(ids, k)) {
        batch.ids.insert(batch.ids.end(), ids.begin() + i * k, ids.begin() + (i + 1) * k);
        batch.actions.insert(batch.actions.end(), actions.begin() + i * a, actions.begin() + (i + 1) * a);
      }
    } else {
      batch.ids = sorted_groups(ids, k);
    }
    for (size_t i = 0; i < n && w.kept.size() < keep_; ++i)
      w.kept.push_back({t, std::vector<watch::ModuleId>(batch.ids.begin() + i * k, batch.ids.begin() + (i + 1) * k)});
    if (out_ == nullptr) return;
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
  // The step's number is the same on every line; the lines go out in blocks of about 1 MiB.
  char number[24];
  const std::string step(number, std::to_chars(number, number + sizeof number, b.t).ptr);
  std::string block;
  block.reserve(1 << 20);
  for (size_t row = 0, i = 0; row < b.rows; ++row, i += k) {
    block += w.prefix;
    block += step;
    block += ",\"slots\":{";
    for (size_t s = 0; s < k; ++s) {
      if (s) block += ',';
      block += w.slot_keys[s];
      block.append(number, std::to_chars(number, number + sizeof number, b.ids[i + s]).ptr);
    }
    block += '}';
    if (!b.actions.empty()) {
      const size_t a = w.info.actions.size();
      block += ",\"then\":";
      block += then_json(w.info, {b.ids.data() + i, k}, {b.actions.data() + row * a, a})
                   .dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    }
    block += "}\n";
    if (block.size() >= (1 << 20) - 256) {
      out_->write(block.data(), static_cast<std::streamsize>(block.size()));
      block.clear();
    }
  }
  out_->write(block.data(), static_cast<std::streamsize>(block.size()));
}

void MatchLog::write_counted(std::string_view watch, uint64_t matches) {
  if (out_)
    *out_ << nlohmann::ordered_json{{"watch", watch}, {"counted", matches}}.dump(
                 -1, ' ', false, nlohmann::json::error_handler_t::replace)
          << "\n";
}

}  // namespace dw::sim
