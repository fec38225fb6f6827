// A scenario's [[watch]] tables: each watchpoint's text (in the file or in a file next to it),
// compiled, with its reading (algorithm, shape, states), action, budget and optimizations, the
// command line's choices winning over the file's; and, once the programs are known, the check
// that a watchpoint reads no variable that no program has.
#include <algorithm>

#include "scenarios/scenario_loader.h"
#include "sim/unknown_variables.h"

namespace dw::scenarios {

namespace {

// Where the watchpoint text's own characters start in the file: compiled with that base, its
// spans and diagnostics point into the scenario file itself, and it keeps only its own text.
// Nothing when the string was written with escapes, whose value differs from its spelling.
std::optional<uint32_t> text_in_place(const FileDiagnostics& d, const toml::node& value, const std::string& text) {
  const std::string& file = d.source().text();
  const uint32_t begin = d.offset(value.source().begin);
  for (std::string_view quote : {"'''", "\"\"\"", "'", "\""}) {
    if (file.compare(begin, quote.size(), quote) != 0) continue;
    size_t start = begin + quote.size();
    if (quote.size() == 3 && file.compare(start, 1, "\n") == 0) ++start;  // TOML trims it
    else if (quote.size() == 3 && file.compare(start, 2, "\r\n") == 0) start += 2;
    if (file.compare(start, text.size(), text) != 0) return std::nullopt;
    return static_cast<uint32_t>(start);
  }
  return std::nullopt;
}

// One part of the reading (algorithm, shape, states, action), by its key, read into `spec`: false
// when it is given and wrong (said here, or by the reader for a value that is not a string).
bool read_part(TableReader& r, sim::WatchSpec& spec, sim::WatchWord part) {
  const std::string key = sim::word_key(part);
  const auto s = r.string(key);
  if (!s) return !r.has(key);
  if (sim::read_word(spec, *s, part)) return true;
  r.error(key, "'" + key + "' must be " + sim::word_choices(part) + ", not \"" + *s + "\"");
  return false;
}

}  // namespace

// A watchpoint's `text` (compiled in place when it can be) or `file` (next to the scenario).
std::optional<watch::Watchpoint> Loader::compile(TableReader& r, const std::string& name) {
  const auto text = r.string("text");
  const auto file = r.string("file");
  if (text && file) {
    r.error("file", "a watchpoint takes 'text' or 'file', not both");
    return std::nullopt;
  }
  if (!text && !file) {
    if (!r.has("text") && !r.has("file")) r.missing("text");
    return std::nullopt;
  }
  if (text) {
    const toml::node* value = r.node("text");
    // Compiled in place, so that its diagnostics name the scenario file's line and column.
    if (const auto in_place = text_in_place(diagnostics, *value, *text)) {
      auto compiled = watch::compile_watchpoint(name, watch::SourceText(path, *text, *in_place));
      if (auto* w = std::get_if<watch::Watchpoint>(&compiled)) return std::move(*w);
      for (watch::Diagnostic& d : std::get<watch::CompileError>(compiled).diagnostics) diagnostics.add(std::move(d));
      return std::nullopt;
    }
    auto compiled = watch::compile_watchpoint(name, watch::SourceText(path + " (watch " + name + ")", *text));
    if (auto* w = std::get_if<watch::Watchpoint>(&compiled)) return std::move(*w);
    r.error("text", "the watchpoint does not compile:");
    extra += std::get<watch::CompileError>(compiled).format();
    return std::nullopt;
  }
  // A file next to the scenario.
  const std::string at = beside(*file);
  auto watch_text = read_beside(r, "file", at, "the watchpoint file");
  if (!watch_text) return std::nullopt;
  auto compiled = watch::compile_watchpoint(name, watch::SourceText(at, std::move(*watch_text)));
  if (auto* w = std::get_if<watch::Watchpoint>(&compiled)) return std::move(*w);
  r.error("file", "the watchpoint in " + at + " does not compile:");
  extra += std::get<watch::CompileError>(compiled).format();
  return std::nullopt;
}

// [[watch]]: zero or more, each named once; the command line's algorithm, shape, states and
// budget (`overrides`) win over the file's.
std::optional<std::vector<sim::HostedWatchpoint>> Loader::watches(TableReader& root,
                                                                  const ScenarioOverrides& overrides) {
  std::vector<sim::HostedWatchpoint> out;
  const toml::node* n = root.node("watch");
  if (!n) return out;
  const toml::array* a = n->as_array();
  if (!a || !a->is_array_of_tables()) {
    root.error("watch", "'watch' must be [[watch]] tables");
    return std::nullopt;
  }
  if (a->size() > watch::kMaxWatchpoints) {
    root.error("watch", "a scenario holds at most " + std::to_string(watch::kMaxWatchpoints) + " watchpoints, not " +
                            std::to_string(a->size()));
    return std::nullopt;
  }
  bool ok = true;
  std::vector<sim::WatchSpec> named;  // the watchpoints so far, by name
  for (const toml::node& e : *a) {
    TableReader r(*e.as_table(), diagnostics, "[[watch]]");
    const std::optional<std::string> given = r.string("name");  // a wrong type is reported here
    sim::WatchSpec spec;  // the default budget and optimizations unless the table says otherwise
    spec.name = given.value_or("");
    if (!r.has("name")) {
      r.missing("name");
      ok = false;
    } else if (!given) {
      ok = false;  // not a string: said by r.string
    } else if (const std::string why = watch::name_problem(spec.name); !why.empty()) {
      r.error("name", why);  // matches, logs and the session's commands name a watchpoint by it
      ok = false;
    } else if (const std::string twice = sim::second_name_problem(spec.name, named); !twice.empty()) {
      r.error("name", twice);
      ok = false;
    }
    named.push_back(spec);
    auto compiled = compile(r, spec.name.empty() ? "watch" : spec.name);
    bool read = true;
    for (const sim::WatchWord part :
         {sim::WatchWord::Algorithm, sim::WatchWord::Shape, sim::WatchWord::States, sim::WatchWord::Action})
      read = read_part(r, spec, part) && read;
    const auto max_live = r.integer(kMaxLiveRange);
    const auto early = r.boolean("early_termination");
    const auto cull = r.boolean("neighbor_culling");
    const auto spans = r.boolean("temporal_spans");
    r.finish();
    if (!compiled || !read || (r.has("max_live") && !max_live) || (r.has("early_termination") && !early) ||
        (r.has("neighbor_culling") && !cull) || (r.has("temporal_spans") && !spans)) {
      ok = false;
      continue;
    }
    if (overrides.algorithm) spec.algorithm = *overrides.algorithm;
    if (overrides.shape) spec.options.shape = overrides.shape;
    if (overrides.states) spec.options.states = overrides.states;
    if (const std::string why = watch::unsupported(spec.algorithm, spec.options); !why.empty()) {
      // Said at what the file chose; a reading the command line chose in part says so (the
      // user typed --shape, not the line of the file the caret is under).
      std::string typed;
      if (overrides.algorithm) typed += std::string(" --algorithm ") + watch::algorithm_name(*overrides.algorithm);
      if (overrides.shape) typed += std::string(" --shape ") + watch::shape_name(*overrides.shape);
      if (overrides.states) typed += std::string(" --states ") + watch::states_name(*overrides.states);
      const char* key = !overrides.shape && r.has("shape")           ? "shape"
                        : !overrides.states && r.has("states")       ? "states"
                        : !overrides.algorithm && r.has("algorithm") ? "algorithm"
                                                                     : "name";
      r.error(key, typed.empty() ? why : "with" + typed + " from the command line: " + why);
      ok = false;
      continue;
    }
    if (max_live) spec.options.live_budget = static_cast<uint64_t>(*max_live);
    if (overrides.max_live) spec.options.live_budget = *overrides.max_live;
    spec.options.optimizations = {.early_termination = early.value_or(true),
                                  .neighbor_culling = cull.value_or(true),
                                  .temporal_spans = spans.value_or(true)};
    out.push_back(sim::hosted(spec, std::move(*compiled)));
  }
  if (!ok) return std::nullopt;
  return out;
}

// A variable no program has would read as unknown forever: the watchpoint could never match.
// The error points at the variable where it is first read, in the scenario or the watch file.
void Loader::check_watched_variables(const sim::Model& model, const toml::table& doc) {
  for (size_t w = 0; w < model.watches.size(); ++w) {
    const watch::Watchpoint& wp = model.watches[w].watchpoint;
    for (const sim::UnknownVariable& v : sim::unknown_variables(model, wp)) {
      std::string known;
      for (const std::string& k : model.universe.variables) known += (known.empty() ? "" : ", ") + k;
      const std::string message = "watchpoint \"" + wp.name + (v.only_set ? "\" sets '" : "\" reads '") + v.name +
                                  "', which no program has (variables: " + known + ")";
      if (wp.source->name() == path) {
        diagnostics.add({v.first_use, message});  // compiled in place: the span is the scenario file's
      } else {
        TableReader r(*(*doc.get("watch")->as_array())[w].as_table(), diagnostics, "[[watch]]");
        r.error(r.has("text") ? "text" : "file", message + ":");
        extra += watch::format_diagnostic(
            *wp.source, {v.first_use, "'" + v.name + (v.only_set ? "' is set here" : "' is read here")});
      }
    }
  }
}

}  // namespace dw::scenarios
