// 2-hop leader election (the paper's Fig. 2 setting): leaders end up at least three hops apart,
// i.e. no two leaders within two hops of each other, and every module within two hops of one.
//
// Each module draws a unique priority at step 0. Every step it broadcasts its status, its
// priority, the best priority among the undecided modules it knows within one hop (itself
// included), and whether a leader is within one hop. From its neighbours' messages a module thus
// sees its 2-hop neighbourhood one step late. An undecided module that hears of a leader within
// two hops becomes a follower; one whose priority beats every undecided module within two hops
// (from step 2 on, when that knowledge has arrived) becomes a leader. Because a module's view is
// at most two steps old and statuses only ever leave `undecided`, two modules within two hops
// can never both be elected (the argument is in tests/scenarios/leader_election_test.cpp).
//
// `bug = true` compares only 1-hop neighbours and only listens to 1-hop leaders — the classic
// mistake that produces the paper's Fig. 2 violation: two leaders two hops apart.
#include <algorithm>

#include "scenarios/programs/programs.h"

namespace dw::scenarios {
namespace {

enum Status : int64_t { kUndecided = 0, kLeader = 1, kFollower = 2 };
enum Var : uint32_t { kIsLeader, kStatus, kPriority };
// Message words.
enum Word : uint32_t { kWStatus, kWPriority, kWBest1, kWLeader1 };

class LeaderElection final : public sim::HostProgram {
 public:
  explicit LeaderElection(bool bug) : bug_(bug) {}
  std::string_view name() const override { return "leader_election"; }
  std::vector<sim::VariableSpec> variables() const override {
    return {{"isLeader", 0}, {"_status", kUndecided}, {"_priority", 0}};
  }

  void step(sim::ModuleContext& m) const override {
    int64_t priority = m.get(kPriority);
    if (m.step() == 0) {
      // Unique: random high bits, the module id in the low 24.
      priority = static_cast<int64_t>((m.random(0) >> 25) << 24) | (m.id() & 0xFFFFFF);
      m.set(kPriority, priority);
    }
    int64_t status = m.get(kStatus);

    // The neighbourhood as the inbox tells it (the neighbours' state at t - 1).
    bool leader_1hop = false, leader_2hop = false;
    int64_t best_neighbor = -1;  // the best priority of an undecided neighbour
    int64_t best_2hop = -1;      // the best the neighbours know of within one hop of them
    for (const sim::Message& msg : m.inbox()) {
      if (msg[kWStatus] == kLeader) leader_1hop = true;
      if (msg[kWStatus] == kUndecided) best_neighbor = std::max(best_neighbor, msg[kWPriority]);
      leader_2hop |= msg[kWLeader1] != 0;
      best_2hop = std::max(best_2hop, msg[kWBest1]);
    }

    if (status == kUndecided) {
      const bool covered = bug_ ? leader_1hop : leader_1hop || leader_2hop;
      const int64_t rival = bug_ ? best_neighbor : std::max(best_neighbor, best_2hop);
      const int64_t ready = bug_ ? 1 : 2;  // the step from which the compared priorities have arrived
      if (covered) status = kFollower;
      else if (m.step() >= ready && priority >= rival) status = kLeader;  // rival may be us, relayed back
    }
    m.set(kStatus, status);
    m.set(kIsLeader, status == kLeader);
    // What the neighbours learn: the new status, the best undecided priority within one hop, and
    // whether a leader is within one hop.
    const int64_t best_1hop = std::max(status == kUndecided ? priority : -1, best_neighbor);
    m.broadcast({status, priority, best_1hop, leader_1hop || status == kLeader});
  }

 private:
  bool bug_;
};

}  // namespace

std::unique_ptr<const sim::HostProgram> make_leader_election(TableReader& params, const ProgramSetup&) {
  return std::make_unique<LeaderElection>(params.boolean("bug").value_or(false));
}

}  // namespace dw::scenarios
