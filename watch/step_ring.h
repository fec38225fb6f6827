// Keeps the items of the most recent `depth` steps, or of every step when depth is 0. This is
// how the detectors bound history to what the watchpoint's temporal spans need (paper §IV-A).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace dw::watch {

template <class T>
class StepRing {
 public:
  void configure(int64_t depth) {
    depth_ = depth;
    items_.assign(depth > 0 ? static_cast<size_t>(depth) : 0, T{});
    newest_ = -1;
  }

  // The item for `step`, to be overwritten. Steps are written in increasing order.
  T& write(int64_t step) {
    newest_ = step;
    if (depth_ > 0) return items_[static_cast<size_t>(step % depth_)];
    if (items_.size() <= static_cast<size_t>(step)) items_.resize(static_cast<size_t>(step) + 1);
    return items_[static_cast<size_t>(step)];
  }

  // The item of `step`, or nullptr when the step is before 0, not written yet, or forgotten.
  const T* find(int64_t step) const {
    if (step < 0 || step > newest_) return nullptr;
    if (depth_ > 0) return step <= newest_ - depth_ ? nullptr : &items_[static_cast<size_t>(step % depth_)];
    return &items_[static_cast<size_t>(step)];
  }

  // How many steps' items are held now.
  int64_t held() const {
    if (newest_ < 0) return 0;
    return depth_ > 0 ? (newest_ + 1 < depth_ ? newest_ + 1 : depth_) : newest_ + 1;
  }

 private:
  std::vector<T> items_;
  int64_t depth_ = 0;
  int64_t newest_ = -1;
};

}  // namespace dw::watch
