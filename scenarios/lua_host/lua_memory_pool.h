// The memory all the Lua states of a run may hold together, and the time their calls may take. Each state has its own
// cap (LuaLimits::memory_bytes), but a run has one state per script per stepping thread: ten scripts on four threads,
// each near its cap, took over a gigabyte the scenario's memory estimate never counted. The pool is half of what the
// machine had available beyond that estimate when the scenario was loaded (the other half is for a step's messages); a
// state takes from it in granules, so that the shared counter is touched once a granule, not once an allocation.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>

namespace dw::scenarios {

class LuaMemoryPool {
 public:
  static constexpr size_t kGranule = size_t{1} << 20;  // what a state takes or gives back at once

  explicit LuaMemoryPool(size_t limit = SIZE_MAX) : limit_(limit) {}
  LuaMemoryPool(const LuaMemoryPool&) = delete;
  LuaMemoryPool& operator=(const LuaMemoryPool&) = delete;

  // Set once the scenario's estimate is known (its programs are loaded before it is).
  void set_limit(size_t bytes) { limit_.store(bytes, std::memory_order_relaxed); }
  size_t limit() const { return limit_.load(std::memory_order_relaxed); }
  size_t used() const { return used_.load(std::memory_order_relaxed); }

  // Takes `bytes` when they fit under the limit (or always, with `force`: dwatch's own work in a
  // state between calls, which must not fail). Whether they fit.
  bool take(size_t bytes, bool force = false) {
    size_t now = used_.load(std::memory_order_relaxed);
    do {
      if (!force && (bytes > limit() || now > limit() - bytes)) return false;
    } while (!used_.compare_exchange_weak(now, now + bytes, std::memory_order_relaxed));
    return true;
  }
  void give_back(size_t bytes) { used_.fetch_sub(bytes, std::memory_order_relaxed); }

  // The wall-clock time all the run's Lua calls may take together, besides each call's own
  // deadline (LuaLimits::deadline): a script taking 9 s a call on every module would otherwise run
  // for ever. 0: no limit.
  static constexpr int64_t kDefaultSeconds = 3600;
  void set_seconds(int64_t seconds) { limit_ns_.store(seconds * 1'000'000'000, std::memory_order_relaxed); }
  int64_t seconds() const { return limit_ns_.load(std::memory_order_relaxed) / 1'000'000'000; }
  // Adds a call's `ns`: whether the run's Lua time is still within its limit.
  bool spend(int64_t ns) {
    const int64_t limit = limit_ns_.load(std::memory_order_relaxed);
    return spent_ns_.fetch_add(ns, std::memory_order_relaxed) + ns <= limit || limit == 0;
  }

 private:
  std::atomic<int64_t> limit_ns_{kDefaultSeconds * 1'000'000'000};
  std::atomic<int64_t> spent_ns_{0};
  std::atomic<size_t> limit_;
  std::atomic<size_t> used_{0};
};

}  // namespace dw::scenarios
