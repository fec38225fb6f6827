// The paper's medium-intensity workload (§V-B): data aggregation over a spanning tree, plus
// landmark routing. Every step each module broadcasts one message with its hop distance to the
// root, its parent, its subtree's sum and its hop distance to each landmark, and recomputes them
// from its neighbours' messages:
//   dist    = 0 at the root, else 1 + the smallest neighbour dist (the spanning tree's depth)
//   parent  = the neighbour with that smallest dist (ties: the smallest id)
//   sum     = own value + the sums of the neighbours whose parent it is (the subtree's total)
//   lm<i>   = 0 at landmark i, else 1 + the smallest neighbour lm<i> (a routing gradient)
// Unknown distances are -1. On a static graph it converges in about twice the diameter; after a
// change of topology it re-converges. Each module's value is 1, so the root's sum counts the
// modules.
#include <algorithm>

#include "scenarios/programs/programs.h"

namespace dw::scenarios {
namespace {

constexpr uint32_t kMaxLandmarks = sim::Message::kMaxWords - 3;
enum Var : uint32_t { kDist, kParent, kSum, kFirstLandmark };

class AggregationRouting final : public sim::HostProgram {
 public:
  AggregationRouting(sim::ModuleId root, std::vector<sim::ModuleId> landmarks)
      : root_(root), landmarks_(std::move(landmarks)) {}
  std::string_view name() const override { return "aggregation_routing"; }
  std::vector<sim::VariableSpec> variables() const override {
    std::vector<sim::VariableSpec> v{{"dist", -1}, {"parent", -1}, {"sum", 0}};
    for (size_t i = 0; i < landmarks_.size(); ++i) v.push_back({"lm" + std::to_string(i), -1});
    return v;
  }

  void step(sim::ModuleContext& m) const override {
    // Message words: dist, parent, sum, lm0, lm1, ...
    const auto inbox = m.inbox();
    auto closest = [&](uint32_t word) {
      int64_t best = -1;
      for (const sim::Message& msg : inbox)
        if (msg[word] >= 0 && (best < 0 || msg[word] < best)) best = msg[word];
      return best < 0 ? -1 : best + 1;
    };
    const bool is_root = m.id() == root_;
    int64_t dist = is_root ? 0 : closest(0);
    int64_t parent = -1;
    if (!is_root && dist >= 0)
      for (const sim::Message& msg : inbox)  // by sender id: the first is the smallest id
        if (msg[0] == dist - 1) {
          parent = msg.from;
          break;
        }
    int64_t sum = 1;
    for (const sim::Message& msg : inbox)
      if (msg[1] == m.id()) sum += msg[2];
    m.set(kDist, dist);
    m.set(kParent, parent);
    m.set(kSum, sum);
    std::array<int64_t, sim::Message::kMaxWords> words{dist, parent, sum};
    for (uint32_t i = 0; i < landmarks_.size(); ++i) {
      const int64_t lm = m.id() == landmarks_[i] ? 0 : closest(3 + i);
      m.set(kFirstLandmark + i, lm);
      words[3 + i] = lm;
    }
    m.broadcast(std::span<const int64_t>(words.data(), 3 + landmarks_.size()));
  }

 private:
  sim::ModuleId root_;
  std::vector<sim::ModuleId> landmarks_;
};

}  // namespace

std::unique_ptr<const sim::HostProgram> make_aggregation_routing(TableReader& params, const ProgramSetup& setup) {
  const int64_t last = int64_t{setup.module_count} - 1;
  const auto root = params.integer("root", 0, last);
  const auto count = params.integer("landmarks", 0, kMaxLandmarks);
  if ((params.has("root") && !root) || (params.has("landmarks") && !count)) return nullptr;
  if (!setup.occupied[static_cast<size_t>(root.value_or(0))]) {
    params.error(params.has("root") ? "root" : "name",
                 "the root, module " + std::to_string(root.value_or(0)) +
                     ", is in a cell left empty: give 'root' a module that is there");
    return nullptr;
  }
  // Landmarks spread evenly over the ids.
  std::vector<sim::ModuleId> landmarks;
  const int64_t n = count.value_or(3);
  for (int64_t i = 0; i < n; ++i)
    landmarks.push_back(static_cast<sim::ModuleId>((2 * i + 1) * int64_t{setup.module_count} / (2 * n)));
  return std::make_unique<AggregationRouting>(static_cast<sim::ModuleId>(root.value_or(0)), std::move(landmarks));
}

}  // namespace dw::scenarios
