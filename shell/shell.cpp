#include "shell/shell.h"

#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "shell/output_files.h"
#include "shell/view_image.h"
#include "scenarios/limits.h"
#include "scenarios/saved_scenario.h"
#include "sim/match_log.h"
#include "sim/state.h"
#include "sim/unknown_variables.h"
#include "watch/watchpoint.h"

namespace dw::shell {
namespace {

using Kind = Command::Kind;

struct CommandSpec {
  const char* name;
  Kind kind;
  const char* usage;
  const char* what;
};

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
    {"hash", Kind::Hash, "hash", "the state hash at the current step, and its simulation and watchpoints parts"},
    {"render", Kind::Render, "render FILE [W H]", "the 3D view of the current step (PNG)"},
    {"record", Kind::Record, "record FILE", "the trace of steps 0..latest, its header listing the interventions"},
    {"save", Kind::Save, "save FILE [overwrite]",
     "this session as a scenario file: its watchpoints, the branch's interventions, paths that work from FILE's "
     "folder; an existing FILE only with 'overwrite'"},
    {"interventions", Kind::Interventions, "interventions", "the interventions of this branch, with their steps"},
    {"reload", Kind::Reload, "reload",
     "load the scenario's Lua scripts again: the changed program runs from the next step, a new branch"},
    {"status", Kind::Status, "status", "where the session stands: steps, watchpoints, history"},
    {"help", Kind::Help, "help", "these commands"},
};

struct Token {
  std::string_view text;
  watch::Span span;
};

std::optional<int64_t> integer(std::string_view s) {
  int64_t v = 0;
  const auto [end, error] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (error != std::errc{} || end != s.data() + s.size()) return std::nullopt;
  return v;
}

// Written as an integer, whatever its size: such a word is a step or a row, and one out of range
// is told so rather than taken for a name.
bool integer_word(std::string_view s) {
  if (!s.empty() && (s[0] == '-' || s[0] == '+')) s.remove_prefix(1);
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

std::optional<double> real(std::string_view s) {
  double v = 0;
  const auto [end, error] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (error != std::errc{} || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

}  // namespace

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

Shell::Shell(const scenarios::Scenario& scenario, sim::Session& session)
    : scenario_(scenario), session_(session) {}

// command := NAME WORD* ('#' comment)?      one a line; see kCommands for each command's arguments
// WORD    := [^ \t#]+ | '"' [^"\n]* '"'      a quoted word (a file's name with spaces, or a '#')
//                                            anywhere but in `watch`, whose text is the rest of the line
std::variant<std::optional<Command>, std::vector<watch::Diagnostic>> Shell::parse(
    const watch::SourceText& source, uint32_t begin, uint32_t line) {
  const std::string& text = source.text();
  uint32_t end = begin;
  while (end < text.size() && text[end] != '\n') ++end;
  uint32_t stop = end;  // the command's end: before a comment
  std::vector<Token> tokens;
  for (uint32_t i = begin; i < end;) {
    if (std::isspace(static_cast<unsigned char>(text[i]))) {
      ++i;
      continue;
    }
    if (text[i] == '"' && !(tokens.size() > 0 && tokens[0].text == "watch")) {
      const size_t close = std::string_view(text).substr(0, end).find('"', i + 1);
      if (close == std::string_view::npos)
        return std::vector<watch::Diagnostic>{{{i, i + 1}, "a quoted word ends with '\"' on its line"}};
      tokens.push_back({std::string_view(text).substr(i + 1, close - i - 1), {i, static_cast<uint32_t>(close + 1)}});
      i = static_cast<uint32_t>(close + 1);
      continue;
    }
    uint32_t j = i;
    while (j < end && text[j] != '#' && !std::isspace(static_cast<unsigned char>(text[j]))) ++j;
    if (j > i) tokens.push_back({std::string_view(text).substr(i, j - i), {i, j}});
    if (j < end && text[j] == '#') {
      stop = j;
      break;
    }
    i = j;
  }
  if (tokens.empty()) return std::optional<Command>{};

  std::vector<watch::Diagnostic> mistakes;
  // Names, files and watchpoints are UTF-8 text: a byte that is not would reach the answers,
  // which are JSON, and the file system, where it names nothing a user can type.
  for (const Token& t : tokens)
    if (const auto at = watch::first_non_utf8(t.text)) {
      const uint32_t begin = t.span.begin + static_cast<uint32_t>(*at);
      return std::vector<watch::Diagnostic>{
          {{begin, begin + 1}, "a byte that is not UTF-8 text: names, files and watchpoints are read as UTF-8"}};
    }
  auto fail = [&](watch::Span at, std::string message) {
    mistakes.push_back({at, std::move(message)});
    return mistakes;
  };
  const CommandSpec* spec = nullptr;
  for (const CommandSpec& c : kCommands)
    if (tokens[0].text == c.name) spec = &c;
  if (!spec) return fail(tokens[0].span, "unknown command '" + std::string(tokens[0].text) + "' ('help' lists them)");

  Command cmd;
  cmd.kind = spec->kind;
  cmd.line = line;
  const watch::Span after_last{tokens.back().span.end, tokens.back().span.end + 1};
  auto usage = [&](watch::Span at) { return fail(at, std::string("usage: ") + spec->usage); };
  auto want = [&](size_t min, size_t max) -> bool {
    if (tokens.size() - 1 < min) return usage(after_last), false;
    if (tokens.size() - 1 > max) return usage(tokens[max + 1].span), false;
    return true;
  };
  // An integer argument within [min, max].
  auto number = [&](size_t i, int64_t min, int64_t max, const char* what) -> std::optional<int64_t> {
    const auto v = integer(tokens[i].text);
    if (!v || *v < min || *v > max) {
      fail(tokens[i].span, std::string(what) + " must be an integer between " + std::to_string(min) + " and " +
                               std::to_string(max) + ", not '" + std::string(tokens[i].text) + "'");
      return std::nullopt;
    }
    return v;
  };
  // A file's name: `""` names none.
  auto file = [&](size_t i) {
    if (tokens[i].text.empty()) return fail(tokens[i].span, "the file's name is empty"), false;
    cmd.name = tokens[i].text;
    return true;
  };
  const sim::Model& model = session_.model();
  const int64_t last_module = static_cast<int64_t>(model.module_count()) - 1;
  constexpr int64_t kMaxStep = scenarios::kStepsRange.max;

  switch (cmd.kind) {
    case Kind::Step:
      if (!want(0, 1)) return mistakes;
      cmd.number = tokens.size() > 1 ? number(1, 1, kMaxStep, "N") : 1;
      break;
    case Kind::Run:
      // run [T] [--to-match NAME], in either order
      for (size_t i = 1; i < tokens.size(); ++i) {
        if (tokens[i].text == "--to-match" && cmd.name.empty()) {
          if (i + 1 == tokens.size()) return fail(after_last, "--to-match needs a watchpoint's name");
          cmd.name = tokens[++i].text;
        } else if (!cmd.number && integer_word(tokens[i].text)) {
          cmd.number = number(i, 0, kMaxStep, "T");
          if (!cmd.number) return mistakes;
        } else {
          return usage(tokens[i].span);
        }
      }
      break;
    case Kind::Action: {
      if (!want(2, 2)) return mistakes;
      cmd.name = tokens[1].text;
      const auto action = sim::parse_action(tokens[2].text);
      if (!action)
        return fail(tokens[2].span, "an action is log, pause or count, not '" + std::string(tokens[2].text) + "'");
      cmd.action = *action;
      break;
    }
    case Kind::Seek:
      if (!want(1, 1)) return mistakes;
      cmd.number = number(1, 0, kMaxStep, "T");
      break;
    case Kind::Set: {
      if (!want(3, 3)) return mistakes;
      const auto m = number(1, 0, last_module, "M");
      const int column = model.column(tokens[2].text);
      if (column < 0) {
        std::string names;
        for (const std::string& v : model.universe.variables) names += (names.empty() ? "" : ", ") + v;
        fail(tokens[2].span,
             "no program has a variable named '" + std::string(tokens[2].text) + "' (there are: " + names + ")");
      }
      const auto value = number(3, INT64_MIN, INT64_MAX, "VALUE");
      if (m && column >= 0 && value)
        cmd.intervention = sim::Intervention{.kind = sim::Intervention::Kind::Set,
                                             .module = static_cast<sim::ModuleId>(*m),
                                             .column = column,
                                             .value = *value};
      break;
    }
    case Kind::Remove:
      if (!want(1, 1)) return mistakes;
      if (const auto m = number(1, 0, last_module, "M"))
        cmd.intervention =
            sim::Intervention{.kind = sim::Intervention::Kind::Remove, .module = static_cast<sim::ModuleId>(*m)};
      break;
    case Kind::Push: {
      if (!want(4, 4)) return mistakes;
      if (session_.head().bodies.empty()) return fail(tokens[0].span, "push needs bodies: the scenario has no physics");
      const auto m = number(1, 0, last_module, "M");
      sim::Vec3 impulse{};
      bool ok = m.has_value();
      for (size_t i = 0; i < 3; ++i) {
        const auto v = real(tokens[2 + i].text);
        if (!v || std::abs(*v) > 1e9) {
          fail(tokens[2 + i].span, "an impulse component is a number of N s (at most 1e9 either way), not '" +
                                       std::string(tokens[2 + i].text) + "'");
          ok = false;
        } else {
          impulse[i] = static_cast<float>(*v);
        }
      }
      if (ok)
        cmd.intervention = sim::Intervention{
            .kind = sim::Intervention::Kind::Push, .module = static_cast<sim::ModuleId>(*m), .impulse = impulse};
      break;
    }
    case Kind::Watch: {
      // watch NAME [centralized|distributed] [chain|ordered|any] [consistent|simultaneous]
      //       [log|pause|count] TEXT: TEXT is the rest of the line.
      if (tokens.size() < 3) return usage(after_last);
      cmd.name = tokens[1].text;
      if (const std::string why = watch::name_problem(cmd.name); !why.empty()) return fail(tokens[1].span, why);
      watch::Algorithm algorithm = watch::Algorithm::Distributed;
      sim::MatchAction action = sim::MatchAction::Log;
      watch::DetectorOptions options;
      options.live_budget = 20'000'000;  // as a scenario's [[watch]] by default
      size_t i = 2;
      // Each kind of word at most once: `centralized distributed` would otherwise keep the last.
      std::array<const Token*, 4> said{};  // algorithm, action, shape, states
      static constexpr std::array<const char*, 4> kKinds{"algorithm", "action", "shape", "states"};
      for (; i < tokens.size() && tokens[i].text.rfind("modules", 0) != 0; ++i) {
        const std::string_view w = tokens[i].text;
        size_t kind = 0;
        if (w == "centralized") algorithm = watch::Algorithm::Centralized;
        else if (w == "distributed") algorithm = watch::Algorithm::Distributed;
        else if (w == "log") action = sim::MatchAction::Log, kind = 1;
        else if (w == "pause") action = sim::MatchAction::Pause, kind = 1;
        else if (w == "count") action = sim::MatchAction::Count, kind = 1;
        else if (auto shape = watch::parse_shape(w)) options.shape = shape, kind = 2;
        else if (auto states = watch::parse_states(w)) options.states = states, kind = 3;
        else
          return fail(tokens[i].span,
                      "expected centralized, distributed, chain, ordered, any, consistent, simultaneous, log, "
                      "pause, count or the watchpoint's text (modules(...); ...), not '" +
                          std::string(w) + "'");
        if (said[kind])
          return fail(tokens[i].span, "'" + std::string(w) + "' after '" + std::string(said[kind]->text) +
                                          "': the watchpoint's " + kKinds[kind] + " is given once");
        said[kind] = &tokens[i];
      }
      if (const std::string why = watch::unsupported(algorithm, options); !why.empty())
        return fail(tokens[1].span, why);
      if (i == tokens.size()) return fail(after_last, "the watchpoint's text is missing: modules(...); ...");
      // Compiled against the script's own text, blanked but for the watchpoint, so that its
      // diagnostics point into the script.
      std::string blanked(text.size(), ' ');
      for (size_t c = 0; c < text.size(); ++c)
        if (text[c] == '\n') blanked[c] = '\n';
      std::copy(text.begin() + tokens[i].span.begin, text.begin() + stop, blanked.begin() + tokens[i].span.begin);
      auto compiled = watch::compile_watchpoint(cmd.name, watch::SourceText(source.name(), std::move(blanked)));
      if (auto* error = std::get_if<watch::CompileError>(&compiled)) return std::move(error->diagnostics);
      sim::HostedWatchpoint hosted{std::move(std::get<watch::Watchpoint>(compiled)), algorithm, action, options};
      for (watch::Diagnostic& d : sim::unknown_variable_mistakes(model, hosted.watchpoint)) mistakes.push_back(std::move(d));
      cmd.watch = std::move(hosted);
      break;
    }
    case Kind::Unwatch:
      if (!want(1, 1)) return mistakes;
      cmd.name = tokens[1].text;
      break;
    case Kind::Matches:
      if (!want(0, 2)) return mistakes;
      for (size_t i = 1; i < tokens.size(); ++i) {
        if (integer_word(tokens[i].text)) {
          cmd.number = number(i, 0, kMaxStep, "T");
          if (!cmd.number) return mistakes;
        } else if (i == 1) cmd.name = tokens[i].text;
        else return usage(tokens[i].span);
      }
      break;
    case Kind::State:
      if (!want(1, 1)) return mistakes;
      cmd.number = number(1, 0, last_module, "M");
      break;
    case Kind::Render:
      if (tokens.size() != 2 && tokens.size() != 4) return usage(tokens.size() > 4 ? tokens[4].span : after_last);
      if (!file(1)) return mistakes;
      if (tokens.size() == 4) {
        const auto w = number(2, 16, 8192, "W"), h = number(3, 16, 8192, "H");
        if (w && h) cmd.width = static_cast<int>(*w), cmd.height = static_cast<int>(*h);
      }
      break;
    case Kind::Record:
      if (!want(1, 1) || !file(1)) return mistakes;
      break;
    case Kind::Save:
      if (!want(1, 2) || !file(1)) return mistakes;
      if (tokens.size() == 3) {
        if (tokens[2].text != "overwrite") return usage(tokens[2].span);
        cmd.overwrite = true;
      }
      break;
    case Kind::Continue:
    case Kind::Hash:
    case Kind::Interventions:
    case Kind::Reload:
    case Kind::Status:
    case Kind::Help:
      if (!want(0, 0)) return mistakes;
      break;
  }
  if (!mistakes.empty()) return mistakes;
  return std::optional<Command>(std::move(cmd));
}

render::Scene Shell::scene() {
  const int64_t t = std::max<int64_t>(0, session_.current());
  render::SceneSettings settings = scene_settings(scenario_, "");
  settings.title = scenario_.name + "  \xC2\xB7  step " + std::to_string(t);
  return render::build_scene(session_.model(), session_.state(), groups_at(session_, t, Highlight::First), settings);
}

nlohmann::ordered_json Shell::position() {
  nlohmann::ordered_json j;
  j["current"] = session_.current();
  j["latest"] = session_.latest();
  j["decided"] = session_.decided();
  return j;
}

nlohmann::ordered_json Shell::match_json(uint32_t w, size_t i) const {
  const sim::HostedWatchpoint& h = session_.model().watches[w];
  const sim::MatchList& list = session_.matches(w);
  const size_t k = h.watchpoint.program.slot_count();
  nlohmann::ordered_json j;
  j["watch"] = h.watchpoint.name;
  j["t"] = list.t[i];
  nlohmann::ordered_json slots = nlohmann::ordered_json::object();
  for (size_t s = 0; s < k; ++s)
    slots[h.watchpoint.program.slot_names[s]] = session_.model().universe.id(list.slots[i * k + s]);
  j["slots"] = std::move(slots);
  if (const size_t a = h.watchpoint.program.actions.size(); a > 0 && list.actions.size() >= (i + 1) * a) {
    std::vector<watch::ModuleId> ids;
    for (size_t s = 0; s < k; ++s) ids.push_back(session_.model().universe.id(list.slots[i * k + s]));
    j["then"] = sim::MatchLog::then_json(sim::MatchLog::info(h.watchpoint), ids, {list.actions.data() + i * a, a});
  }
  j["detected"] = list.detected[i];
  return j;
}

std::variant<nlohmann::ordered_json, std::string> Shell::execute(const Command& cmd,
                                                                        const sim::Control& control) {
  using Result = std::variant<nlohmann::ordered_json, std::string>;
  const auto failed = [](std::string why) { return Result(std::in_place_index<1>, std::move(why)); };
  const sim::Model& model = session_.model();
  nlohmann::ordered_json answer;
  for (const CommandSpec& c : kCommands)
    if (c.kind == cmd.kind) answer["cmd"] = c.name;
  auto merge = [&](const nlohmann::ordered_json& more) {
    for (auto it = more.begin(); it != more.end(); ++it) answer[it.key()] = it.value();
  };
  auto intervention_answer = [&](const sim::Intervention& i) {
    return nlohmann::ordered_json::parse(sim::intervention_json(i, model.universe));
  };
  try {
    switch (cmd.kind) {
      case Kind::Step:
      case Kind::Run:
      case Kind::Continue: {
        std::optional<uint32_t> to_match;
        if (cmd.kind == Kind::Run && !cmd.name.empty()) {
          const int w = session_.watch_index(cmd.name);
          if (w < 0) return failed("no watchpoint is named '" + cmd.name + "'");
          if (model.watches[static_cast<size_t>(w)].action == sim::MatchAction::Count)
            return failed("'" + cmd.name + "' counts its matches and keeps none to stop at ('action " + cmd.name +
                          " log' keeps them from now on)");
          to_match = static_cast<uint32_t>(w);
        }
        const int64_t target = cmd.kind == Kind::Step ? session_.current() + *cmd.number
                               : cmd.number           ? *cmd.number
                                                      : std::max(session_.end() - 1, session_.current());
        const auto pause = session_.run_until(target + 1, {}, control, to_match);
        merge(position());
        nlohmann::ordered_json stop = nullptr;
        if (pause) {
          const sim::HostedWatchpoint& h = model.watches[pause->watch];
          nlohmann::ordered_json group = nlohmann::ordered_json::object();
          for (size_t s = 0; s < pause->group.size(); ++s)
            group[h.watchpoint.program.slot_names[s]] = model.universe.id(pause->group[s]);
          stop = {{"watch", h.watchpoint.name},
                  {"t", pause->t},
                  {"detected", pause->detected},
                  {"group", group},
                  {"matches", pause->matches}};
        }
        // A run to a match stopped by that match says so apart from a pause action's stop.
        const bool asked = pause && pause->asked;
        answer["paused"] = asked ? nullptr : stop;
        if (to_match) answer["matched"] = asked ? stop : nullptr;
        if (control.stopped()) answer["cancelled"] = true;
        break;
      }
      case Kind::Action: {
        const int w = session_.watch_index(cmd.name);
        if (w < 0) return failed("no watchpoint is named '" + cmd.name + "'");
        answer["watch"] = cmd.name;
        answer["was"] = std::string(sim::action_name(model.watches[static_cast<size_t>(w)].action));
        session_.set_action(static_cast<uint32_t>(w), cmd.action);
        answer["action"] = std::string(sim::action_name(cmd.action));
        break;
      }
      case Kind::Seek:
        if (*cmd.number > session_.latest())
          return failed("step " + std::to_string(*cmd.number) + " has not been simulated (the latest is " +
                        std::to_string(session_.latest()) + "; step or run to get there)");
        if (!session_.seek(*cmd.number, control)) {
          if (control.stopped()) return failed("cancelled");
          return failed("the session keeps no history to seek back to");
        }
        merge(position());
        break;
      case Kind::Set:
      case Kind::Remove:
      case Kind::Push: {
        const int64_t dropped = session_.latest() - session_.current();
        const std::string stuck = cmd.kind == Kind::Push ? session_.push_moves_nothing(cmd.intervention->module) : "";
        if (std::string error = session_.intervene(*cmd.intervention); !error.empty()) return failed(error);
        sim::Intervention made = *cmd.intervention;
        made.at = session_.current() + 1;
        answer["intervention"] = intervention_answer(made);
        answer["dropped_steps"] = dropped;
        merge(position());
        if (!stuck.empty()) answer["warning"] = stuck;
        break;
      }
      case Kind::Reload: {
        if (scenario_.scripts.empty()) return failed("the scenario runs no Lua script to reload");
        const int64_t dropped = session_.latest() - session_.current();
        auto reloaded = scenarios::reload_scripts(scenario_, session_);
        if (auto* error = std::get_if<std::string>(&reloaded)) return failed(*error);
        answer["reloaded"] = std::get<std::vector<std::string>>(reloaded);
        answer["from"] = session_.current() + 1;
        answer["dropped_steps"] = dropped;
        merge(position());
        break;
      }
      case Kind::Watch: {
        const bool replaces = std::any_of(
            model.watches.begin(), model.watches.end(),
            [&](const sim::HostedWatchpoint& h) { return h.watchpoint.name == cmd.watch->watchpoint.name; });
        if (!replaces && model.watches.size() >= watch::kMaxWatchpoints)
          return failed("a session holds at most " + std::to_string(watch::kMaxWatchpoints) +
                        " watchpoints: unwatch one first");
        const auto w = session_.set_watch(*cmd.watch, control);
        if (!w)
          return failed(control.stopped() ? "cancelled" : "the session keeps no history to evaluate a watchpoint over");
        const sim::HostedWatchpoint& h = model.watches[*w];
        answer["watch"] = h.watchpoint.name;
        answer["index"] = *w;
        answer["algorithm"] = watch::algorithm_name(h.algorithm);
        answer["shape"] = watch::shape_name(watch::group_shape(h.algorithm, h.options));
        answer["action"] = sim::action_name(h.action);
        answer["lag"] = h.lag();
        answer["matches"] = session_.match_count(*w);
        answer["decided"] = session_.decided(*w);
        break;
      }
      case Kind::Unwatch:
        if (!session_.remove_watch(cmd.name)) return failed("no watchpoint is named '" + cmd.name + "'");
        answer["unwatched"] = cmd.name;
        break;
      case Kind::Matches: {
        int w = -1;
        if (!cmd.name.empty() && (w = session_.watch_index(cmd.name)) < 0)
          return failed("no watchpoint is named '" + cmd.name + "'");
        // A `count` watchpoint keeps only the number of its matches of each step, not the groups.
        // Its action may have changed on the way (`action W count`, then `log`): what it kept is
        // listed and what it counted answered under only_counted, whatever its action is now.
        nlohmann::ordered_json list = nlohmann::ordered_json::array(), only_counted = nlohmann::ordered_json::object();
        uint64_t counted = 0;
        for (uint32_t i = 0; i < model.watches.size(); ++i) {
          if (w >= 0 && i != static_cast<uint32_t>(w)) continue;
          const sim::MatchList& m = session_.matches(i);
          const uint64_t n = cmd.number ? m.counted_at(*cmd.number) : m.counted_total();
          if (n > 0 || model.watches[i].action == sim::MatchAction::Count) {
            only_counted[model.watches[i].watchpoint.name] = n;
            counted += n;
          }
          const auto [first, last] = cmd.number ? m.at(*cmd.number) : std::pair<size_t, size_t>{0, m.size()};
          for (size_t k = first; k < last; ++k) list.push_back(match_json(i, k));
        }
        if (cmd.number) {
          answer["t"] = *cmd.number;
          answer["decided"] = *cmd.number <= session_.decided();
        }
        answer["count"] = list.size() + counted;
        if (!only_counted.empty()) answer["only_counted"] = std::move(only_counted);
        answer["matches"] = std::move(list);
        break;
      }
      case Kind::State: {
        const auto m = static_cast<sim::ModuleId>(*cmd.number);
        const sim::State& s = session_.state();
        answer["t"] = session_.current();
        answer["module"] = model.universe.id(m);
        answer["present"] = session_.seen_present()[m] != 0;
        nlohmann::ordered_json vars = nlohmann::ordered_json::object();
        for (uint32_t v = 0; v < model.variable_count(); ++v)
          vars[model.universe.variables[v]] = s.values[size_t{m} * model.variable_count() + v];
        answer["vars"] = std::move(vars);
        nlohmann::ordered_json nbrs = nlohmann::ordered_json::array();
        for (sim::ModuleId n : session_.seen_graph().neighbors(m)) nbrs.push_back(model.universe.id(n));
        answer["nbrs"] = std::move(nbrs);
        if (!s.bodies.empty()) {
          const sim::Pose& p = s.bodies.poses[m];
          answer["pose"] = {{"position", p.position}, {"orientation", p.orientation}};
        }
        break;
      }
      case Kind::Hash: {
        const sim::StateHash hash = session_.hash();
        answer["t"] = session_.current();
        answer["hash"] = sim::hash_text(hash.whole());
        answer["simulation"] = sim::hash_text(hash.simulation);
        answer["watchpoints"] = sim::hash_text(hash.watches);
        break;
      }
      case Kind::Render: {
        const NamedFile file{"render", cmd.name};
        std::unique_ptr<sim::OutputFile> out;
        if (cmd.name == "-") return failed("render needs a file name");
        if (std::string error = open_output_apart(scenario_.inputs, file, out); !error.empty()) return failed(error);
        const render::Scene view = scene();
        if (std::string error = write_view(view, *out, cmd.width, cmd.height); !error.empty()) return failed(error);
        // A signal while it drew stops the script here: the file it would replace stays as it was.
        if (control.stopped()) return failed("cancelled");
        if (std::string error = out->commit(); !error.empty()) return failed(error);
        answer["render"] = cmd.name;
        answer["t"] = std::max<int64_t>(0, session_.current());
        answer["width"] = cmd.width;
        answer["height"] = cmd.height;
        answer["groups"] = view.groups.size();
        break;
      }
      case Kind::Record: {
        const NamedFile file{"record", cmd.name};
        std::unique_ptr<sim::OutputFile> out;
        if (std::string error = open_output_apart(scenario_.inputs, file, out); !error.empty()) return failed(error);
        if (std::string error = session_.record(out->stream(), control); !error.empty()) {
          if (error == "cancelled") return failed(error);  // the temporary goes with `out`
          // The file knows why its writing failed (a full disk): its reason, rather than the stream's.
          const std::string reason = out->commit();
          return failed(reason.empty() ? error : reason);
        }
        if (std::string error = out->commit(); !error.empty()) return failed(error);
        answer["record"] = cmd.name;
        answer["steps"] = session_.latest() + 1;
        answer["interventions"] = session_.interventions().size();
        break;
      }
      case Kind::Save: {
        if (cmd.name == "-") return failed("save needs a file name");
        struct stat st {};
        // A folder is no file to overwrite: opening it says so ("Is a directory").
        if (!cmd.overwrite && ::lstat(cmd.name.c_str(), &st) == 0 && !S_ISDIR(st.st_mode))
          return failed(cmd.name + " exists; 'save " + command_word(cmd.name) + " overwrite' replaces it");
        std::string why;
        const std::optional<std::string> text = scenarios::saved_scenario(scenario_, session_, cmd.name, &why);
        if (!text) return failed(why);
        std::unique_ptr<sim::OutputFile> out;
        if (std::string error = open_output_apart(scenario_.inputs, {"save", cmd.name}, out); !error.empty())
          return failed(error);
        out->stream() << *text;
        if (std::string error = out->commit(); !error.empty()) return failed(error);
        answer["save"] = cmd.name;
        answer["watches"] = session_.model().watches.size();
        answer["interventions"] = session_.interventions().size();
        break;
      }
      case Kind::Interventions: {
        nlohmann::ordered_json list = nlohmann::ordered_json::array();
        for (const sim::Intervention& i : session_.interventions()) list.push_back(intervention_answer(i));
        answer["interventions"] = std::move(list);
        break;
      }
      case Kind::Status: {
        merge(position());
        answer["end"] = session_.end();
        nlohmann::ordered_json watches = nlohmann::ordered_json::array();
        for (uint32_t w = 0; w < model.watches.size(); ++w) {
          const sim::HostedWatchpoint& h = model.watches[w];
          watches.push_back({{"name", h.watchpoint.name},
                             {"algorithm", watch::algorithm_name(h.algorithm)},
                             {"shape", watch::shape_name(watch::group_shape(h.algorithm, h.options))},
                             {"action", sim::action_name(h.action)},
                             {"lag", h.lag()},
                             {"decided", session_.decided(w)},
                             {"matches", session_.match_count(w)},
                             {"stopped", session_.stats(w).stopped}});
        }
        answer["watches"] = std::move(watches);
        answer["interventions"] = session_.interventions().size();
        // How the history is kept: it varies with the machine's speed (never the results).
        answer["history"] = {{"keyframe_interval", session_.keyframe_interval()},
                             {"keyframes", session_.keyframes()},
                             {"bytes", session_.history_bytes()}};
        break;
      }
      case Kind::Help: answer["commands"] = command_help(); break;
    }
  } catch (const sim::ProgramError& e) {
    return failed(e.what());
  } catch (const std::exception& e) {
    // A mistake of dwatch's own, not the command's: said, and the session goes on (a command
    // leaves the session as it was, or where a run had got to).
    return failed(std::string("internal error: ") + e.what());
  }
  return answer;
}

}  // namespace dw::shell
