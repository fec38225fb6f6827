// Sorted vectors of many bonds or cluster members changed by a few thousand entries a step:
// merged and thinned in place, from the back and in one pass, with no buffer the size of the
// whole (std::inplace_merge and std::set_difference into a copy fault in fresh pages each step).
#pragma once

#include <algorithm>
#include <span>
#include <vector>

namespace dw::sim {

// Adds `more` (sorted, none already in `into`) to `into` (sorted).
template <typename T>
void merge_into(std::vector<T>& into, std::span<const T> more) {
  size_t i = into.size(), j = more.size(), k = i + j;
  into.resize(k);
  while (j > 0) into[--k] = (i > 0 && more[j - 1] < into[i - 1]) ? into[--i] : more[--j];
}

// Removes from `from` (sorted) the entries of `gone` (sorted).
template <typename T>
void erase_from(std::vector<T>& from, std::span<const T> gone) {
  if (gone.empty()) return;
  // Nothing moves before the first entry gone.
  auto kept = std::lower_bound(from.begin(), from.end(), gone.front());
  auto next = gone.begin();
  for (auto x = kept; x != from.end(); ++x) {
    while (next != gone.end() && *next < *x) ++next;
    if (next == gone.end() || !(*next == *x)) *kept++ = *x;
  }
  from.erase(kept, from.end());
}

}  // namespace dw::sim
