// A zero-slot watchpoint's matches (docs/design.md §4c) in the window, without a window: a row with
// no module in the matches table ("(no module)"), a click on it seeks to its step and selects no
// module, and the view lights none.
#include <gtest/gtest.h>

#include "app/view/readout.h"
#include "app/view/view_model.h"
#include "scenarios/scenario.h"
#include "shell/view_image.h"

namespace dw::view {
namespace {

TEST(ZeroSlot, TheMatchesTableListsRowsWithNoModuleAndAClickSelectsNone) {
  auto loaded = scenarios::load_scenario(std::string(DWATCH_SCENARIOS_DIR) + "/one_token_ring.toml");
  ASSERT_TRUE(std::holds_alternative<scenarios::Scenario>(loaded)) << std::get<std::string>(loaded);
  scenarios::Scenario& scenario = std::get<scenarios::Scenario>(loaded);
  sim::Session session(*scenario.model, *scenario.world, {1, scenario.steps});
  session.run_until(scenario.steps);
  const MatchRows all = filter_matches(session, {}, 1'000'000);
  EXPECT_EQ(all.total, 19u);  // steps 21 to 39
  MatchFilter holding;
  holding.module = 3;
  EXPECT_EQ(filter_matches(session, holding, 1'000'000).total, 0u);  // no row holds a module
  ViewModel view;
  const std::vector<std::string> sent = view.on_match_click(session, all.rows.front());
  EXPECT_EQ(sent, std::vector<std::string>{command::seek(21)});
  EXPECT_FALSE(view.selected);
  EXPECT_FALSE(view.reveal_group);
  const Readout readout = read_readout(session, scenario, view, {});
  ASSERT_EQ(readout.match_rows.size(), 19u);
  EXPECT_EQ(readout.match_rows.front().slots, "(no module)");
  EXPECT_TRUE(shell::groups_at(session, 21, shell::Highlight::All).empty());  // nothing to light
}

}  // namespace
}  // namespace dw::view
