// `dwatch check TEXT|@FILE...`: diagnostics, or what the watchpoint means to the detectors.
#include <iostream>

#include "app/cli/commands.h"
#include "app/cli/watch_args.h"
#include "watch/explain.h"

namespace dw::app {

void add_check_command(CLI::App& app, std::function<int()>& run) {
  auto* cmd = app.add_subcommand("check", "Parse watchpoints and explain them: slots, offsets, spans, E+");
  auto watches = std::make_shared<std::vector<std::string>>();
  cmd->add_option("watch", *watches, "Watchpoint text, @FILE, NAME=TEXT or NAME=@FILE")->required();
  cmd->callback([&run, watches] {
    run = [watches] {
      auto loaded = load_watchpoints(*watches);
      if (auto* errors = std::get_if<std::string>(&loaded)) {
        std::cerr << *errors;
        return 2;
      }
      for (const sim::HostedWatchpoint& h : std::get<std::vector<sim::HostedWatchpoint>>(loaded))
        watch::explain_watchpoint(h.watchpoint, std::cout);
      return 0;
    };
  });
}

}  // namespace dw::app
