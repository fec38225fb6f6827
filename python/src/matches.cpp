#include "python/src/matches.h"

#include "sim/match_log.h"
#include "watch/detector.h"

namespace dw::python {

void Matches::Builder::add(int64_t detected_at, int64_t step, std::span<const watch::ModuleId> ids, size_t slot_count) {
  const size_t groups = watch::match_rows(ids.size(), slot_count);  // a zero-slot row holds no id
  count += groups;
  if (!keep) return;
  t.append(groups, step);
  detected.append(groups, detected_at);
  // In the match log's order.
  slots.append(
      std::span<const watch::ModuleId>(sim::MatchLog::sorted_groups(ids.first(groups * slot_count), slot_count)));
}

Matches Matches::make(std::string watch, std::vector<std::string> slot_names, Builder&& built) {
  const auto n = static_cast<py::ssize_t>(built.t.size());
  const auto k = static_cast<py::ssize_t>(slot_names.size());
  return {std::move(watch),
          std::move(slot_names),
          std::move(built.t).to_numpy({n}),
          std::move(built.detected).to_numpy({n}),
          std::move(built.slots).to_numpy({n, k}),
          built.count};
}

void add_matches(py::module_& m) {
  py::class_<Matches>(m, "Matches",
                      "The matches of one watchpoint, in the match log's order (by t, then by the slots' module "
                      "ids): t[i] is match i's watch step, detected[i] the step during which it was found (t plus "
                      "the detector's lag), slots[i] the module filling each slot (slot_names). All int64. count: "
                      "every match, also when they were only counted (the arrays then empty).")
      .def_readonly("watch", &Matches::watch, "The watchpoint's name.")
      .def_readonly("slot_names", &Matches::slot_names, "The slots, in the order of the columns of slots.")
      .def_readonly("t", &Matches::t, "Watch step of each match: int64, shape (n,).")
      .def_readonly("detected", &Matches::detected, "Step during which each match was found: int64, shape (n,).")
      .def_readonly("slots", &Matches::slots, "Module id filling each slot: int64, shape (n, len(slot_names)).")
      .def_readonly("count", &Matches::count, "How many matches there are, kept or only counted.")
      .def(
          "records",
          [](const Matches& self) {
            // Fields t, detected and one per slot (named as the slot; slot_NAME if it is t or detected).
            py::list columns, names;
            columns.append(self.t), names.append("t");
            columns.append(self.detected), names.append("detected");
            for (size_t k = 0; k < self.slot_names.size(); ++k) {
              const std::string& slot = self.slot_names[k];
              columns.append(self.slots.attr("__getitem__")(
                  py::make_tuple(py::slice(py::none(), py::none(), py::none()), static_cast<py::ssize_t>(k))));
              names.append(slot == "t" || slot == "detected" ? "slot_" + slot : slot);
            }
            return py::module_::import("numpy").attr("rec").attr("fromarrays")(columns, py::arg("names") = names);
          },
          "The matches as a numpy structured array (a record array): fields t, detected and one per slot.")
      .def(
          "to_pandas",
          [](const Matches& self) {
            return py::module_::import("pandas").attr("DataFrame")(py::cast(self).attr("records")());
          },
          "The matches as a pandas DataFrame (columns t, detected and the slots); needs pandas (python3-pandas).")
      .def("__len__", [](const Matches& self) { return self.t.size(); })
      .def("__repr__", [](const Matches& self) {
        return "<dwatch.Matches of '" + self.watch + "': " + std::to_string(self.count) + " matches" +
               (self.count != static_cast<uint64_t>(self.t.size()) ? ", counted only>" : ">");
      });
}

}  // namespace dw::python
