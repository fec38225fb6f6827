// Shell::parse: a line of the session language into a Command, checked against the model, or a
// diagnostic for each mistake (docs/design.md §7a). The words are read first (read_words), then
// each command's arguments by the grammar above its reader.
#include "shell/shell.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>

#include "scenarios/limits.h"
#include "sim/group_query.h"
#include "sim/unknown_variables.h"
#include "watch/watchpoint.h"

namespace dw::shell {
namespace {

using Kind = Command::Kind;

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

// The words of a line, and where its command ends (before a comment).
struct Words {
  std::vector<Token> tokens;
  uint32_t stop = 0;
};

// command := NAME WORD* ('#' comment)?      one a line; each command's arguments as its reader reads them
// WORD    := [^ \t#]+ | '"' [^"\n]* '"'      a quoted word (a file's name with spaces, or a '#')
//                                            anywhere but in `watch`, whose text is the rest of the line
std::variant<Words, std::vector<watch::Diagnostic>> read_words(const std::string& text, uint32_t begin) {
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
  return Words{std::move(tokens), stop};
}

// The arguments of one command, read into `cmd`. Each reader returns false when the command
// cannot be read further (its mistakes are then the answer); a mistake that leaves the rest
// readable is kept and the reading goes on, so that one line reports all it can.
struct ArgumentReader {
  const watch::SourceText& source;
  const std::vector<Token>& tokens;
  uint32_t stop;  // the command's end: before a comment
  const CommandSpec& spec;
  const sim::Session& session;
  Command cmd;
  std::vector<watch::Diagnostic> mistakes;

  const sim::Model& model = session.model();
  const int64_t last_module = static_cast<int64_t>(model.module_count()) - 1;
  const watch::Span after_last{tokens.back().span.end, tokens.back().span.end + 1};
  static constexpr int64_t kMaxStep = scenarios::kStepsRange.max;
  static constexpr int64_t kMaxWhyDepth = 64;

  bool fail(watch::Span at, std::string message) {
    mistakes.push_back({at, std::move(message)});
    return false;
  }
  bool usage(watch::Span at) { return fail(at, std::string("usage: ") + spec.usage); }
  // Between min and max arguments.
  bool want(size_t min, size_t max) {
    if (tokens.size() - 1 < min) return usage(after_last);
    if (tokens.size() - 1 > max) return usage(tokens[max + 1].span);
    return true;
  }
  // An integer argument within [min, max].
  std::optional<int64_t> number(size_t i, int64_t min, int64_t max, const char* what) {
    const auto v = integer(tokens[i].text);
    if (!v || *v < min || *v > max) {
      fail(tokens[i].span, std::string(what) + " must be an integer between " + std::to_string(min) + " and " +
                               std::to_string(max) + ", not '" + std::string(tokens[i].text) + "'");
      return std::nullopt;
    }
    return v;
  }
  // The column of the variable token i names, or -1 (a mistake said).
  int variable(size_t i) {
    const int column = model.column(tokens[i].text);
    if (column < 0) {
      std::string names;
      for (const std::string& v : model.universe.variables) names += (names.empty() ? "" : ", ") + v;
      fail(tokens[i].span,
           "no program has a variable named '" + std::string(tokens[i].text) + "' (there are: " + names + ")");
    }
    return column;
  }
  // A file's name: `""` names none.
  bool file(size_t i) {
    if (tokens[i].text.empty()) return fail(tokens[i].span, "the file's name is empty");
    cmd.name = tokens[i].text;
    return true;
  }

  // The line from token i on, before a comment: a watchpoint's or a condition's text.
  std::string rest_of_line(size_t i) const {
    return source.text().substr(tokens[i].span.begin, stop - tokens[i].span.begin);
  }
  // The script's own text blanked but for the rest of the line from token i: what a text is
  // compiled against, so that its diagnostics point into the script.
  watch::SourceText blanked_but_rest(size_t i) const {
    const std::string& text = source.text();
    std::string blanked(text.size(), ' ');
    for (size_t c = 0; c < text.size(); ++c)
      if (text[c] == '\n') blanked[c] = '\n';
    const std::string rest = rest_of_line(i);
    std::copy(rest.begin(), rest.end(), blanked.begin() + tokens[i].span.begin);
    blanked.resize(stop);  // its end is the text's: "before end of input" points there, on its line
    return watch::SourceText(source.name(), std::move(blanked));
  }

  bool arguments();
  bool step();
  bool run();
  bool action();
  bool set();
  bool remove();
  bool push();
  bool watch();
  bool matches();
  bool render();
  bool save();
  bool why();
  bool find();
  bool eval();
  bool group(size_t from, size_t to);
  bool condition(size_t i);
};

bool ArgumentReader::arguments() {
  switch (cmd.kind) {
    case Kind::Step: return step();
    case Kind::Run: return run();
    case Kind::Action: return action();
    case Kind::Seek:  // seek := 'seek' T
      if (!want(1, 1)) return false;
      cmd.number = number(1, 0, kMaxStep, "T");
      return true;
    case Kind::Set: return set();
    case Kind::Remove: return remove();
    case Kind::Push: return push();
    case Kind::Watch: return watch();
    case Kind::Unwatch:  // unwatch := 'unwatch' NAME
      if (!want(1, 1)) return false;
      cmd.name = tokens[1].text;
      return true;
    case Kind::Matches: return matches();
    case Kind::State:  // state := 'state' M
      if (!want(1, 1)) return false;
      cmd.number = number(1, 0, last_module, "M");
      return true;
    case Kind::Render: return render();
    case Kind::Record:  // record := 'record' FILE '--messages'?
      if (!want(1, 2) || !file(1)) return false;
      if (tokens.size() == 3 && tokens[2].text != "--messages") return usage(tokens[2].span);
      cmd.messages = tokens.size() == 3;
      return true;
    case Kind::Save: return save();
    case Kind::Why: return why();
    case Kind::Find: return find();
    case Kind::Eval: return eval();
    case Kind::Mark:  // mark := 'mark' T NOTE?      NOTE is the rest of the line
      if (!want(1, SIZE_MAX)) return false;
      cmd.number = number(1, 0, kMaxStep, "T");
      if (tokens.size() > 2) cmd.name = rest_of_line(2);
      return true;
    case Kind::Unmark:  // unmark := 'unmark' T
      if (!want(1, 1)) return false;
      cmd.number = number(1, 0, kMaxStep, "T");
      return true;
    case Kind::Diff:  // diff := 'diff' T1 T2
      if (!want(2, 2)) return false;
      cmd.number = number(1, 0, kMaxStep, "T1");
      cmd.other = number(2, 0, kMaxStep, "T2");
      return true;
    case Kind::Marks:
    case Kind::Continue:
    case Kind::Hash:
    case Kind::Interventions:
    case Kind::Reload:
    case Kind::Status:
    case Kind::Help: return want(0, 0);
  }
  return true;
}

// step := 'step' N?
bool ArgumentReader::step() {
  if (!want(0, 1)) return false;
  cmd.number = tokens.size() > 1 ? number(1, 1, kMaxStep, "N") : 1;
  return true;
}

// run := 'run' T? ('--to-match' NAME)?      in either order
bool ArgumentReader::run() {
  for (size_t i = 1; i < tokens.size(); ++i) {
    if (tokens[i].text == "--to-match" && cmd.name.empty()) {
      if (i + 1 == tokens.size()) return fail(after_last, "--to-match needs a watchpoint's name");
      cmd.name = tokens[++i].text;
    } else if (!cmd.number && integer_word(tokens[i].text)) {
      cmd.number = number(i, 0, kMaxStep, "T");
      if (!cmd.number) return false;
    } else {
      return usage(tokens[i].span);
    }
  }
  return true;
}

// action := 'action' NAME ('log' | 'pause' | 'count')
bool ArgumentReader::action() {
  if (!want(2, 2)) return false;
  cmd.name = tokens[1].text;
  const auto action = sim::parse_action(tokens[2].text);
  if (!action)
    return fail(tokens[2].span, "an action is log, pause or count, not '" + std::string(tokens[2].text) + "'");
  cmd.action = *action;
  return true;
}

// set := 'set' M VAR VALUE
bool ArgumentReader::set() {
  if (!want(3, 3)) return false;
  const auto m = number(1, 0, last_module, "M");
  const int column = variable(2);
  const auto value = number(3, INT64_MIN, INT64_MAX, "VALUE");
  if (m && column >= 0 && value)
    cmd.intervention = sim::Intervention{.kind = sim::Intervention::Kind::Set,
                                         .module = static_cast<sim::ModuleId>(*m),
                                         .column = column,
                                         .value = *value};
  return true;
}

// remove := 'remove' M
bool ArgumentReader::remove() {
  if (!want(1, 1)) return false;
  if (const auto m = number(1, 0, last_module, "M"))
    cmd.intervention =
        sim::Intervention{.kind = sim::Intervention::Kind::Remove, .module = static_cast<sim::ModuleId>(*m)};
  return true;
}

// push := 'push' M X Y Z      an impulse in N s, on a body of the physics
bool ArgumentReader::push() {
  if (!want(4, 4)) return false;
  if (session.head().bodies.empty()) return fail(tokens[0].span, "push needs bodies: the scenario has no physics");
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
  return true;
}

// watch := 'watch' NAME ('centralized' | 'distributed')? ('chain' | 'ordered' | 'any')?
//          ('consistent' | 'simultaneous')? ('log' | 'pause' | 'count')? TEXT
//          each word in any order, at most once; TEXT (modules(...); ...) is the rest of the line
bool ArgumentReader::watch() {
  if (tokens.size() < 3) return usage(after_last);
  cmd.name = tokens[1].text;
  if (const std::string why = watch::name_problem(cmd.name); !why.empty()) return fail(tokens[1].span, why);
  sim::WatchSpec spec;  // with the default budget, as a scenario's [[watch]]
  spec.name = cmd.name;
  size_t i = 2;
  // Each kind of word at most once: `centralized distributed` would otherwise keep the last.
  std::array<const Token*, 4> said{};  // by sim::WatchWord: algorithm, action, shape, states
  for (; i < tokens.size() && tokens[i].text.rfind("modules", 0) != 0; ++i) {
    const std::string_view w = tokens[i].text;
    const std::optional<sim::WatchWord> part = sim::read_word(spec, w);
    if (!part)
      return fail(tokens[i].span,
                  "expected centralized, distributed, chain, ordered, any, consistent, simultaneous, log, "
                  "pause, count or the watchpoint's text (modules(...); ...), not '" +
                      std::string(w) + "'");
    const auto kind = static_cast<size_t>(*part);
    if (said[kind])
      return fail(tokens[i].span, "'" + std::string(w) + "' after '" + std::string(said[kind]->text) +
                                      "': the watchpoint's " + sim::word_key(*part) + " is given once");
    said[kind] = &tokens[i];
  }
  if (const std::string why = watch::unsupported(spec.algorithm, spec.options); !why.empty())
    return fail(tokens[1].span, why);
  if (i == tokens.size()) return fail(after_last, "the watchpoint's text is missing: modules(...); ...");
  spec.text = rest_of_line(i);
  auto compiled = sim::compile(spec, blanked_but_rest(i));
  if (auto* error = std::get_if<watch::CompileError>(&compiled)) {
    mistakes = std::move(error->diagnostics);
    return false;
  }
  sim::HostedWatchpoint& hosted = std::get<sim::HostedWatchpoint>(compiled);
  for (watch::Diagnostic& d : sim::unknown_variable_mistakes(model, hosted.watchpoint))
    mistakes.push_back(std::move(d));
  cmd.watch = std::move(hosted);
  return true;
}

// matches := 'matches' NAME? T?
bool ArgumentReader::matches() {
  if (!want(0, 2)) return false;
  for (size_t i = 1; i < tokens.size(); ++i) {
    if (integer_word(tokens[i].text)) {
      cmd.number = number(i, 0, kMaxStep, "T");
      if (!cmd.number) return false;
    } else if (i == 1) cmd.name = tokens[i].text;
    else return usage(tokens[i].span);
  }
  return true;
}

// render := 'render' FILE (W H)?      W and H in 16..8192
bool ArgumentReader::render() {
  if (tokens.size() != 2 && tokens.size() != 4) return usage(tokens.size() > 4 ? tokens[4].span : after_last);
  if (!file(1)) return false;
  if (tokens.size() == 4) {
    const auto w = number(2, 16, 8192, "W"), h = number(3, 16, 8192, "H");
    if (w && h) cmd.width = static_cast<int>(*w), cmd.height = static_cast<int>(*h);
  }
  return true;
}

// save := 'save' FILE 'overwrite'?
bool ArgumentReader::save() {
  if (!want(1, 2) || !file(1)) return false;
  if (tokens.size() == 3) {
    if (tokens[2].text != "overwrite") return usage(tokens[2].span);
    cmd.overwrite = true;
  }
  return true;
}

// why      := 'why' M VAR T? option* | 'why' 'match' W (ROW | T SLOTS+) option*
// option   := '--depth' D | '--narrow'      after the other words; D in 0..64
bool ArgumentReader::why() {
  Command::Why why;
  std::vector<size_t> words;  // the positional ones
  for (size_t i = 1; i < tokens.size(); ++i) {
    if (tokens[i].text == "--narrow") {
      why.narrow = true;
    } else if (tokens[i].text == "--depth") {
      if (i + 1 == tokens.size()) return fail(after_last, "--depth needs a number of steps");
      const auto d = number(++i, 0, kMaxWhyDepth, "D");
      if (!d) return false;
      why.depth = static_cast<int>(*d);
    } else if (tokens[i].text.rfind("--", 0) == 0) {
      return fail(tokens[i].span, "why takes --depth D and --narrow, not '" + std::string(tokens[i].text) + "'");
    } else {
      words.push_back(i);
    }
  }
  if (words.empty()) return usage(after_last);
  if (tokens[words[0]].text == "match") {
    why.match = true;
    if (words.size() < 3) return usage(after_last);
    cmd.name = tokens[words[1]].text;
    if (words.size() == 3) {
      why.row = number(words[2], 0, INT64_MAX, "ROW");
      if (!why.row) return false;
    } else {
      why.t = number(words[2], 0, kMaxStep, "T");
      for (size_t k = 3; k < words.size(); ++k)
        if (const auto m = number(words[k], 0, last_module, "a slot's module")) why.slots.push_back(*m);
      if (!why.t || why.slots.size() != words.size() - 3) return false;
    }
  } else {
    if (words.size() < 2 || words.size() > 3) return usage(words.size() < 2 ? after_last : tokens[words[3]].span);
    cmd.number = number(words[0], 0, last_module, "M");
    why.column = variable(words[1]);
    if (words.size() == 3 && !(why.t = number(words[2], 0, kMaxStep, "T"))) return false;
    if (!cmd.number || why.column < 0) return false;
  }
  cmd.why = std::move(why);
  return true;
}

// The modules of tokens [from, to): a condition's group, its slots in order.
bool ArgumentReader::group(size_t from, size_t to) {
  for (size_t k = from; k < to; ++k) {
    const auto m = number(k, 0, last_module, "M");
    if (!m) return false;
    cmd.query->group.push_back(static_cast<sim::ModuleId>(*m));
  }
  return true;
}

// A condition from token i to the line's end: a watchpoint's text with every window written out
// (no module keeps one for it), whose slots the group fills.
bool ArgumentReader::condition(size_t i) {
  const watch::Span at{tokens[i].span.begin, stop};
  auto compiled = watch::compile_watchpoint("condition", blanked_but_rest(i), watch::WindowKeeping::WrittenOut);
  if (auto* error = std::get_if<watch::CompileError>(&compiled)) {
    mistakes = std::move(error->diagnostics);
    return false;
  }
  watch::Watchpoint& w = std::get<watch::Watchpoint>(compiled);
  for (watch::Diagnostic& d : sim::unknown_variable_mistakes(model, w)) mistakes.push_back(std::move(d));
  if (const std::string why = sim::why_undecidable(w.program, cmd.query->group.size()); !why.empty())
    return fail(at, why);
  cmd.query->condition = std::move(w);
  return true;
}

// find := 'find' ('prev' | 'next') M VAR | 'find' ('prev' | 'next') M+ 'when' TEXT
bool ArgumentReader::find() {
  if (tokens.size() < 4) return usage(after_last);
  if (tokens[1].text != "prev" && tokens[1].text != "next")
    return fail(tokens[1].span, "find prev or find next, not '" + std::string(tokens[1].text) + "'");
  cmd.query.emplace().back = tokens[1].text == "prev";
  size_t when = 2;
  while (when < tokens.size() && tokens[when].text != "when") ++when;
  if (when == tokens.size()) {  // find prev|next M VAR
    if (!want(3, 3) || !group(2, 3)) return false;
    cmd.query->column = variable(3);
    return cmd.query->column >= 0;
  }
  if (when == 2) return fail(tokens[2].span, "find prev|next M... when TEXT: the modules come before 'when'");
  if (when + 1 == tokens.size()) return fail(after_last, "the condition is missing after 'when': modules(...); ...");
  return group(2, when) && condition(when + 1);
}

// eval := 'eval' M+ TEXT      TEXT (modules(...); ...) is the rest of the line
bool ArgumentReader::eval() {
  cmd.query.emplace();
  size_t text = 1;
  while (text < tokens.size() && integer_word(tokens[text].text)) ++text;
  if (text == 1 || text == tokens.size()) return usage(text == 1 && tokens.size() > 1 ? tokens[1].span : after_last);
  return group(1, text) && condition(text);
}

}  // namespace

std::variant<std::optional<Command>, std::vector<watch::Diagnostic>> Shell::parse(const watch::SourceText& source,
                                                                                  uint32_t begin, uint32_t line) {
  auto read = read_words(source.text(), begin);
  if (auto* mistakes = std::get_if<std::vector<watch::Diagnostic>>(&read)) return std::move(*mistakes);
  const Words& words = std::get<Words>(read);
  const std::vector<Token>& tokens = words.tokens;
  if (tokens.empty()) return std::optional<Command>{};

  // Names, files and watchpoints are UTF-8 text: a byte that is not would reach the answers,
  // which are JSON, and the file system, where it names nothing a user can type.
  for (const Token& t : tokens)
    if (const auto at = watch::first_non_utf8(t.text)) {
      const uint32_t begin = t.span.begin + static_cast<uint32_t>(*at);
      return std::vector<watch::Diagnostic>{
          {{begin, begin + 1}, "a byte that is not UTF-8 text: names, files and watchpoints are read as UTF-8"}};
    }
  const CommandSpec* spec = find_command(tokens[0].text);
  if (!spec)
    return std::vector<watch::Diagnostic>{
        {tokens[0].span, "unknown command '" + std::string(tokens[0].text) + "' ('help' lists them)"}};

  ArgumentReader reader{.source = source, .tokens = tokens, .stop = words.stop, .spec = *spec, .session = session_};
  reader.cmd.kind = spec->kind;
  reader.cmd.line = line;
  if (!reader.arguments() || !reader.mistakes.empty()) return std::move(reader.mistakes);
  return std::optional<Command>(std::move(reader.cmd));
}

}  // namespace dw::shell
