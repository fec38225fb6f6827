#include "scenarios/saved_scenario.h"

#include <toml++/toml.h>
#include <cstdint>
#include <filesystem>
#include <sstream>
#include <variant>

namespace dw::scenarios {
namespace {

namespace fs = std::filesystem;

// `path` as the scenario at `from` names it (beside the scenario), named from `to_dir` instead.
std::string path_from(const std::string& path, const std::string& from, const fs::path& to_dir) {
  const fs::path p(path);
  if (p.is_absolute()) return path;
  const fs::path at = fs::absolute(fs::path(from).parent_path() / p).lexically_normal();
  // Relative while it stays under the saved file's folder (the two move together); otherwise
  // absolute, which runs from anywhere.
  const fs::path relative = at.lexically_relative(to_dir);
  return relative.empty() || *relative.begin() == ".." ? at.string() : relative.string();
}

// A watchpoint as a [[watch]] table holds it, every setting written out (sim::toml_fields).
toml::table watch_table(const sim::HostedWatchpoint& h) {
  toml::table t;
  for (const auto& [key, value] : sim::toml_fields(sim::spec_of(h)))
    std::visit([&t, key = key](const auto& v) { t.insert(key, v); }, value);
  return t;
}

toml::table event_table(const sim::Intervention& i, const sim::Model& model) {
  toml::table t;
  t.insert("at", i.at);
  t.insert("module", static_cast<int64_t>(model.universe.id(i.module)));
  switch (i.kind) {
    case sim::Intervention::Kind::Set: {
      toml::table set;
      set.insert(model.universe.variables[size_t(i.column)], i.value);
      set.is_inline(true);
      t.insert("set", std::move(set));
      break;
    }
    case sim::Intervention::Kind::Remove: t.insert("remove", true); break;
    case sim::Intervention::Kind::Push:
      t.insert("push", toml::array{double(i.impulse[0]), double(i.impulse[1]), double(i.impulse[2])});
      break;
  }
  return t;
}

// The header comment: where the file came from. A comment holds no control character and only
// UTF-8: with `plain`, every byte of the path that is not printable ASCII is shown as '?'.
std::string header(const std::string& path, const sim::Session& session, bool plain) {
  std::string from = path;
  for (char& c : from)
    if (uint8_t(c) < 0x20 || uint8_t(c) == 0x7F || (plain && uint8_t(c) >= 0x80)) c = '?';
  const int64_t t = session.current();
  const size_t n = session.interventions().size();
  return "# Saved by dwatch from " + from + (t < 0 ? " before step 0" : " at step " + std::to_string(t)) +
         ": its watchpoints and\n# the " + std::to_string(n) + (n == 1 ? " intervention" : " interventions") +
         " of its branch.\n";
}

// `doc` as a scenario file that reads back as `doc`, checked by reading it back. toml++ writes a
// string holding a newline as a multi-line literal even when it holds ''' (`'''x` ... `''''''`,
// which does not parse), and drops a leading newline from one: strings are written as basic
// strings (quotes, backslashes and control characters escaped), multi-line so that the
// watchpoints' texts stay readable, or each on one line when that would not read back.
std::optional<std::string> text_that_reads_back(const toml::table& doc, const std::string& path,
                                                const sim::Session& session) {
  const toml::format_flags basic = toml::toml_formatter::default_flags & ~toml::format_flags::allow_literal_strings;
  for (const bool plain : {false, true})
    for (const toml::format_flags flags : {basic, basic & ~toml::format_flags::allow_multi_line_strings}) {
      std::ostringstream out;
      out << header(path, session, plain) << toml::toml_formatter(doc, flags) << "\n";
      try {
        if (toml::parse(out.str()) == doc) return out.str();
      } catch (const toml::parse_error&) {  // tried again the next way
      }
    }
  return std::nullopt;
}

}  // namespace

std::optional<std::string> saved_scenario(const Scenario& scenario, const sim::Session& session,
                                          const sim::Bookmarks& bookmarks, const std::string& destination,
                                          std::string* error) {
  // A scenario file runs one version of each script from step 0.
  if (const std::optional<int64_t> from = session.first_replacement()) {
    if (error)
      *error =
          "this branch runs a reloaded script from step " + std::to_string(*from) +
          ", and a scenario runs each script from step 0: it cannot say this branch (seek 0 and reload, then save)";
    return std::nullopt;
  }
  toml::table doc;
  try {
    doc = toml::parse(std::string_view(scenario.text), std::string_view(scenario.path));
  } catch (const toml::parse_error& e) {  // it was parsed when loaded: only a changed loader could
    if (error) *error = "the scenario's text no longer parses: " + std::string(e.description());
    return std::nullopt;
  }
  const sim::Model& model = session.model();
  try {  // the working folder may have been removed
    const fs::path to_dir = fs::absolute(fs::path(destination)).parent_path();
    if (toml::array* programs = doc["program"].as_array())
      for (toml::node& p : *programs)
        if (toml::table* t = p.as_table())
          if (const auto script = (*t)["script"].value<std::string>())
            t->insert_or_assign("script", path_from(*script, scenario.path, to_dir));
  } catch (const fs::filesystem_error& e) {
    if (error) *error = "cannot place the scripts' paths for " + destination + ": " + e.code().message();
    return std::nullopt;
  }

  doc.insert_or_assign("seed", static_cast<int64_t>(model.seed));
  doc.erase("watch");
  toml::array watches;
  for (const sim::HostedWatchpoint& h : session.watches().hosted()) watches.push_back(watch_table(h));
  if (!watches.empty()) doc.insert("watch", std::move(watches));
  doc.erase("event");
  toml::array events;
  for (const sim::Intervention& i : session.interventions()) events.push_back(event_table(i, model));
  if (!events.empty()) doc.insert("event", std::move(events));
  doc.erase("bookmark");
  toml::array marks;
  for (const sim::Bookmark& b : bookmarks.all()) marks.push_back(toml::table{{"at", b.at}, {"note", b.note}});
  if (!marks.empty()) doc.insert("bookmark", std::move(marks));

  if (std::optional<std::string> text = text_that_reads_back(doc, scenario.path, session)) return text;
  if (error) *error = "the scenario's tables cannot be written so that they read back the same (a TOML writer's bug)";
  return std::nullopt;
}

}  // namespace dw::scenarios
