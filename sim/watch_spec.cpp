#include "sim/watch_spec.h"

#include <algorithm>

#include "watch/ast.h"

namespace dw::sim {

std::string_view action_name(MatchAction a) {
  switch (a) {
    case MatchAction::Pause: return "pause";
    case MatchAction::Log: return "log";
    case MatchAction::Count: return "count";
  }
  return "?";
}

std::optional<MatchAction> parse_action(std::string_view name) {
  for (MatchAction a : kActions)
    if (name == action_name(a)) return a;
  return std::nullopt;
}

std::string WatchSpec::words() const {
  return std::string(algorithm_name()) + " " + shape_name() + (distributed() ? std::string(" ") + states_name() : "") +
         " " + std::string(action_name(action));
}

const char* word_key(WatchWord part) {
  switch (part) {
    case WatchWord::Algorithm: return "algorithm";
    case WatchWord::Action: return "action";
    case WatchWord::Shape: return "shape";
    case WatchWord::States: return "states";
  }
  return "?";
}

std::string word_choices(WatchWord part) {
  switch (part) {
    case WatchWord::Algorithm: return watch::algorithm_names();
    case WatchWord::Action: return action_names();
    case WatchWord::Shape: return watch::shape_names();
    case WatchWord::States: return watch::states_names();
  }
  return {};
}

std::optional<WatchWord> read_word(WatchSpec& spec, std::string_view word, std::optional<WatchWord> only) {
  const auto may = [&](WatchWord part) { return !only || *only == part; };
  if (const auto a = watch::parse_algorithm(word); a && may(WatchWord::Algorithm)) {
    spec.algorithm = *a;
    return WatchWord::Algorithm;
  }
  if (const auto a = parse_action(word); a && may(WatchWord::Action)) {
    spec.action = *a;
    return WatchWord::Action;
  }
  if (const auto s = watch::parse_shape(word); s && may(WatchWord::Shape)) {
    spec.options.shape = s;
    return WatchWord::Shape;
  }
  if (const auto s = watch::parse_states(word); s && may(WatchWord::States)) {
    spec.options.states = s;
    return WatchWord::States;
  }
  return std::nullopt;
}

std::string second_name_problem(std::string_view name, std::span<const WatchSpec> before) {
  if (std::none_of(before.begin(), before.end(), [&](const WatchSpec& s) { return s.name == name; })) return {};
  return "a second watchpoint named \"" + std::string(name) + "\"";
}

WatchSpec spec_of(const HostedWatchpoint& h) {
  return {h.watchpoint.name, watch::to_string(h.watchpoint.ast), h.algorithm, h.options, h.action};
}

std::vector<WatchSpec> specs_of(const HostedWatches& hosted) {
  std::vector<WatchSpec> out;
  for (const HostedWatchpoint& h : hosted) out.push_back(spec_of(h));
  return out;
}

std::variant<HostedWatchpoint, watch::CompileError> compile(const WatchSpec& spec, watch::SourceText source) {
  auto compiled = watch::compile_watchpoint(spec.name, std::move(source));
  if (auto* e = std::get_if<watch::CompileError>(&compiled)) return std::move(*e);
  return hosted(spec, std::move(std::get<watch::Watchpoint>(compiled)));
}

HostedWatchpoint hosted(const WatchSpec& spec, watch::Watchpoint compiled) {
  return {std::move(compiled), spec.algorithm, spec.action, spec.options};
}

std::variant<HostedWatchpoint, watch::CompileError> compile(const WatchSpec& spec, const std::string& file) {
  return compile(spec, watch::SourceText(file + " (watch " + spec.name + ")", spec.text));
}

std::variant<std::vector<HostedWatchpoint>, std::string> compile_all(std::span<const WatchSpec> specs,
                                                                     const std::string& file) {
  std::vector<HostedWatchpoint> out;
  for (const WatchSpec& spec : specs) {
    auto compiled = compile(spec, file);
    if (auto* e = std::get_if<watch::CompileError>(&compiled)) return e->format();
    out.push_back(std::move(std::get<HostedWatchpoint>(compiled)));
  }
  return out;
}

nlohmann::ordered_json to_json(const WatchSpec& spec) {
  return {{"name", spec.name},
          {"text", spec.text},
          {"algorithm", spec.algorithm_name()},
          {"shape", spec.shape_name()},
          {"states", spec.states_name()},
          {"action", action_name(spec.action)}};
}

std::variant<WatchSpec, SpecError> spec_from_json(const nlohmann::json& object, std::span<const WatchSpec> before) {
  // Every key a string first, then each checked in the order written.
  std::string value[std::size(kJsonKeys)];
  for (size_t k = 0; k < std::size(kJsonKeys); ++k) {
    const auto found = object.find(kJsonKeys[k]);
    if (found == object.end() || !found->is_string()) return SpecError{std::string(kJsonKeys[k]), "", true};
    value[k] = found->get<std::string>();
  }
  WatchSpec spec;
  spec.name = std::move(value[0]);
  spec.text = std::move(value[1]);
  if (std::string why = watch::name_problem(spec.name); !why.empty()) return SpecError{"name", std::move(why)};
  if (std::string why = second_name_problem(spec.name, before); !why.empty()) return SpecError{"name", std::move(why)};
  constexpr std::pair<WatchWord, size_t> kWords[] = {
      {WatchWord::Algorithm, 2}, {WatchWord::Shape, 3}, {WatchWord::States, 4}, {WatchWord::Action, 5}};
  for (const auto& [part, k] : kWords) {
    if (read_word(spec, value[k], part)) continue;
    const std::string key = word_key(part);
    return SpecError{key, "\"" + key + "\" must be " + word_choices(part) + ", not \"" + value[k] + "\""};
  }
  // The header names the states of every watchpoint; the centralized detector compares
  // simultaneous ones whatever it says.
  if (!spec.distributed()) spec.options.states.reset();
  if (std::string why = watch::unsupported(spec.algorithm, spec.options); !why.empty())
    return SpecError{"states", "watchpoint \"" + spec.name + "\" cannot run: " + why};
  return spec;
}

std::vector<std::pair<std::string_view, TomlValue>> toml_fields(const WatchSpec& spec) {
  std::vector<std::pair<std::string_view, TomlValue>> t;
  t.emplace_back("name", spec.name);
  t.emplace_back("text", spec.text);
  t.emplace_back("algorithm", std::string(spec.algorithm_name()));
  t.emplace_back("shape", std::string(spec.shape_name()));
  if (spec.distributed()) t.emplace_back("states", std::string(spec.states_name()));
  t.emplace_back("action", std::string(action_name(spec.action)));
  t.emplace_back("max_live", static_cast<int64_t>(spec.options.live_budget));
  t.emplace_back("early_termination", spec.options.optimizations.early_termination);
  t.emplace_back("neighbor_culling", spec.options.optimizations.neighbor_culling);
  t.emplace_back("temporal_spans", spec.options.optimizations.temporal_spans);
  return t;
}

}  // namespace dw::sim
