#include "python/src/matches.h"

#include <algorithm>
#include <numeric>

namespace dw::python {

void Matches::Builder::add(int64_t detected_at, int64_t step, std::span<const watch::ModuleId> ids, size_t slot_count) {
  // The groups of one watch step in the match log's order: by slot ids, in slot order.
  const size_t groups = slot_count ? ids.size() / slot_count : 0;
  std::vector<size_t> order(groups);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return std::lexicographical_compare(ids.begin() + a * slot_count, ids.begin() + (a + 1) * slot_count,
                                        ids.begin() + b * slot_count, ids.begin() + (b + 1) * slot_count);
  });
  for (size_t g : order) {
    t.push_back(step);
    detected.push_back(detected_at);
    for (size_t s = 0; s < slot_count; ++s) slots.push_back(ids[g * slot_count + s]);
  }
}

Matches Matches::make(std::string watch, std::vector<std::string> slot_names, const Builder& built) {
  const auto n = static_cast<py::ssize_t>(built.t.size());
  const auto k = static_cast<py::ssize_t>(slot_names.size());
  Matches out{std::move(watch), std::move(slot_names), py::array_t<int64_t>(n), py::array_t<int64_t>(n),
              py::array_t<int64_t>({n, k})};
  std::copy(built.t.begin(), built.t.end(), out.t.mutable_data());
  std::copy(built.detected.begin(), built.detected.end(), out.detected.mutable_data());
  std::copy(built.slots.begin(), built.slots.end(), out.slots.mutable_data());
  for (auto* a : {&out.t, &out.detected, &out.slots}) a->attr("flags").attr("writeable") = false;
  return out;
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
