// A scenario too large for the memory it may use is refused before anything is allocated, at its
// lattice's size, with the estimate and the limit in the message (scenarios/memory_estimate.h).
#include "scenarios/memory_estimate.h"

#include <gtest/gtest.h>

#include "scenarios/scenario.h"

namespace dw::scenarios {
namespace {

std::string cube(int side, bool physics) {
  return "steps = 2\n[lattice]\nkind = \"cubic\"\nsize = [" + std::to_string(side) + ", " + std::to_string(side) +
         ", " + std::to_string(side) + "]\n[[program]]\nname = \"leader_election\"\n" +
         (physics ? "[physics]\nenabled = true\n" : "");
}

TEST(MemoryEstimate, GrowsWithModulesPhysicsAndHistory) {
  EXPECT_LT(memory_estimate(1000, false, 256), memory_estimate(2000, false, 256));
  EXPECT_LT(memory_estimate(1000, false, 256), memory_estimate(1000, true, 256));
  EXPECT_LT(memory_estimate(1000, false, 16), memory_estimate(1000, false, 256));
  // 10^8 modules without physics: well over 100 GiB, which no 24 GiB machine holds.
  EXPECT_GT(memory_estimate(100'000'000, false, 256), uint64_t{100} << 30);
}

TEST(MemoryEstimate, AScenarioAboveTheLimitIsRefusedAtItsSize) {
  ScenarioOverrides limited;
  limited.memory_limit = uint64_t{512} << 20;  // 512 MiB
  // 45^3 = 91,125 modules and 256 MiB of history: about 460 MiB without physics, 550 with it.
  EXPECT_TRUE(std::holds_alternative<Scenario>(load_scenario_text("small.toml", cube(45, false), limited)));
  const auto refused = load_scenario_text("big.toml", cube(45, true), limited);
  ASSERT_TRUE(std::holds_alternative<std::string>(refused));
  const std::string& message = std::get<std::string>(refused);
  EXPECT_EQ(message.rfind("big.toml:4:8: error: that is 91125 modules, which need about ", 0), 0u) << message;
  EXPECT_NE(message.find("physics included"), std::string::npos) << message;
  EXPECT_NE(message.find("this machine has 512 MiB available (--no-memory-check tries anyway)"), std::string::npos)
      << message;
  // No limit: loaded as asked.
  EXPECT_TRUE(std::holds_alternative<Scenario>(load_scenario_text("big.toml", cube(12, true))));
}

// The programs' variables count too, once they are known: 16 variables a module on 91,125
// modules add 35 MiB, over the limit that the lattice alone stays under.
TEST(MemoryEstimate, AScenarioWhoseVariablesDoNotFitIsRefusedAtItsPrograms) {
  EXPECT_EQ(memory_estimate(1000, false, 256, 3000) - memory_estimate(1000, false, 256), 1000u * 3000u * 24u);
  const std::string many =
      "steps = 2\n[lattice]\nkind = \"cubic\"\nsize = [45, 45, 45]\n[[program]]\n"
      "name = \"random_vars\"\ntuple = [2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2]\n";
  ScenarioOverrides limited;
  limited.memory_limit = memory_estimate(45 * 45 * 45, false, 256) + (uint64_t{20} << 20);
  const auto refused = load_scenario_text("vars.toml", many, limited);
  ASSERT_TRUE(std::holds_alternative<std::string>(refused));
  const std::string& message = std::get<std::string>(refused);
  EXPECT_EQ(message.rfind("vars.toml:5:1: error: that is 91125 modules, which need about ", 0), 0u) << message;
  EXPECT_NE(message.find("16 variables each"), std::string::npos) << message;
  limited.memory_limit += uint64_t{20} << 20;
  EXPECT_TRUE(std::holds_alternative<Scenario>(load_scenario_text("vars.toml", many, limited)));
}

TEST(MemoryEstimate, TheMachinesLimitIsKnownHere) {
  // /proc/meminfo is there on Linux: a limit of 0 would turn the check off without a word.
  EXPECT_GT(memory_limit(), uint64_t{16} << 20);
}

}  // namespace
}  // namespace dw::scenarios
