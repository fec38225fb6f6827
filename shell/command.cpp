#include "shell/command.h"

#include <algorithm>
#include <cctype>

namespace dw::shell {
namespace {

using Kind = Command::Kind;

const CommandSpec kCommands[] = {
    {"step", Kind::Step, "step [N]", "run N steps (default 1); stops at a pause"},
    {"run", Kind::Run, "run [T] [--to-match NAME]",
     "run until a pause fires (or NAME's next match), step T, or the scenario's end"},
    {"continue", Kind::Continue, "continue",
     "run on past the pause that stopped the cursor: to the next one, or the end"},
    {"seek", Kind::Seek, "seek T", "make step T current (0 <= T <= latest); nothing is lost"},
    {"set", Kind::Set, "set M VAR VALUE", "intervention at the current step: a new branch"},
    {"remove", Kind::Remove, "remove M", "intervention: module M leaves the ensemble"},
    {"push", Kind::Push, "push M X Y Z", "intervention (physics): an impulse (N s) on M's body"},
    {"watch", Kind::Watch,
     "watch NAME [centralized|distributed] [chain|ordered|any] [consistent|simultaneous] [log|pause|count] TEXT",
     "add or replace a watchpoint (its shape and states as in docs/design.md section 3); answers its matches count "
     "over the history"},
    {"unwatch", Kind::Unwatch, "unwatch NAME", "remove a watchpoint"},
    {"action", Kind::Action, "action NAME log|pause|count",
     "what watchpoint NAME does with its matches from now on (nothing is evaluated again)"},
    {"matches", Kind::Matches, "matches [NAME] [T]", "the matches (as in the match log), of one watch / at step T"},
    {"state", Kind::State, "state M", "module M at the current step: variables, neighbours, pose"},
    {"hash", Kind::Hash, "hash",
     "the state hash at the current step, its simulation and watchpoints parts, and the run hash of the steps to it"},
    {"render", Kind::Render, "render FILE [W H]", "the 3D view of the current step (PNG)"},
    {"record", Kind::Record, "record FILE [--messages]",
     "the trace of steps 0..latest, its header listing the interventions; --messages: each line with what its "
     "module read (why)"},
    {"save", Kind::Save, "save FILE [overwrite]",
     "this session as a scenario file: its watchpoints, the branch's interventions, paths that work from FILE's "
     "folder; an existing FILE only with 'overwrite'"},
    {"interventions", Kind::Interventions, "interventions", "the interventions of this branch, with their steps"},
    {"reload", Kind::Reload, "reload",
     "load the scenario's Lua scripts again: the changed program runs from the next step, a new branch"},
    {"status", Kind::Status, "status", "where the session stands: steps, watchpoints, history"},
    {"why", Kind::Why, "why M VAR [T] [--depth D] [--narrow] | why match W ROW|T SLOTS... [--depth D] [--narrow]",
     "the causal history of a value, or of a match: the events, messages and neighbour changes that could have led "
     "to it, D steps deep (docs/design.md section 7b)"},
    {"find", Kind::Find, "find prev|next M VAR | find prev|next M... when TEXT",
     "go to the nearest step before or after this one where M's VAR changed, or where the condition TEXT "
     "(modules(a ...); ..., its slots filled by M... in order) holds"},
    {"eval", Kind::Eval, "eval M... TEXT",
     "the condition TEXT (modules(a ...); ...) on the modules M... (its slots, in order) at the current step: "
     "true, false or unknown"},
    {"mark", Kind::Mark, "mark T [NOTE]",
     "bookmark step T with a note (the rest of the line): on the window's timeline, saved with the scenario"},
    {"unmark", Kind::Unmark, "unmark T", "remove step T's bookmark"},
    {"marks", Kind::Marks, "marks", "the bookmarks, by step"},
    {"diff", Kind::Diff, "diff T1 T2",
     "what differs between steps T1 and T2: each module whose variables, presence or neighbours differ"},
    {"help", Kind::Help, "help", "these commands"},
};

}  // namespace

const CommandSpec* find_command(std::string_view name) {
  const CommandSpec* spec = nullptr;
  for (const CommandSpec& c : kCommands)
    if (name == c.name) spec = &c;
  return spec;
}

const CommandSpec& command_spec(Command::Kind kind) {
  for (const CommandSpec& c : kCommands)
    if (c.kind == kind) return c;
  return kCommands[std::size(kCommands) - 1];  // every kind has its line: never reached
}

std::string command_word(const std::string& word) {
  const bool plain = !word.empty() && word[0] != '"' && std::none_of(word.begin(), word.end(), [](char c) {
    return c == '#' || std::isspace(static_cast<unsigned char>(c));
  });
  return plain ? word : '"' + word + '"';
}

const std::vector<std::string>& command_help() {
  static const std::vector<std::string> help = [] {
    std::vector<std::string> lines;
    for (const CommandSpec& c : kCommands) {
      std::string usage = c.usage;
      usage.resize(std::max<size_t>(usage.size() + 2, 22), ' ');
      lines.push_back(usage + c.what);
    }
    return lines;
  }();
  return help;
}

}  // namespace dw::shell
