// libFuzzer target for the session's protocol layer (shell/protocol.h, docs/session.md "The
// protocol"): any bytes are the standard input of `dwatch session X --protocol`, read by
// run_protocol as it reads them (its reader thread, parse_request, the queue, `cancel`, the
// answers), on a small scenario. session_fuzz fuzzes the commands themselves; this one fuzzes what
// wraps them: JSON requests and plain lines, ids of every kind, bytes that are not UTF-8, nesting,
// keys given twice, blank and comment lines, cancels. Beyond "no crash, no hang, no sanitizer
// report", it checks what a controller relies on:
//   - the session ends with exit 0 at the end of its input;
//   - every answer is one line of UTF-8 JSON, an object that is a command's answer (its "cmd"),
//     an error with its line and message, or progress;
//   - an id is echoed as a string, an integer or null, never anything else;
//   - there are never more answers than requests (a line is a request; the last may have no newline).
//
// Budget, so that one input stays in the milliseconds: every command a request would run is
// parsed first, as the protocol will parse it (a JSON request's "cmd", else the line); an input is
// skipped when one of them would simulate more than kMaxSteps steps in all, or is one of the
// commands that write files, draw, evaluate a watchpoint over the history or reload (session_fuzz
// fuzzes those). A request the protocol refuses before parsing it runs nothing.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "scenarios/scenario.h"
#include "shell/options.h"
#include "shell/protocol.h"
#include "shell/shell.h"
#include "tests/fuzz/small_scenarios.h"
#include "watch/diagnostic.h"

namespace {

using dw::shell::Command;
using Kind = Command::Kind;
using Json = nlohmann::json;

constexpr int64_t kMaxSteps = 64;

// The token ring of the session's fuzz scenarios.
constexpr const char* kScenario = dw::fuzz::kScenarios[0].toml;

[[noreturn]] void fail(const char* what, const std::string& detail = "") {
  std::fprintf(stderr, "protocol_fuzz: %s%s%s\n", what, detail.empty() ? "" : ": ", detail.c_str());
  __builtin_trap();
}

dw::scenarios::Scenario& scenario() {
  static std::optional<dw::scenarios::Scenario> loaded;
  if (!loaded) {
    auto made = dw::scenarios::load_scenario_text("fuzz_protocol.toml", kScenario);
    if (auto* errors = std::get_if<std::string>(&made)) fail("the scenario does not load", *errors);
    loaded.emplace(std::get<dw::scenarios::Scenario>(std::move(made)));
  }
  return *loaded;
}

std::vector<std::string> lines_of(std::string_view text) {
  std::vector<std::string> lines;
  for (size_t begin = 0; begin < text.size();) {
    const size_t newline = text.find('\n', begin);
    const size_t end = newline == std::string_view::npos ? text.size() : newline;
    lines.emplace_back(text.substr(begin, end - begin));
    begin = end + 1;
  }
  return lines;
}

// The command line a request would run: a JSON request's "cmd" (the last, as nlohmann keeps it),
// else the line itself.
std::string command_of(const std::string& line) {
  const size_t first = line.find_first_not_of(" \t");
  if (first == std::string::npos || line[first] != '{') return line;
  const Json j = Json::parse(line, nullptr, /*allow_exceptions=*/false);
  if (j.is_object() && j.contains("cmd") && j["cmd"].is_string()) return j["cmd"].get<std::string>();
  return "";
}

// Whether every command the input's requests would run fits the budget.
bool fits_budget(dw::shell::Shell& shell, std::string_view input) {
  int64_t steps = 0;
  for (const std::string& line : lines_of(input)) {
    const std::string cmd = command_of(line);
    if (cmd.empty() || cmd.find('\n') != std::string::npos) continue;
    const dw::watch::SourceText source("request", cmd);
    auto parsed = shell.parse(source, 0, 1);
    const auto* command = std::get_if<std::optional<Command>>(&parsed);
    if (!command || !*command) continue;
    const Command& c = **command;
    int64_t asked = 0;  // at most what the command simulates
    switch (c.kind) {
      case Kind::Step: asked = c.number.value_or(1); break;
      case Kind::Run: asked = c.number.value_or(24); break;
      case Kind::Continue: asked = 24; break;
      case Kind::Why:
        if (!c.why || c.why->depth > 8) return false;
        asked = c.why->t ? *c.why->t : 24;
        break;
      case Kind::Render:
      case Kind::Record:
      case Kind::Save:
      case Kind::Watch:
      case Kind::Reload: return false;
      default: break;
    }
    if (asked < 0 || asked > kMaxSteps || (steps += asked) > kMaxSteps) return false;
  }
  return true;
}

bool is_utf8(std::string_view text) { return !dw::watch::first_non_utf8(text); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  namespace sim = dw::sim;
  const std::string input(reinterpret_cast<const char*>(data), size);
  dw::scenarios::Scenario& loaded = scenario();
  sim::SessionOptions options = dw::shell::session_options(loaded, {});
  options.threads = 1;
  options.history_bytes = size_t{16} << 10;  // keyframes thinned within the few steps an input runs
  sim::Session session(*loaded.model, *loaded.world, options);
  dw::shell::Shell shell(loaded, session);
  if (!fits_budget(shell, input)) return 0;

  // The input on a pipe, as a controller writes it (max_len is far under a pipe's 64 KiB).
  int fds[2];
  if (::pipe(fds) != 0) fail("pipe");
  for (size_t done = 0; done < input.size();) {
    const ssize_t n = ::write(fds[1], input.data() + done, input.size() - done);
    if (n <= 0) fail("writing the input to the pipe");
    done += static_cast<size_t>(n);
  }
  ::close(fds[1]);
  std::ostringstream out;
  const int code = dw::shell::run_protocol(shell, fds[0], out, nullptr);
  ::close(fds[0]);
  if (code != 0) fail("the end of the input ends the session with exit 0, not", std::to_string(code));

  const std::string answers = out.str();
  if (!answers.empty() && answers.back() != '\n') fail("the last answer does not end its line");
  size_t count = 0;
  for (const std::string& line : lines_of(answers)) {
    if (!is_utf8(line)) fail("an answer is not UTF-8", line);
    const Json a = Json::parse(line, nullptr, /*allow_exceptions=*/false);
    if (!a.is_object()) fail("an answer is not a JSON object", line);
    if (a.contains("id") && !a["id"].is_string() && !a["id"].is_number_integer() && !a["id"].is_null())
      fail("an answer's id is not a string, an integer or null", line);
    if (a.contains("progress")) continue;
    ++count;
    if (a.contains("error")) {
      const Json& e = a["error"];
      if (!e.is_object() || !e.contains("line") || !e.contains("message") || !e["message"].is_string())
        fail("an error answer lacks its line or message", line);
    } else if (!a.contains("cmd")) {
      fail("an answer is neither a command's nor an error", line);
    }
  }
  if (count > lines_of(input).size()) fail("more answers than requests", answers);
  return 0;
}
