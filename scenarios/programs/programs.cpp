#include "scenarios/programs/programs.h"

namespace dw::scenarios {
namespace {

constexpr ProgramInfo kPrograms[] = {
    {"random_vars", "the paper's benchmark host: x1..xk drawn uniformly from 0..max_i-1 every step", make_random_vars},
    {"leader_election", "2-hop leader election: no two leaders within two hops (paper Fig. 2)", make_leader_election},
    {"token_ring", "token passing around a ring, with a master that regenerates a lost token (paper Fig. 3)",
     make_token_ring},
    {"aggregation_routing", "data aggregation over a spanning tree plus landmark routing (paper §V-B)",
     make_aggregation_routing},
    {"body_sense", "what a module feels of its body: neighbour count, moving, speed, height (physics)",
     make_body_sense},
    {"slide", "modules sliding along the top of a row by lattice moves, like a train (paper §I; physics)", make_slide},
    {"surface_flow", "holes flowing through the top layer of a block by lattice moves along +x and +y (physics)",
     make_surface_flow},
};

}  // namespace

std::span<const ProgramInfo> builtin_programs() { return kPrograms; }

const ProgramInfo* find_program(std::string_view name) {
  for (const ProgramInfo& p : kPrograms)
    if (p.name == name) return &p;
  return nullptr;
}

}  // namespace dw::scenarios
