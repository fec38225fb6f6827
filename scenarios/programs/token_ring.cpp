// Token passing on a ring (the paper's Fig. 3 setting). The module holding the token at step t
// passes it to its successor (the neighbour with the next id around the ring), which holds it at
// t + 1: exactly one module holds it at every step. Module 0 is the master: if the token has not
// come back for more than `timeout` steps (default: the ring's size) it regenerates one; it makes
// the first token at step 0.
//
// Bugs, for the Fig. 3 watchpoint to find:
//   duplicate_at = S  the holder at step S keeps the token and passes a copy: at S + 1 the
//                     holder still has it although neither neighbour had it at S.
//   lose_at = S       the holder at step S drops the token; the master regenerates it when the
//                     timeout runs out, where again neither neighbour had it the step before.
#include <limits>

#include "scenarios/programs/programs.h"

namespace dw::scenarios {
namespace {

enum Var : uint32_t { kToken, kSince, kKeep };

class TokenRing final : public sim::HostProgram {
 public:
  TokenRing(int64_t timeout, int64_t duplicate_at, int64_t lose_at)
      : timeout_(timeout), duplicate_at_(duplicate_at), lose_at_(lose_at) {}
  std::string_view name() const override { return "token_ring"; }
  std::vector<sim::VariableSpec> variables() const override { return {{"token", 0}, {"_since", 0}, {"_keep", 0}}; }

  void step(sim::ModuleContext& m) const override {
    bool holds = !m.inbox().empty() || m.get(kKeep) != 0;
    if (m.id() == 0) {
      const int64_t since = holds ? 0 : m.get(kSince) + 1;
      if (since > timeout_ || m.step() == 0) holds = true;  // the token is lost, or not yet made: make one
      m.set(kSince, holds ? 0 : since);
    }
    m.set(kToken, holds);
    m.set(kKeep, 0);
    if (!holds || m.step() == lose_at_) return;
    if (m.neighbors().empty()) {  // cut off from the ring (a module that fell away): keep the token
      m.set(kKeep, 1);
      return;
    }
    m.send(successor(m), {1});
    if (m.step() == duplicate_at_) m.set(kKeep, 1);
  }

 private:
  // The neighbour with the smallest id above ours, or else the smallest id: around the ring.
  static sim::ModuleId successor(const sim::ModuleContext& m) {
    const auto n = m.neighbors();
    for (sim::ModuleId id : n)
      if (id > m.id()) return id;
    return n.front();
  }

  int64_t timeout_, duplicate_at_, lose_at_;
};

}  // namespace

std::unique_ptr<const sim::HostProgram> make_token_ring(TableReader& params, const ProgramSetup& setup) {
  const int64_t never = -1, big = std::numeric_limits<int32_t>::max();
  const auto timeout = params.integer("timeout", 1, big);
  const auto duplicate = params.integer("duplicate_at", 0, big);
  const auto lose = params.integer("lose_at", 0, big);
  if (params.has("timeout") && !timeout) return nullptr;
  if ((params.has("duplicate_at") && !duplicate) || (params.has("lose_at") && !lose)) return nullptr;
  if (setup.present_count() < 2) {
    params.error("name",
                 "token_ring passes a token to a neighbour: it needs at least 2 modules, and this lattice has " +
                     std::to_string(setup.present_count()));
    return nullptr;
  }
  return std::make_unique<TokenRing>(timeout.value_or(setup.module_count), duplicate.value_or(never),
                                     lose.value_or(never));
}

}  // namespace dw::scenarios
