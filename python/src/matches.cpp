#include "python/src/matches.h"

#include <algorithm>
#include <numeric>

namespace dw::python {

void Matches::Builder::add(int64_t detected_at, int64_t step, std::span<const watch::ModuleId> ids, size_t slot_count) {
  const size_t groups = slot_count ? ids.size() / slot_count : 0;
  const auto group = [&](size_t g) { return ids.subspan(g * slot_count, slot_count); };
  const auto before = [&](size_t a, size_t b) { return std::ranges::lexicographical_compare(group(a), group(b)); };
  t.append(groups, step);
  detected.append(groups, detected_at);
  // The groups of one watch step in the match log's order: by slot ids, in slot order. Detectors
  // mostly give them so already; checked first, sorted only when not.
  bool sorted = true;
  for (size_t g = 1; g < groups && sorted; ++g) sorted = !before(g, g - 1);
  if (sorted) {
    slots.append(ids.first(groups * slot_count));
    return;
  }
  std::vector<size_t> order(groups);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), before);
  for (size_t g : order) slots.append(group(g));
}

Matches Matches::make(std::string watch, std::vector<std::string> slot_names, Builder&& built) {
  const auto n = static_cast<py::ssize_t>(built.t.size());
  const auto k = static_cast<py::ssize_t>(slot_names.size());
  return {std::move(watch), std::move(slot_names), std::move(built.t).to_numpy({n}),
          std::move(built.detected).to_numpy({n}), std::move(built.slots).to_numpy({n, k})};
}

void add_matches(py::module_& m) {
  py::class_<Matches>(m, "Matches",
                      "The matches of one watchpoint, in the match log's order (by t, then by the slots' module "
                      "ids): t[i] is match i's watch step, detected[i] the step during which it was found (t plus "
                      "the detector's lag), slots[i] the module filling each slot (slot_names). All int64.")
      .def_readonly("watch", &Matches::watch, "The watchpoint's name.")
      .def_readonly("slot_names", &Matches::slot_names, "The slots, in the order of the columns of slots.")
      .def_readonly("t", &Matches::t, "Watch step of each match: int64, shape (n,).")
      .def_readonly("detected", &Matches::detected, "Step during which each match was found: int64, shape (n,).")
      .def_readonly("slots", &Matches::slots, "Module id filling each slot: int64, shape (n, len(slot_names)).")
      .def("__len__", [](const Matches& self) { return self.t.size(); })
      .def("__repr__", [](const Matches& self) {
        return "<dwatch.Matches of '" + self.watch + "': " + std::to_string(self.t.size()) + " matches>";
      });
}

}  // namespace dw::python
