#include "shell/protocol.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <functional>
#include <iostream>
#include <memory>
#include <mutex>
#include <optional>
#include <stop_token>
#include <thread>

#include "shell/utf8_text.h"
#include "sim/json_brackets.h"
#include "watch/diagnostic.h"

namespace dw::shell {
namespace {

using Json = nlohmann::ordered_json;

// One request as read: its id (null when none was given) and its command line, or why it could
// not be read.
struct Request {
  std::optional<Json> id;  // as given (null included): a string or an integer
  uint32_t number = 0;     // its place among the requests taken (cancels apart), from 1
  std::string line;
  std::string unreadable;    // a line too long, JSON that is not a request, bytes that are not UTF-8
  size_t unreadable_at = 0;  // the byte of the line the reason is at
  bool json = false;         // {"cmd": ...}: always answered, even when its command is blank
  bool end = false;          // the input ended
  std::stop_source stop;     // asked by `cancel`, queued or while it runs

  // Whether it asks something, and is answered: not the end of the input, nor a plain blank or
  // `#` comment line.
  bool asks() const {
    if (end) return false;
    if (json || !unreadable.empty()) return true;
    const size_t first = line.find_first_not_of(" \t\r");
    return first != std::string::npos && line[first] != '#';
  }
};

// Answers go out whole and in one piece from the reader (cancel) and the runner alike.
class AnswerWriter {
 public:
  explicit AnswerWriter(std::ostream& out) : out_(out) {}
  void write(const std::optional<Json>& id, Json body) {
    Json line;
    if (id) line["id"] = *id;  // only when the request gave one
    for (auto it = body.begin(); it != body.end(); ++it) line[it.key()] = std::move(it.value());
    std::lock_guard lock(mutex_);
    out_ << answer_line(line) << "\n" << std::flush;
    if (!out_) failed_ = true;
  }
  // Whether an answer could not be written (standard output a closed pipe or a full disk): no
  // later one can reach the controller either, and the session ends.
  bool failed() {
    std::lock_guard lock(mutex_);
    return failed_;
  }

 private:
  std::ostream& out_;
  std::mutex mutex_;
  bool failed_ = false;
};

// nlohmann reads and writes nested arrays by recursion: an id 100,000 arrays deep, echoed back,
// overflowed the stack. A request is refused past this depth, counted before it is parsed.
constexpr size_t kMaxRequestDepth = 64;
size_t json_depth(std::string_view text) {
  size_t depth = 0, deepest = 0;
  sim::for_each_bracket(text, 0, [&](size_t, char c) {
    if (c == '[' || c == '{') deepest = std::max(deepest, ++depth);
    else if (depth > 0) --depth;
    return true;
  });
  return deepest;
}

// The id of a request that could not be read whole, when its top-level object gives a usable one
// (a string, an integer or null) before whatever went wrong: its error then carries it, for the
// controller to match. Nested values are skipped as they are read, never kept.
std::optional<Json> readable_id(std::string_view text) {
  std::optional<Json> id;
  bool next_is_id = false;
  const Json kept = Json::parse(  // nothing but the top-level object's scalars: the id is taken as read
      text,
      [&](int depth, Json::parse_event_t event, Json& parsed) {
        if (depth != 1) return true;  // the top-level object itself, or inside a value already skipped
        if (event == Json::parse_event_t::key) {
          next_is_id = !id && parsed == "id";
        } else if (next_is_id) {
          next_is_id = false;
          if (event == Json::parse_event_t::value &&
              (parsed.is_string() || parsed.is_number_integer() || parsed.is_null()))
            id = parsed;
        }
        return event != Json::parse_event_t::object_start && event != Json::parse_event_t::array_start;
      },
      /*allow_exceptions=*/false);
  return id;
}

Request parse_request(std::string line) {
  Request r;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  // A request is UTF-8 text, its JSON too: a byte that is not would reach the answers (an unknown
  // command is echoed), and a file name of it names nothing a user can type.
  if (const auto at = watch::first_non_utf8(line)) {
    char byte[8];
    std::snprintf(byte, sizeof byte, "0x%02X", unsigned(uint8_t(line[*at])));
    r.unreadable = std::string("a request is UTF-8 text: the byte ") + byte + " at column " + std::to_string(*at + 1) +
                   " is not part of a UTF-8 character";
    r.unreadable_at = *at;
    r.id = readable_id(std::string_view(line).substr(0, *at));
    return r;
  }
  const size_t first = line.find_first_not_of(" \t");
  if (first == std::string::npos || line[first] != '{') {
    r.line = std::move(line);
    return r;
  }
  if (json_depth(line) > kMaxRequestDepth) {
    r.unreadable = "a request nests arrays and objects more than " + std::to_string(kMaxRequestDepth) + " deep";
    r.id = readable_id(line);
    return r;
  }
  // nlohmann keeps the last of two equal keys: {"cmd": "step 1", "cmd": "step 3"} would run one
  // of them unsaid, so a key seen twice in an object (the keys of each open object, innermost
  // last) refuses the request.
  std::vector<std::vector<std::string>> keys;
  std::string twice;
  const Json j = Json::parse(
      line,
      [&](int, Json::parse_event_t event, Json& parsed) {
        if (event == Json::parse_event_t::object_start) keys.emplace_back();
        else if (event == Json::parse_event_t::object_end) keys.pop_back();
        else if (event == Json::parse_event_t::key && twice.empty()) {
          const std::string key = parsed.get<std::string>();
          if (std::find(keys.back().begin(), keys.back().end(), key) != keys.back().end()) twice = key;
          else keys.back().push_back(key);
        }
        return true;
      },
      /*allow_exceptions=*/false);
  // An id is echoed as given: a string, an integer or null. A number with a fraction or past 64
  // bits (read as a double) would come back rounded, and the reader could not match it.
  const bool usable_id =
      j.is_object() && j.contains("id") && (j["id"].is_string() || j["id"].is_number_integer() || j["id"].is_null());
  if (usable_id) r.id = j["id"];
  if (j.is_discarded() || !j.is_object() || !j.contains("cmd") || !j["cmd"].is_string()) {
    if (!r.id && j.is_discarded()) r.id = readable_id(line);
    r.unreadable = "a request is a command line, or a JSON object {\"id\": ..., \"cmd\": \"COMMAND LINE\"}";
    return r;
  }
  r.json = true;
  if (!twice.empty()) {
    r.unreadable = "a request gives the key \"" + twice + "\" twice";
    return r;
  }
  if (j.contains("id") && !usable_id) {
    r.unreadable = "a request's id is a string or an integer of at most 64 bits, not " + j["id"].dump();
    return r;
  }
  r.line = j["cmd"].get<std::string>();
  if (r.line.find('\n') != std::string::npos) r.unreadable = "a request's command is one line";
  return r;
}

bool is_cancel(const std::string& line) {
  const size_t b = line.find_first_not_of(" \t"), e = line.find_last_not_of(" \t\r");
  return b != std::string::npos && line.substr(b, e - b + 1) == "cancel";
}

// Requests read and not yet taken by the runner are kept to these, the most a controller sending
// one at a time ever needs many times over: past them a request is refused at once, never kept
// (`yes hash | dwatch session X --protocol` held 7.6 GB in 40 s).
constexpr size_t kMaxWaitingRequests = 1024;
constexpr size_t kMaxWaitingBytes = size_t{64} << 20;

// The requests read and not yet answered, shared by the reader and the runner.
struct Requests {
  std::mutex mutex;
  std::condition_variable ready;
  std::deque<Request> queue;
  size_t queued_bytes = 0;                  // of the queued requests' lines
  uint32_t taken = 0;                       // requests numbered so far
  std::optional<std::stop_source> running;  // the request under way's, for `cancel`
};

// A request as the reader takes it: `cancel` acted on at once, anything else queued. A cancel
// stops the oldest request not yet answered nor already told to stop: the one under way, or,
// when the runner has not taken it yet, the first queued (sent together, `run 1000000` and
// `cancel` reach the reader before the runner starts the run; a cancel then found nothing
// running and was lost). A request past what may wait is answered with an error at once.
void take(Request r, Requests& requests, AnswerWriter& answers) {
  if (r.unreadable.empty() && is_cancel(r.line)) {
    std::lock_guard lock(requests.mutex);
    bool stopped = requests.running && requests.running->request_stop();
    for (auto q = requests.queue.begin(); !stopped && q != requests.queue.end(); ++q)
      if (q->asks()) stopped = q->stop.request_stop();
    answers.write(r.id, {{"cmd", "cancel"}, {"cancelled", stopped}});
    return;
  }
  std::string refused;
  {
    std::lock_guard lock(requests.mutex);
    r.number = ++requests.taken;
    if (requests.queue.size() < kMaxWaitingRequests && requests.queued_bytes + r.line.size() <= kMaxWaitingBytes) {
      requests.queued_bytes += r.line.size();
      requests.queue.push_back(std::move(r));
      requests.ready.notify_one();
      return;
    }
    if (r.asks())
      refused = "refused: " + std::to_string(requests.queue.size()) + " requests (" +
                std::to_string(requests.queued_bytes) + " bytes) already wait to be answered, at most " +
                std::to_string(kMaxWaitingRequests) + " (" + std::to_string(kMaxWaitingBytes >> 20) +
                " MiB) may: send more as answers come";
  }
  if (!refused.empty()) answers.write(r.id, {{"error", {{"line", r.number}, {"col", 1}, {"message", refused}}}});
}

// The reader: lines as they come (the runner may be busy), each taken at once, then the end of
// the input queued.
void read_requests(int in_fd, Requests& requests, AnswerWriter& answers) {
  std::string line;
  bool too_long = false;
  char buffer[65536];
  for (;;) {
    const ssize_t n = ::read(in_fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0 || answers.failed()) break;  // no answer could reach anyone: read no more
    for (ssize_t i = 0; i < n; ++i) {
      if (buffer[i] != '\n') {
        if (too_long) continue;
        if (line.size() < kMaxRequestBytes) {
          line += buffer[i];
          continue;
        }
        // Answered when it goes over, not at its newline, which an endless input (/dev/zero)
        // never sends; the rest of it, to its newline, is skipped.
        too_long = true;
        line = std::string();
        take(Request{.unreadable = "a request longer than " + std::to_string(kMaxRequestBytes) + " bytes"}, requests,
             answers);
        continue;
      }
      if (!too_long) take(parse_request(std::move(line)), requests, answers);
      line.clear();
      too_long = false;
    }
  }
  if (!line.empty()) take(parse_request(std::move(line)), requests, answers);
  std::lock_guard lock(requests.mutex);
  requests.queue.push_back(Request{.end = true});
  requests.ready.notify_one();
}

// Parses and carries out request r, and answers it. The signal that ended the session
// meanwhile, if one did.
std::optional<int> answer_request(Shell& shell, Request& r, Requests& requests, AnswerWriter& answers,
                                  Interrupts* interrupts) {
  const uint32_t number = r.number;
  // Every answer but progress: the request is no longer under way once it is answered.
  const auto reply = [&](Json body) {
    {
      std::lock_guard lock(requests.mutex);
      requests.running.reset();
    }
    answers.write(r.id, std::move(body));
  };
  const auto fail = [&](int64_t col, const std::string& message) {
    reply({{"error", {{"line", number}, {"col", col}, {"message", message}}}});
  };
  if (r.stop.stop_requested()) {
    fail(1, "cancelled before it ran");
    return std::nullopt;
  }
  if (!r.unreadable.empty()) {
    fail(static_cast<int64_t>(r.unreadable_at) + 1, r.unreadable);
    return std::nullopt;
  }
  const watch::SourceText source("request " + std::to_string(number), r.line);
  auto parsed = shell.parse(source, 0, number);
  if (auto* mistakes = std::get_if<std::vector<watch::Diagnostic>>(&parsed)) {
    const watch::Diagnostic& d = mistakes->front();  // one mistake, one message: the first
    reply({{"error",
            {{"line", number},
             {"col", d.span.begin + 1},
             {"message", d.message},
             {"text", watch::format_diagnostics(source, {d})}}}});
    return std::nullopt;
  }
  const std::optional<Command>& command = std::get<std::optional<Command>>(parsed);
  if (!command) {
    // A blank or comment line is no request; a JSON one is, and its controller waits for the answer.
    if (r.json) fail(1, "a request's command is empty (blank, or a # comment)");
    return std::nullopt;
  }

  std::optional<Interrupts::Stoppable> stoppable;
  std::optional<std::stop_callback<std::function<void()>>> on_signal;
  if (interrupts) {
    stoppable.emplace(*interrupts);
    on_signal.emplace(stoppable->token(), std::function<void()>([&r] { r.stop.request_stop(); }));
  }
  auto last = std::chrono::steady_clock::now();
  const sim::Control control{.stop = r.stop.get_token(), .progress = [&](int64_t done, int64_t total) {
                               const auto now = std::chrono::steady_clock::now();
                               if (now - last < std::chrono::milliseconds(100)) return;
                               last = now;
                               answers.write(r.id, {{"progress", {{"done", done}, {"total", total}}}});
                             }};
  auto answer = shell.execute(*command, control);
  if (auto* error = std::get_if<std::string>(&answer)) fail(1, *error);
  else reply(std::move(std::get<Json>(answer)));
  on_signal.reset();
  if (stoppable) {
    if (const auto signal = stoppable->signal()) {
      std::cerr << "dwatch session: " << Interrupts::name(*signal) << ": the session ends\n";
      return Interrupts::exit_code(*signal);
    }
  }
  return std::nullopt;
}

}  // namespace

int run_protocol(Shell& shell, int in_fd, std::ostream& out, Interrupts* interrupts) {
  // Shared with the reader, which may outlive this function: when the session ends early (a
  // signal, answers that cannot be written) it is left reading, and must not touch what is gone.
  struct Shared {
    explicit Shared(std::ostream& out) : answers(out) {}
    AnswerWriter answers;
    Requests requests;
  };
  const auto shared = std::make_shared<Shared>(out);
  AnswerWriter& answers = shared->answers;
  Requests& requests = shared->requests;
  // Taking a request from the queue and marking it under way is one step under the lock, so a
  // request is always one or the other until it is answered.
  std::jthread reader([shared, in_fd] { read_requests(in_fd, shared->requests, shared->answers); });
  for (;;) {
    Request r;
    {
      std::unique_lock lock(requests.mutex);
      requests.ready.wait(lock, [&] { return !requests.queue.empty(); });
      r = std::move(requests.queue.front());
      requests.queue.pop_front();
      requests.queued_bytes -= r.line.size();
      if (r.asks()) requests.running = r.stop;
    }
    if (r.end) break;
    std::optional<int> code = answer_request(shell, r, requests, answers, interrupts);
    if (!code && answers.failed()) code = 1;  // the caller says why: standard output has failed
    if (code) {
      reader.detach();  // blocked reading the input, which nothing else will read
      return *code;
    }
  }
  return answers.failed() ? 1 : 0;
}

}  // namespace dw::shell
