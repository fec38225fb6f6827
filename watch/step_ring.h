// Keeps the items of the most recent `depth` steps, or of every step when depth is 0. This is
// how the detectors bound history to what the watchpoint's temporal spans need (paper §IV-A).
// Storage is rounded up to a power of two so that finding a step is a mask, not a division; only
// the last `depth` steps are ever readable.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace dw::watch {

template <class T, class Storage = std::vector<T>>
class StepRing {
 public:
  void configure(int64_t depth) {
    depth_ = depth;
    size_t capacity = 0;
    if (depth > 0) {
      capacity = 1;
      while (capacity < static_cast<size_t>(depth)) capacity *= 2;
    }
    mask_ = capacity - 1;
    items_.assign(capacity, T{});
    newest_ = -1;
  }

  // The item for `step`, to be overwritten. Steps are written in increasing order.
  T& write(int64_t step) {
    newest_ = step;
    if (depth_ > 0) return items_[static_cast<size_t>(step) & mask_];
    if (items_.size() <= static_cast<size_t>(step)) items_.resize(static_cast<size_t>(step) + 1);
    return items_[static_cast<size_t>(step)];
  }

  // The item of `step`, or nullptr when the step is before 0, not written yet, or forgotten.
  const T* find(int64_t step) const {
    if (step < 0 || step > newest_) return nullptr;
    if (depth_ > 0) return step <= newest_ - depth_ ? nullptr : &items_[static_cast<size_t>(step) & mask_];
    return &items_[static_cast<size_t>(step)];
  }
  T* find(int64_t step) { return const_cast<T*>(std::as_const(*this).find(step)); }

  // The items' storage (not what they point to).
  size_t capacity() const { return items_.capacity(); }
  const Storage& items() const { return items_; }

  // How many steps' items are held now.
  int64_t held() const {
    if (newest_ < 0) return 0;
    return depth_ > 0 ? (newest_ + 1 < depth_ ? newest_ + 1 : depth_) : newest_ + 1;
  }

 private:
  Storage items_;
  int64_t depth_ = 0;
  size_t mask_ = 0;
  int64_t newest_ = -1;
};

}  // namespace dw::watch
