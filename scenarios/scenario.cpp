#include "scenarios/scenario.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "scenarios/programs.h"
#include "scenarios/table_reader.h"
#include "sim/lattice.h"

namespace dw::scenarios {
namespace {

constexpr int64_t kMaxSteps = 10'000'000;
constexpr uint64_t kMaxModules = 100'000'000;

// The watchpoint text's own characters in the file, everything else blanked (newlines kept):
// compiled as if it were the whole file, its diagnostics point into the scenario file itself.
// Nothing when the string was written with escapes, whose value differs from its spelling.
std::optional<std::string> text_in_place(const FileDiagnostics& d, const toml::node& value, const std::string& text) {
  const std::string& file = d.source().text();
  const uint32_t begin = d.offset(value.source().begin);
  for (std::string_view quote : {"'''", "\"\"\"", "'", "\""}) {
    if (file.compare(begin, quote.size(), quote) != 0) continue;
    size_t start = begin + quote.size();
    if (quote.size() == 3 && file.compare(start, 1, "\n") == 0) ++start;  // TOML trims it
    else if (quote.size() == 3 && file.compare(start, 2, "\r\n") == 0) start += 2;
    if (file.compare(start, text.size(), text) != 0) return std::nullopt;
    std::string blank(file.size(), ' ');
    for (size_t i = 0; i < file.size(); ++i)
      if (file[i] == '\n') blank[i] = '\n';
    blank.replace(start, text.size(), text);
    return blank;
  }
  return std::nullopt;
}

struct Loader {
  std::string path;
  watch::SourceText source;
  FileDiagnostics diagnostics{source};
  std::string extra;  // diagnostics rendered against other files (watchpoint files)

  Loader(std::string p, std::string text) : path(p), source(std::move(p), std::move(text)) {}

  std::optional<watch::Algorithm> algorithm(TableReader& r) {
    const auto s = r.string("algorithm");
    if (!s) return std::nullopt;
    if (*s == "centralized") return watch::Algorithm::Centralized;
    if (*s == "distributed") return watch::Algorithm::Distributed;
    r.error("algorithm", "'algorithm' must be \"centralized\" or \"distributed\", not \"" + *s + "\"");
    return std::nullopt;
  }

  std::optional<sim::MatchAction> action(TableReader& r) {
    const auto s = r.string("action");
    if (!s) return std::nullopt;
    if (*s == "pause") return sim::MatchAction::Pause;
    if (*s == "log") return sim::MatchAction::Log;
    if (*s == "count") return sim::MatchAction::Count;
    r.error("action", "'action' must be \"pause\", \"log\" or \"count\", not \"" + *s + "\"");
    return std::nullopt;
  }

  std::optional<sim::LatticeSpec> lattice(TableReader& root) {
    const toml::table* t = root.table("lattice");
    if (!t) {
      if (!root.has("lattice")) root.missing("lattice");
      return std::nullopt;
    }
    TableReader r(*t, diagnostics, "[lattice]");
    sim::LatticeSpec spec;
    bool ok = true;
    const auto kind_name = r.string("kind");
    std::optional<sim::LatticeKind> kind;
    if (kind_name) {
      kind = sim::lattice_from_name(*kind_name);
      if (!kind) r.error("kind", "unknown lattice kind \"" + *kind_name + "\" (cubic, square2d, hex2d, ring, line)");
    } else if (!r.has("kind")) {
      r.missing("kind");
    }
    const auto size = r.integers("size", 1, 1'000'000, 1, 3);
    if (!size && !r.has("size")) r.missing("size");
    r.finish();
    if (!kind || !size) return std::nullopt;
    spec.kind = *kind;
    const size_t dims = static_cast<size_t>(sim::lattice_dimensions(*kind));
    if (size->size() != dims) {
      r.error("size", "a " + std::string(sim::lattice_name(*kind)) + " lattice takes " + std::to_string(dims) +
                          " size" + (dims == 1 ? "" : "s") + ", not " + std::to_string(size->size()));
      return std::nullopt;
    }
    for (size_t i = 0; i < dims; ++i) spec.size[i] = static_cast<uint32_t>((*size)[i]);
    if (spec.module_count() > kMaxModules) {
      r.error("size", "that is " + std::to_string(spec.module_count()) + " modules; the most is " +
                          std::to_string(kMaxModules));
      ok = false;
    }
    if (*kind == sim::LatticeKind::Ring && spec.size[0] < 3) {
      r.error("size", "a ring needs at least 3 modules");
      ok = false;
    }
    if (!ok) return std::nullopt;
    return spec;
  }

  std::optional<std::vector<std::unique_ptr<const sim::HostProgram>>> programs(TableReader& root,
                                                                              const ProgramSetup& setup) {
    const toml::node* n = root.node("program");
    if (!n) {
      root.missing("program");
      return std::nullopt;
    }
    const toml::array* a = n->as_array();
    if (!a || !a->is_array_of_tables() || a->empty()) {
      root.error("program", "'program' must be one or more [[program]] tables");
      return std::nullopt;
    }
    std::vector<std::unique_ptr<const sim::HostProgram>> out;
    bool ok = true;
    for (const toml::node& e : *a) {
      const toml::table& t = *e.as_table();
      TableReader r(t, diagnostics, "[[program]]");
      const auto name = r.string("name");
      if (!name) {
        if (!r.has("name")) r.missing("name");
        ok = false;
        continue;
      }
      const ProgramInfo* info = find_program(*name);
      if (!info) {
        std::string known;
        for (const ProgramInfo& p : builtin_programs()) known += (known.empty() ? "" : ", ") + std::string(p.name);
        r.error("name", "unknown program \"" + *name + "\" (built in: " + known + ")");
        ok = false;
        continue;
      }
      TableReader params(t, diagnostics, "[[program]] " + *name);
      params.node("name");
      auto program = info->make(params, setup);
      params.finish();
      if (!program) ok = false;
      else out.push_back(std::move(program));
    }
    if (!ok) return std::nullopt;
    return out;
  }

  std::optional<watch::Watchpoint> compile(TableReader& r, const std::string& name) {
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
      if (auto in_place = text_in_place(diagnostics, *value, *text)) {
        auto compiled = watch::compile_watchpoint(name, watch::SourceText(path, std::move(*in_place)));
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
    const std::filesystem::path at = std::filesystem::path(path).parent_path() / *file;
    std::ifstream in(at, std::ios::binary);
    if (!in) {
      r.error("file", "cannot read the watchpoint file " + at.string());
      return std::nullopt;
    }
    std::stringstream ss;
    ss << in.rdbuf();
    auto compiled = watch::compile_watchpoint(name, watch::SourceText(at.string(), ss.str()));
    if (auto* w = std::get_if<watch::Watchpoint>(&compiled)) return std::move(*w);
    r.error("file", "the watchpoint in " + at.string() + " does not compile:");
    extra += std::get<watch::CompileError>(compiled).format();
    return std::nullopt;
  }

  std::optional<std::vector<sim::HostedWatchpoint>> watches(TableReader& root, const ScenarioOverrides& overrides) {
    std::vector<sim::HostedWatchpoint> out;
    const toml::node* n = root.node("watch");
    if (!n) return out;
    const toml::array* a = n->as_array();
    if (!a || !a->is_array_of_tables()) {
      root.error("watch", "'watch' must be [[watch]] tables");
      return std::nullopt;
    }
    bool ok = true;
    std::vector<std::string> names;
    for (const toml::node& e : *a) {
      TableReader r(*e.as_table(), diagnostics, "[[watch]]");
      std::string name = r.string("name").value_or("");
      if (name.empty()) {
        if (!r.has("name")) r.missing("name");
        ok = false;
      } else if (std::find(names.begin(), names.end(), name) != names.end()) {
        r.error("name", "a second watchpoint named \"" + name + "\"");
        ok = false;
      }
      names.push_back(name);
      auto compiled = compile(r, name.empty() ? "watch" : name);
      const auto alg = algorithm(r);
      const auto act = action(r);
      const auto max_live = r.integer("max_live", 0, INT64_MAX);
      const auto early = r.boolean("early_termination");
      const auto cull = r.boolean("neighbor_culling");
      const auto spans = r.boolean("temporal_spans");
      r.finish();
      if (!compiled || (r.has("algorithm") && !alg) || (r.has("action") && !act) || (r.has("max_live") && !max_live) ||
          (r.has("early_termination") && !early) || (r.has("neighbor_culling") && !cull) ||
          (r.has("temporal_spans") && !spans)) {
        ok = false;
        continue;
      }
      watch::DetectorOptions options;
      options.live_budget = static_cast<uint64_t>(max_live.value_or(20'000'000));
      options.optimizations.early_termination = early.value_or(true);
      options.optimizations.neighbor_culling = cull.value_or(true);
      options.optimizations.temporal_spans = spans.value_or(true);
      out.push_back(sim::HostedWatchpoint{std::move(*compiled),
                                          overrides.algorithm.value_or(alg.value_or(watch::Algorithm::Distributed)),
                                          act.value_or(sim::MatchAction::Log), options});
    }
    if (!ok) return std::nullopt;
    return out;
  }

  std::variant<Scenario, std::string> load(const ScenarioOverrides& overrides) {
    toml::table doc;
    try {
      doc = toml::parse(std::string_view(source.text()), std::string_view(path));
    } catch (const toml::parse_error& e) {
      diagnostics.add(e.source(), std::string(e.description()));
      return diagnostics.format();
    }
    TableReader root(doc, diagnostics, "the scenario");
    Scenario s;
    s.path = path;
    s.name = root.string("name").value_or(std::filesystem::path(path).stem().string());
    root.string("description");
    const auto steps = root.integer("steps", 0, kMaxSteps);
    const auto seed = root.integer("seed", 0, INT64_MAX);
    const auto snapshots = root.integer("snapshots", 0, 100'000);
    const auto threads = root.integer("threads", 1, 256);
    s.steps = steps.value_or(100);
    s.snapshots = static_cast<size_t>(snapshots.value_or(64));
    s.threads = static_cast<unsigned>(threads.value_or(1));

    const auto spec = lattice(root);
    std::optional<std::vector<std::unique_ptr<const sim::HostProgram>>> progs;
    if (spec) {
      const ProgramSetup setup{*spec, static_cast<uint32_t>(spec->module_count())};
      progs = programs(root, setup);
    } else {
      root.node("program");  // its errors wait for a lattice
    }
    auto hosted = watches(root, overrides);

    if (const toml::table* physics = root.table("physics")) {
      TableReader r(*physics, diagnostics, "[physics]");
      if (r.boolean("enabled").value_or(false))
        r.error("enabled", "physics worlds are not available yet; this build runs static lattices only");
      r.finish();
    }
    if (const toml::table* view = root.table("view")) {
      TableReader r(*view, diagnostics, "[view]");
      s.view.color_by = r.string("color_by").value_or("");
      if (auto eye = r.numbers("camera_eye", 3)) s.view.camera_eye = std::array<double, 3>{(*eye)[0], (*eye)[1], (*eye)[2]};
      if (auto target = r.numbers("camera_target", 3))
        s.view.camera_target = std::array<double, 3>{(*target)[0], (*target)[1], (*target)[2]};
      r.finish();
    }
    root.finish();
    if (!diagnostics.empty() || !extra.empty() || !spec || !progs || !hosted) return diagnostics.format() + extra;

    auto built = sim::build_model(sim::make_lattice(*spec), std::move(*progs), std::move(*hosted),
                                  overrides.seed.value_or(static_cast<uint64_t>(seed.value_or(1))));
    if (auto* message = std::get_if<std::string>(&built)) {
      diagnostics.add(doc.get("program")->source(), *message);
      return diagnostics.format();
    }
    s.model = std::move(std::get<std::unique_ptr<sim::Model>>(built));
    // A variable no program has would read as unknown forever: the watchpoint could never match.
    for (size_t w = 0; w < s.model->watches.size(); ++w)
      for (const std::string& v : s.model->watches[w].watchpoint.program.variables)
        if (s.model->column(v) < 0) {
          std::string known;
          for (const std::string& k : s.model->universe.variables) known += (known.empty() ? "" : ", ") + k;
          TableReader r(*(*doc.get("watch")->as_array())[w].as_table(), diagnostics, "[[watch]]");
          r.error(r.has("text") ? "text" : "file", "watchpoint \"" + s.model->watches[w].watchpoint.name +
                                                       "\" reads '" + v + "', which no program has (variables: " +
                                                       known + ")");
        }
    if (!diagnostics.empty()) return diagnostics.format();
    if (!s.view.color_by.empty() && s.model->column(s.view.color_by) < 0) {
      TableReader r(*doc.get("view")->as_table(), diagnostics, "[view]");
      r.error("color_by", "no program has a variable named \"" + s.view.color_by + "\"");
      return diagnostics.format();
    }
    s.world = std::make_unique<sim::StaticLatticeWorld>();
    return s;
  }
};

}  // namespace

std::variant<Scenario, std::string> load_scenario_text(const std::string& path, std::string text,
                                                       const ScenarioOverrides& overrides) {
  Loader loader(path, std::move(text));
  return loader.load(overrides);
}

std::variant<Scenario, std::string> load_scenario(const std::string& path, const ScenarioOverrides& overrides) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return path + ": error: cannot read the scenario file\n";
  std::stringstream ss;
  ss << in.rdbuf();
  return load_scenario_text(path, ss.str(), overrides);
}

}  // namespace dw::scenarios
