#include "shell/detector_flags.h"

#include "shell/integer_option.h"
#include "watch/ast.h"

namespace dw::shell {

sim::WatchSpec DetectorFlags::reading() const {
  sim::WatchSpec r;  // the flags' names were checked as they were read (add_detector_flags)
  sim::read_word(r, algorithm_name, sim::WatchWord::Algorithm);
  if (!shape_name.empty()) sim::read_word(r, shape_name, sim::WatchWord::Shape);
  if (!states_name.empty()) sim::read_word(r, states_name, sim::WatchWord::States);
  r.options.live_budget = max_live;
  r.options.optimizations = {.early_termination = !no_early_termination,
                             .neighbor_culling = !no_neighbor_culling,
                             .temporal_spans = !no_temporal_spans};
  return r;
}

void add_detector_flags(CLI::App& cmd, DetectorFlags& flags, bool with_algorithm) {
  if (with_algorithm) {
    cmd.add_option("--algorithm,-a", flags.algorithm_name, "centralized (Alg. 1) or distributed (Alg. 2)")
        ->check(CLI::IsMember({"centralized", "distributed"}))
        ->capture_default_str();
  }
  cmd.add_option("--shape", flags.shape_name,
                 "Groups to find: chain, ordered or any (default: ordered centralized, chain distributed)")
      ->check(CLI::IsMember({"chain", "ordered", "any"}));
  cmd.add_option("--states", flags.states_name,
                 "Distributed: consistent (the paper's) or simultaneous (exact, any shape; docs/design.md §4a)")
      ->check(CLI::IsMember({"consistent", "simultaneous"}));
  cmd.add_flag("--no-early-termination", flags.no_early_termination, "Keep PatternMatchers that can no longer match");
  cmd.add_flag("--no-neighbor-culling", flags.no_neighbor_culling,
               "Spread to every neighbour regardless of neighbor()");
  cmd.add_flag("--no-temporal-spans", flags.no_temporal_spans, "Keep all history instead of each variable's span");
  add_integer_option(cmd, "--max-live", flags.max_live, scenarios::kMaxLiveRange,
                     "Budget: most PatternMatchers alive in one step; past it the run stops (exit 1). 0: none")
      ->default_val(flags.max_live);
}

}  // namespace dw::shell
