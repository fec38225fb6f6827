// A command of the session language (docs/design.md §7a) as parsed: which one, and its
// arguments, checked against the model (Shell::parse makes it, Shell::execute carries it out).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sim/intervention.h"
#include "sim/model.h"
#include "watch/watchpoint.h"

namespace dw::shell {

// find prev|next M VAR | find prev|next M... when TEXT; eval M... TEXT (sim/group_query.h). Outside
// Command: clang cannot default-construct a nested class with member initializers in an
// optional member of the class around it (std::optional::emplace() is then refused).
struct CommandQuery {
  bool back = false;                           // prev
  std::vector<sim::ModuleId> group;            // M...: the condition's slots, in order
  int column = -1;                             // find M VAR
  std::optional<watch::Watchpoint> condition;  // TEXT, its windows written out
};

struct Command {
  enum class Kind {
    Step,
    Run,
    Continue,
    Seek,
    Set,
    Remove,
    Push,
    Watch,
    Unwatch,
    Action,
    Matches,
    State,
    Hash,
    Render,
    Record,
    Save,
    Interventions,
    Reload,
    Status,
    Why,
    Find,
    Eval,
    Mark,
    Unmark,
    Marks,
    Diff,
    Help,
  };
  Kind kind = Kind::Help;
  uint32_t line = 0;              // in the script
  std::optional<int64_t> number;  // step N, run T, seek T, matches T, mark T, diff T1
  std::optional<int64_t> other;   // diff T1 T2: T2
  std::string name;  // watch/unwatch/action/matches NAME, run --to-match NAME, render/record/save FILE, mark's NOTE
  sim::MatchAction action = sim::MatchAction::Log;  // action NAME ACTION
  bool overwrite = false;                           // save FILE overwrite
  bool messages = false;                            // record FILE --messages
  int width = 1280, height = 720;                   // render
  std::optional<sim::Intervention> intervention;
  std::optional<sim::HostedWatchpoint> watch;
  // why M VAR [T] (M in `number`), why match W ROW | W T SLOTS (W in `name`): docs/design.md §7b.
  struct Why {
    bool match = false;
    int column = -1;             // VAR
    std::optional<int64_t> t;    // T (the current step when not given)
    std::optional<int64_t> row;  // ROW of `matches W`
    std::vector<int64_t> slots;  // SLOTS: the group's modules, in slot order
    int depth = 3;
    bool narrow = false;
  };
  std::optional<Why> why;
  using Query = CommandQuery;
  std::optional<Query> query;
};

// A command's line in the table of commands: its name, its arguments as `help` shows them, and
// what it does.
struct CommandSpec {
  const char* name;
  Command::Kind kind;
  const char* usage;
  const char* what;
};
// The command named `name`, or nullptr.
const CommandSpec* find_command(std::string_view name);
// The line of `kind`.
const CommandSpec& command_spec(Command::Kind kind);

// `word` as one word of a command line: in double quotes when it holds a space or a '#' (a file's
// name; one holding a double quote cannot be said).
std::string command_word(const std::string& word);

// The commands, one line each, as `help` answers them.
const std::vector<std::string>& command_help();

}  // namespace dw::shell
