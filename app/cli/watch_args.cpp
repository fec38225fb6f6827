#include "app/cli/watch_args.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "sim/read_file.h"
#include "watch/watchpoint.h"

namespace dw::app {
namespace {

bool is_name(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) return false;
  return true;
}

}  // namespace

std::variant<std::vector<sim::HostedWatchpoint>, std::string> load_watchpoints(const std::vector<std::string>& args,
                                                                               const sim::WatchSpec& reading,
                                                                               std::vector<std::string>* files_read) {
  if (args.size() > watch::kMaxWatchpoints)
    return "dwatch: error: at most " + std::to_string(watch::kMaxWatchpoints) + " watchpoints, not " +
           std::to_string(args.size()) + "\n";
  // NAME=... names the watchpoint; a watchpoint's own text starts with `modules(`, never NAME=.
  auto given_name = [](const std::string& arg) -> std::string {
    const size_t eq = arg.find('=');
    if (eq == std::string::npos || !is_name(arg.substr(0, eq)) || arg.substr(0, eq) == "modules") return "";
    return arg.substr(0, eq);
  };
  std::vector<std::string> given;  // so that no name made up below is one the user gave
  for (const std::string& arg : args) given.push_back(given_name(arg));
  std::vector<sim::HostedWatchpoint> out;
  std::vector<sim::WatchSpec> named;
  std::string errors;
  for (size_t i = 0; i < args.size(); ++i) {
    std::string arg = args[i];
    std::string name = given[i];
    if (!name.empty()) arg = arg.substr(name.size() + 1);
    std::string source_name = "<watch " + std::to_string(i + 1) + ">";
    std::string text = arg;
    if (!arg.empty() && arg[0] == '@') {
      const std::string path = arg.substr(1);
      if (files_read) files_read->push_back(path);
      std::string error;
      auto file_text = sim::read_file(path, &error);
      if (!file_text) {
        errors += path + ": error: " + error + " (the watchpoint file)\n";
        continue;
      }
      text = std::move(*file_text);
      source_name = path;
      if (name.empty()) {
        // A file named watch.txt is named by its folder, as in the conformance cases.
        const std::filesystem::path p(path);
        name = p.stem() == "watch" && p.has_parent_path() ? p.parent_path().filename().string() : p.stem().string();
        if (!watch::name_problem(name).empty()) name.clear();  // 12.watch: matches could not say "12"
      }
    }
    if (name.empty()) {
      name = "w" + std::to_string(i + 1);
      while (std::find(given.begin(), given.end(), name) != given.end()) name += "_";
    }
    // Matches and logs name a watchpoint by it, as the scenario loader refuses a second [[watch]]
    // of one name.
    if (const std::string twice = sim::second_name_problem(name, named); !twice.empty()) {
      errors += source_name + ":1:1: error: " + twice + "\n";
      continue;
    }
    sim::WatchSpec spec = reading;
    spec.name = name;
    spec.text = text;
    named.push_back(spec);
    auto compiled = sim::compile(spec, watch::SourceText(source_name, text));
    if (auto* e = std::get_if<watch::CompileError>(&compiled)) errors += e->format();
    else out.push_back(std::move(std::get<sim::HostedWatchpoint>(compiled)));
  }
  if (!errors.empty()) return errors;
  return out;
}

}  // namespace dw::app
