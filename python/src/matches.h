// dwatch.Matches: the matches of one watchpoint as numpy arrays, made by dwatch.replay and
// Session.matches alike.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "python/src/bindings.h"
#include "python/src/growing_array.h"
#include "watch/value.h"

namespace dw::python {

struct Matches {
  std::string watch;
  std::vector<std::string> slot_names;
  py::array_t<int64_t> t, detected, slots;  // n; n; n x slot count
  uint64_t count = 0;                       // every match, also those counted only

  // Collects matches as found; `make` turns them into the arrays, without a copy.
  struct Builder {
    bool keep = true;  // false: matches are counted, not kept
    uint64_t count = 0;
    GrowingArray t, detected, slots;
    void add(int64_t detected_at, int64_t step, std::span<const watch::ModuleId> ids, size_t slot_count);
  };
  static Matches make(std::string watch, std::vector<std::string> slot_names, Builder&& built);
};

void add_matches(py::module_& m);

}  // namespace dw::python
