// The contact graph's bookkeeping per module (physics/contact_graph.cpp): records kept for the
// modules it has seen, and lists of module ids that may be every id without holding them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "sim/neighbor_graph.h"
#include "sim/paged_array.h"

namespace dw::physics {

// Per-module records kept for some modules only (sim::PagedArray, with which are known): over
// ranks a rank remembers the poses of its window and the modules next to it, a few in ten of a
// large ensemble; in one process, every module's. A record equal to its default (a module at rest
// in its cell) takes no page.
template <typename T, typename Default>
class PagedRecords {
 public:
  PagedRecords() = default;
  explicit PagedRecords(const Default& defaults) : records_(defaults) {}
  const Default& defaults() const { return records_.defaults(); }
  size_t size() const { return known_.size(); }
  void resize(size_t n) {
    known_.resize(n, 0);
    records_.resize(n);
  }
  bool known(sim::ModuleId m) const { return known_[m] != 0; }
  const T operator[](sim::ModuleId m) const { return records_[m]; }
  void set(sim::ModuleId m, const T& value) {
    records_.set(m, value);
    known_[m] = 1;
  }

 private:
  std::vector<uint8_t> known_;
  sim::PagedArray<T, Default> records_;
};

// Module ids, ascending: a list, or every id below n without holding them (a full measurement
// looks at and flags every module: two lists of them took 8 MB a million, on every rank).
class Ids {
 public:
  void all(size_t n) {
    list_.clear();
    every_ = n;
  }
  std::vector<sim::ModuleId>& list() {
    every_.reset();
    return list_;
  }
  size_t size() const { return every_ ? *every_ : list_.size(); }
  bool empty() const { return size() == 0; }
  sim::ModuleId operator[](size_t i) const { return every_ ? static_cast<sim::ModuleId>(i) : list_[i]; }
  struct Iterator {
    const Ids* ids;
    size_t i;
    sim::ModuleId operator*() const { return (*ids)[i]; }
    Iterator& operator++() {
      ++i;
      return *this;
    }
    bool operator==(const Iterator&) const = default;
  };
  Iterator begin() const { return {this, 0}; }
  Iterator end() const { return {this, size()}; }

 private:
  std::optional<size_t> every_;
  std::vector<sim::ModuleId> list_;
};

}  // namespace dw::physics
