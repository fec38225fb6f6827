// Two steps compared (sim/step_diff.h): the first step's values, presence and neighbour graph
// copied, then the second's read against them, each module once.
#include "sim/step_diff.h"

#include <algorithm>
#include <memory>

#include "sim/session.h"

namespace dw::sim {

std::optional<StepDiff> diff_steps(Session& session, int64_t a, int64_t b, size_t most, const Control& control) {
  const int64_t back = session.current();
  if (!session.seek(a, control)) return std::nullopt;
  const std::vector<int64_t> values_a = session.state().values;
  const std::span<const uint8_t> seen_a = session.seen_present();
  const std::vector<uint8_t> present_a(seen_a.begin(), seen_a.end());
  const NeighborGraph graph_a = session.seen_graph();
  if (!session.seek(b, control)) {
    session.seek(back);
    return std::nullopt;
  }
  const std::vector<int64_t>& values_b = session.state().values;
  const std::span<const uint8_t> present_b = session.seen_present();
  const NeighborGraph& graph_b = session.seen_graph();
  const size_t v = session.model().variable_count();
  StepDiff diff{.a = a, .b = b};
  for (ModuleId m = 0; m < session.model().module_count(); ++m) {
    ModuleDiff d{.module = m, .present_a = present_a[m] != 0, .present_b = present_b[m] != 0};
    for (size_t c = 0; d.present_a && d.present_b && c < v; ++c) {  // an absent module's values are stale
      const size_t i = size_t{m} * v + c;
      if (values_a[i] != values_b[i]) d.values.push_back({int(c), values_a[i], values_b[i]});
    }
    // N(m) is sorted: the two sets' differences in one pass each.
    const auto na = graph_a.neighbors(m), nb = graph_b.neighbors(m);
    std::set_difference(nb.begin(), nb.end(), na.begin(), na.end(), std::back_inserter(d.gained));
    std::set_difference(na.begin(), na.end(), nb.begin(), nb.end(), std::back_inserter(d.lost));
    if (d.present_a == d.present_b && d.values.empty() && d.gained.empty() && d.lost.empty()) continue;
    ++diff.total;
    if (diff.modules.size() < most) diff.modules.push_back(std::move(d));
  }
  session.seek(back);
  return diff;
}

}  // namespace dw::sim
