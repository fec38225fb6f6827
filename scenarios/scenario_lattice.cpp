// A scenario's [lattice] (docs/design.md §5): its kind, its size, the boxes of cells left empty,
// and the refusal of a lattice too large for the limits before anything is allocated.
#include <algorithm>
#include <array>

#include "scenarios/memory_estimate.h"
#include "scenarios/scenario_loader.h"

namespace dw::scenarios {

// The lattice, once its size is known to fit: within `overrides.max_modules`, and (when a limit
// is given) its memory estimate within the limit, checked before anything is allocated.
std::optional<sim::Lattice> Loader::lattice(TableReader& root, const ScenarioOverrides& overrides, bool physics,
                                            uint64_t history_mb) {
  const uint64_t max_modules = overrides.max_modules;
  const toml::table* t = root.table("lattice");
  if (!t) {
    if (!root.has("lattice")) root.missing("lattice");
    return std::nullopt;
  }
  TableReader r(*t, diagnostics, "[lattice]");
  sim::LatticeSpec spec;
  bool ok = true;
  const auto kind_name = r.string("kind");
  std::optional<sim::LatticeKind> kind;
  if (kind_name) {
    kind = sim::lattice_from_name(*kind_name);
    if (!kind)
      r.error("kind",
              "unknown lattice kind \"" + *kind_name + "\" (cubic, square2d, hex2d, ring, line, fcc, hex2d_vertical)");
  } else if (!r.has("kind")) {
    r.missing("kind");
  }
  const auto size = r.integers("size", kSizeRange.min, kSizeRange.max, 1, 3);
  if (!size && !r.has("size")) r.missing("size");
  // Boxes of cells left empty: [[lattice.empty]] from = [x, y, z], to = [x, y, z] (inclusive).
  std::vector<std::array<std::vector<int64_t>, 2>> empty;
  for (const toml::table* box : r.tables("empty")) {
    TableReader e(*box, diagnostics, "[[lattice.empty]]");
    auto from = e.integers("from", 0, 1'000'000, 3, 3), to = e.integers("to", 0, 1'000'000, 3, 3);
    if (!from && !e.has("from")) e.missing("from");
    if (!to && !e.has("to")) e.missing("to");
    if (from && to)
      for (size_t i = 0; i < 3; ++i)
        if ((*from)[i] > (*to)[i]) {
          e.error("to",
                  "each coordinate of 'to' must be at least the one of 'from' (the box is from..to, inclusive), "
                  "not " +
                      std::to_string((*to)[i]) + " < " + std::to_string((*from)[i]));
          from.reset();
          break;
        }
    e.finish();
    if (from && to) empty.push_back({*from, *to});
    else ok = false;
  }
  r.finish();
  if (!kind || !size) return std::nullopt;
  spec.kind = *kind;
  const size_t dims = static_cast<size_t>(sim::lattice_dimensions(*kind));
  if (size->size() != dims) {
    r.error("size", "a " + std::string(sim::lattice_name(*kind)) + " lattice takes " + std::to_string(dims) + " size" +
                        (dims == 1 ? "" : "s") + ", not " + std::to_string(size->size()));
    return std::nullopt;
  }
  for (size_t i = 0; i < dims; ++i) spec.size[i] = static_cast<uint32_t>((*size)[i]);
  if (spec.module_count() > max_modules) {
    r.error("size",
            "that is " + std::to_string(spec.module_count()) + " modules; the most is " + std::to_string(max_modules));
    ok = false;
  } else if (overrides.memory_limit > 0 &&
             memory_estimate(spec.module_count(), physics, history_mb) > overrides.memory_limit) {
    r.error("size", memory_refusal(spec.module_count(), physics, history_mb, overrides.memory_limit));
    ok = false;
  }
  if (*kind == sim::LatticeKind::Ring && spec.size[0] < 3) {
    r.error("size", "a ring needs at least 3 modules");
    ok = false;
  }
  std::vector<sim::LatticeBox> boxes;
  for (size_t b = 0; b < empty.size(); ++b) {
    const auto& [from, to] = empty[b];
    boxes.push_back({{{uint32_t(from[0]), uint32_t(from[1]), uint32_t(from[2])},
                      {uint32_t(to[0]), uint32_t(to[1]), uint32_t(to[2])}}});
    for (size_t i = 0; i < 3; ++i)
      if (from[i] >= int64_t{spec.size[i]}) {
        r.error("empty", "box " + std::to_string(b + 1) + " (from [" + std::to_string(from[0]) + ", " +
                             std::to_string(from[1]) + ", " + std::to_string(from[2]) +
                             "]) lies outside the lattice, whose cells go up to [" + std::to_string(spec.size[0] - 1) +
                             ", " + std::to_string(spec.size[1] - 1) + ", " + std::to_string(spec.size[2] - 1) +
                             "]: it would empty nothing");
        ok = false;
        break;
      }
  }
  if (!ok) return std::nullopt;
  // A physical world's contacts make its graph (sim::Lattice::graph): none is made here.
  sim::Lattice l = sim::make_lattice(spec, !physics);
  sim::leave_empty(l, boxes);
  if (std::none_of(l.occupied.begin(), l.occupied.end(), [](uint8_t o) { return o != 0; })) {
    r.error("empty", "these boxes leave every cell of the lattice empty: there is no module to run");
    return std::nullopt;
  }
  return l;
}

}  // namespace dw::scenarios
