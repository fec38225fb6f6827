#include <simdjson.h>

#include <algorithm>
#include <cstring>
#include <tuple>
#include <unordered_map>

#include "sim/json_brackets.h"
#include "sim/read_file.h"
#include "sim/trace.h"
#include "watch/watchpoint.h"

namespace dw::sim {
namespace {

constexpr size_t kMaxErrors = 20;

class TraceReader {
 public:
  TraceReader(std::string name, const simdjson::padded_string& text) : name_(std::move(name)), text_(text) {}

  std::variant<Trace, std::vector<TraceError>> run() {
    const char* base = text_.data();
    const size_t size = text_.size();
    size_t at = 0;
    uint64_t line = 0;
    bool seen_content = false;
    entries_.reserve(static_cast<size_t>(std::count(base, base + size, '\n')) + 1);
    while (at < size && errors_.size() < kMaxErrors) {
      ++line;
      size_t end = std::find(base + at, base + size, '\n') - base;
      size_t len = end - at;
      if (len > 0 && base[at + len - 1] == '\r') --len;
      std::string_view text(base + at, len);
      if (text.find_first_not_of(" \t") != std::string_view::npos) {
        line_ = line;
        if (paused_) errors_.push_back({name_, line, 1, "a line after the {\"paused\":...} line, which ends a trace"});
        else parse_line(text, !seen_content);
        seen_content = true;
      }
      at = end + 1;
    }
    const bool stopped = errors_.size() >= kMaxErrors && at < size;
    check_paused();
    report_duplicates();
    if (errors_.size() > kMaxErrors) {
      const uint64_t next = errors_[kMaxErrors].line;
      errors_.resize(kMaxErrors);
      errors_.push_back({name_, next, 1, "too many errors; stopping here"});
    } else if (stopped) {
      errors_.push_back({name_, line, 1, "too many errors; stopping here"});
    }
    if (!errors_.empty()) return errors_;
    Trace trace = Trace::build(std::move(entries_), std::move(names_));
    trace.set_watches(std::move(watches_));
    trace.set_interventions(std::move(interventions_));
    trace.set_paused(std::move(paused_));
    return trace;
  }

 private:
  // Where a problem is: the line, and the key it concerns (searched for only when reporting, as
  // the DOM keeps no positions), from `from` on.
  struct Where {
    std::string_view line;
    std::string_view key;
    size_t from = 0;
  };

  void error(const Where& w, std::string message) {
    size_t col = w.key.empty() ? w.from : 0;  // no key: where the value it concerns starts
    if (!w.key.empty()) {
      const size_t at = w.line.find("\"" + std::string(w.key) + "\"", w.from);
      if (at != std::string_view::npos) col = at;
    }
    errors_.push_back({name_, line_, col + 1, std::move(message)});
  }

  // A JSON number that is an integer; 1.5, 1e3, true and "1" are not.
  bool integer(simdjson::dom::element v, int64_t& out, const Where& at, const std::string& what) {
    switch (v.type()) {
      case simdjson::dom::element_type::INT64: out = v.get_int64().value_unsafe(); return true;
      case simdjson::dom::element_type::UINT64:
        error(at, what + " does not fit in a signed 64-bit integer");
        return false;
      default: error(at, what + " must be an integer"); return false;
    }
  }

  // The last line of a run a pause stopped: {"paused":{"watch":"w","t":41}}.
  void read_paused(simdjson::dom::element v, const Where& at) {
    TracePause pause;
    std::string_view watch;
    simdjson::dom::object o;
    if (v.get_object().get(o) || o.size() != 2 || o["watch"].get_string().get(watch) || o["t"].get_int64().get(pause.t))
      return error(at, "\"paused\" is {\"watch\": NAME, \"t\": STEP}");
    if (pause.t < 0 || pause.t > kMaxStep)
      return error(at, "\"paused\" has a step out of 0.." + std::to_string(kMaxStep));
    // It names the watchpoint that paused the run: one of the header's, which precede it.
    if (std::none_of(watches_.begin(), watches_.end(), [&](const WatchSpec& w) { return w.name == watch; }))
      return error(at, "\"paused\" names the watchpoint '" + std::string(watch) +
                           "', which the header's \"watches\" does not hold");
    pause.watch = std::string(watch);
    paused_ = std::move(pause);
    // Its step is checked against the trace's last once every line is read (check_paused).
    paused_line_ = line_;
    paused_at_ = Where{at.line, "t", at.line.find("\"paused\"")};
  }

  // A pause stops a run at a step it has run: one the trace holds, as the frames before the
  // {"paused":...} line are that run's.
  void check_paused() {
    if (!paused_) return;
    const auto last = std::max_element(entries_.begin(), entries_.end(),
                                       [](const Trace::Entry& a, const Trace::Entry& b) { return a.t < b.t; });
    if (last != entries_.end() && paused_->t <= last->t) return;
    line_ = paused_line_;
    error(paused_at_, "\"paused\" names step " + std::to_string(paused_->t) +
                          (last == entries_.end() ? ", and the trace has no step"
                                                  : ", after the trace's last step, " + std::to_string(last->t)));
    // The lines before it may have errors too: the list stays in line order.
    std::rotate(std::upper_bound(errors_.begin(), errors_.end() - 1, errors_.back(),
                                 [](const TraceError& a, const TraceError& b) { return a.line < b.line; }),
                errors_.end() - 1, errors_.end());
  }

  // Where each object in the array opening at `open` starts: the DOM keeps no positions, and a
  // field of the second watch is searched for from where that watch starts.
  static std::vector<size_t> object_starts(std::string_view text, size_t open) {
    std::vector<size_t> starts;
    int depth = 0;
    for_each_bracket(text, open, [&](size_t i, char c) {
      if (c == ']' || c == '}') return --depth != 0;
      if (depth++ == 1 && c == '{') starts.push_back(i);
      return true;
    });
    return starts;
  }

  // Whether an entry's field `field.key` comes for the first time (`seen`: the entry's fields so
  // far). A second one is an error at it, searched for past the first.
  bool first_time(std::vector<std::string_view>& seen, const Where& field, const char* entry) {
    const std::string_view key = field.key;
    if (std::find(seen.begin(), seen.end(), key) == seen.end()) {
      seen.push_back(key);
      return true;
    }
    const size_t first_at = field.line.find("\"" + std::string(key) + "\"", field.from);
    error(Where{field.line, key, first_at + 1}, "duplicate field \"" + std::string(key) + "\" in " + entry);
    return false;
  }

  // The header's "interventions", as sim::intervention_json writes them: {"at": STEP, "module": ID,
  // and one of "set": {"VAR": N}, "remove": true, "push": [X, Y, Z]; "scheduled": true for a
  // scenario's own}. The frames carry their effects; a list that is not one says the header was
  // not written by a run.
  bool read_interventions(simdjson::dom::element v, const Where& at) {
    simdjson::dom::array list;
    if (v.get_array().get(list)) {
      error(at, "\"interventions\" must be an array");
      return false;
    }
    const char* form =
        "each of \"interventions\" is {\"at\": STEP, \"module\": ID, and \"set\": {\"VAR\": N}, \"remove\": true or "
        "\"push\": [X, Y, Z]}";
    const std::vector<size_t> starts = object_starts(at.line, at.line.find('[', at.line.find("\"interventions\"")));
    size_t index = 0;
    for (simdjson::dom::element item : list) {
      const size_t from = index < starts.size() ? starts[index] : 0;
      ++index;
      simdjson::dom::object o;
      if (item.get_object().get(o)) {
        error(at, form);
        return false;
      }
      std::vector<std::string_view> seen;
      int changes = 0;
      TraceIntervention& kept = interventions_.emplace_back();
      for (auto [key, value] : o) {
        const Where field{at.line, key, from};
        if (!first_time(seen, field, "an intervention")) return false;
        int64_t n = 0;
        simdjson::dom::object set;
        simdjson::dom::array push;
        if (key == "at") {
          if (!integer(value, n, field, "\"at\"")) return false;
          if (n < 0 || n > kMaxStep) {
            error(field, "\"at\" must be a step in 0.." + std::to_string(kMaxStep));
            return false;
          }
          kept.at = n;
        } else if (key == "module") {
          if (!integer(value, n, field, "\"module\"")) return false;
          if (n < 0 || n > UINT32_MAX) {
            error(field, "\"module\" must be in 0..4294967295");
            return false;
          }
          kept.module = static_cast<watch::ModuleId>(n);
        } else if (key == "set" || key == "remove" || key == "push") {
          ++changes;
          const bool ok = key == "set" ? !value.get_object().get(set) && set.size() == 1 &&
                                             (*set.begin()).value.type() == simdjson::dom::element_type::INT64
                          : key == "remove" ? value.is_bool() && value.get_bool().value_unsafe()
                                            : !value.get_array().get(push) && push.size() == 3 &&
                                                  std::all_of(push.begin(), push.end(),
                                                              [](simdjson::dom::element x) { return x.is_number(); });
          if (!ok) {
            error(field, form);
            return false;
          }
          kept.remove = key == "remove";
          if (key == "set") {
            kept.variable = std::string((*set.begin()).key);
            kept.value = (*set.begin()).value.get_int64().value_unsafe();
          }
        } else if (key == "scheduled") {
          if (!value.is_bool()) {
            error(field, "\"scheduled\" must be true or false");
            return false;
          }
          kept.scheduled = value.get_bool().value_unsafe();
        } else {
          error(field,
                "unknown field \"" + std::string(key) +
                    "\" in an intervention (it has \"at\", \"module\", \"set\", \"remove\", \"push\", \"scheduled\")");
          return false;
        }
      }
      if (changes != 1 || std::find(seen.begin(), seen.end(), "at") == seen.end() ||
          std::find(seen.begin(), seen.end(), "module") == seen.end()) {
        error(Where{at.line, {}, from}, form);
        return false;
      }
    }
    return true;
  }

  // The header's "watches": objects of a WatchSpec's six strings (sim::to_json), each reading and
  // action one the scenario loader accepts (its names), the names given and each once.
  bool read_watches(simdjson::dom::element v, const Where& at) {
    simdjson::dom::array list;
    if (v.get_array().get(list)) {
      error(at, "\"watches\" must be an array of watchpoints");
      return false;
    }
    if (list.size() > watch::kMaxWatchpoints) {
      error(at, "\"watches\" holds at most " + std::to_string(watch::kMaxWatchpoints) + " watchpoints, not " +
                    std::to_string(list.size()));
      return false;
    }
    const std::vector<size_t> starts = object_starts(at.line, at.line.find('[', at.line.find("\"watches\"")));
    size_t index = 0;
    for (simdjson::dom::element item : list) {
      const Where entry{at.line, {}, index < starts.size() ? starts[index] : 0};
      ++index;
      simdjson::dom::object o;
      if (item.get_object().get(o)) {
        error(at, "each of \"watches\" must be an object");
        return false;
      }
      auto field_at = [&](std::string_view key) { return Where{at.line, key, entry.from}; };
      std::vector<std::string_view> seen;
      for (auto [key, value] : o) {
        if (!first_time(seen, field_at(key), "a watch of \"watches\"")) return false;
        const std::string_view name = key;  // clang 14 captures no structured binding
        if (std::none_of(std::begin(kJsonKeys), std::end(kJsonKeys), [&](std::string_view k) { return name == k; })) {
          std::string known;
          for (std::string_view k : kJsonKeys) known += (known.empty() ? "\"" : ", \"") + std::string(k) + "\"";
          error(field_at(key),
                "unknown field \"" + std::string(key) + "\" in a watch of \"watches\" (a watch has " + known + ")");
          return false;
        }
      }
      // Its strings, each once, read as every watchpoint's JSON is (a value that is not one is
      // left out: the reader says it is missing).
      nlohmann::json strings = nlohmann::json::object();
      for (std::string_view key : kJsonKeys)
        if (std::string_view value; !o[key].get_string().get(value)) strings[std::string(key)] = value;
      auto read = spec_from_json(strings, watches_);
      if (const auto* bad = std::get_if<SpecError>(&read)) {
        if (bad->missing) error(at, "each of \"watches\" needs the string \"" + bad->key + "\"");
        else error(field_at(bad->key), bad->why);
        return false;
      }
      watches_.push_back(std::move(std::get<WatchSpec>(read)));
    }
    return true;
  }

  // "recv":[{"from":ID,"sent":STEP,"words":[W...]}...]: what the module read at the line's step.
  bool read_recv(simdjson::dom::element v, const Where& at, std::vector<Trace::Received>& recv) {
    const char* form = "\"recv\" must be an array of {\"from\":ID,\"sent\":STEP,\"words\":[...]}";
    simdjson::dom::array list;
    if (v.get_array().get(list)) return error(at, form), false;
    for (simdjson::dom::element item : list) {
      simdjson::dom::object message;
      if (item.get_object().get(message) || message.size() != 3) return error(at, form), false;
      Trace::Received r;
      int64_t from = 0;
      simdjson::dom::array words;
      if (message["from"].error() || message["sent"].error() || message["words"].get_array().get(words))
        return error(at, form), false;
      if (!integer(message["from"].value_unsafe(), from, at, "a message's \"from\"") ||
          !integer(message["sent"].value_unsafe(), r.sent, at, "a message's \"sent\""))
        return false;
      if (from < 0 || from > UINT32_MAX) return error(at, "a message's \"from\" must be in 0..4294967295"), false;
      if (r.sent < 0 || r.sent > kMaxStep)
        return error(at, "a message's \"sent\" must be a step in 0.." + std::to_string(kMaxStep)), false;
      r.from = static_cast<uint32_t>(from);
      for (simdjson::dom::element w : words) {
        int64_t x = 0;
        if (!integer(w, x, at, "a message's word")) return false;
        r.words.push_back(x);
      }
      recv.push_back(std::move(r));
    }
    return true;
  }

  // Parses one line in place; the text after it in the padded buffer is simdjson's padding.
  void parse_line(std::string_view text, bool first) {
    simdjson::dom::element doc;
    if (auto err = parser_.parse(text.data(), text.size(), false).get(doc))
      return error(Where{text, {}, 0}, std::string("malformed JSON: ") + simdjson::error_message(err));
    simdjson::dom::object obj;
    if (doc.get_object().get(obj)) return error(Where{text, {}, 0}, "expected a JSON object");

    Trace::Entry e;
    bool has_t = false, has_m = false, has_vars = false, has_nbrs = false, header = false;
    for (auto [key, v] : obj) {
      const Where at{text, key, 0};
      if (key == "paused") {
        if (obj.size() != 1) return error(at, "the {\"paused\":...} line holds nothing else");
        return read_paused(v, at);
      }
      if (key == "wptrace") {
        int64_t version;
        if (!first) return error(at, "the {\"wptrace\":1} header may only be the first line");
        if (!integer(v, version, at, "\"wptrace\"")) return;
        if (version != 1)
          return error(at, "unsupported trace version " + std::to_string(version) + " (this reader reads wptrace 1)");
        header = true;
      } else if (key == "interventions") {
        // Provenance (docs/design.md §7): how the run was made. The frames already carry its effects.
        if (!first) return error(at, "\"interventions\" belongs to the header, the first line");
        if (!read_interventions(v, at)) return;
        header = true;
      } else if (key == "watches") {
        if (!first) return error(at, "\"watches\" belongs to the header, the first line");
        if (!read_watches(v, at)) return;
        header = true;
      } else if (key == "t") {
        if (has_t) return error(at, "duplicate field \"t\"");
        if (!integer(v, e.t, at, "step \"t\"")) return;
        if (e.t < 0) return error(at, "step \"t\" is negative");
        if (e.t > kMaxStep) return error(at, "step \"t\" is beyond " + std::to_string(kMaxStep));
        has_t = true;
      } else if (key == "m") {
        if (has_m) return error(at, "duplicate field \"m\"");
        int64_t m;
        if (!integer(v, m, at, "module id \"m\"")) return;
        if (m < 0 || m > UINT32_MAX) return error(at, "module id \"m\" must be in 0..4294967295");
        e.m = static_cast<uint32_t>(m);
        has_m = true;
      } else if (key == "vars") {
        if (has_vars) return error(at, "duplicate field \"vars\"");
        simdjson::dom::object vars;
        if (v.get_object().get(vars)) return error(at, "\"vars\" must be an object of integer variables");
        const size_t vars_at = text.find("\"vars\"");  // where a variable's key is searched from
        for (auto [name, value] : vars) {
          const Where var_at{text, name, vars_at};
          const uint32_t index = intern(name);
          // A variable seen twice on one line: its stamp is already this line's.
          if (seen_on_line_[index] == line_) return error(var_at, "variable '" + std::string(name) + "' appears twice");
          seen_on_line_[index] = line_;
          int64_t x;
          if (!integer(value, x, var_at, "variable '" + std::string(name) + "'")) return;
          e.vars.emplace_back(index, x);
        }
        has_vars = true;
      } else if (key == "nbrs") {
        if (has_nbrs) return error(at, "duplicate field \"nbrs\"");
        simdjson::dom::array nbrs;
        if (v.get_array().get(nbrs)) return error(at, "\"nbrs\" must be an array of module ids");
        for (simdjson::dom::element item : nbrs) {
          int64_t n;
          if (!integer(item, n, at, "neighbour id")) return;
          if (n < 0 || n > UINT32_MAX) return error(at, "neighbour id must be in 0..4294967295");
          e.nbrs.push_back(static_cast<uint32_t>(n));
        }
        has_nbrs = true;
      } else if (key == "recv") {
        if (e.has_recv) return error(at, "duplicate field \"recv\"");
        if (!read_recv(v, at, e.recv)) return;
        e.has_recv = true;
      } else if (first &&
                 (obj["wptrace"].error() == simdjson::SUCCESS || obj["interventions"].error() == simdjson::SUCCESS ||
                  obj["watches"].error() == simdjson::SUCCESS)) {
        // A header's field misspelt: the fields it may have, not a frame line's.
        return error(at, "unknown field \"" + std::string(key) +
                             "\" (the header has \"wptrace\", \"interventions\", \"watches\")");
      } else {
        return error(at, "unknown field \"" + std::string(key) + "\" (a line has \"t\", \"m\", \"vars\", \"nbrs\")");
      }
    }
    if (header) {
      if (has_t || has_m || has_vars || has_nbrs || e.has_recv)
        return error(Where{text, {}, 0}, "the header line holds only \"wptrace\", \"interventions\" and \"watches\"");
      return;
    }
    std::string missing;
    for (auto [has, name] :
         {std::pair{has_t, "\"t\""}, {has_m, "\"m\""}, {has_vars, "\"vars\""}, {has_nbrs, "\"nbrs\""}})
      if (!has) missing += (missing.empty() ? "" : ", ") + std::string(name);
    if (!missing.empty()) return error(Where{text, {}, 0}, "missing field " + missing);
    if (std::find(e.nbrs.begin(), e.nbrs.end(), e.m) != e.nbrs.end())
      return error(Where{text, {}, 0}, "module " + std::to_string(e.m) + " lists itself as a neighbour");
    std::vector<uint32_t> sorted = e.nbrs;
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
      return error(Where{text, {}, 0}, "a neighbour appears twice in \"nbrs\"");
    e.line = line_;
    entries_.push_back(std::move(e));
  }

  // Two lines for one module at one step, found once the lines are sorted by (step, module, line):
  // a table of every (step, module) seen took more memory than the lines' text.
  void report_duplicates() {
    std::sort(entries_.begin(), entries_.end(), [](const Trace::Entry& a, const Trace::Entry& b) {
      return a.t != b.t ? a.t < b.t : a.m != b.m ? a.m < b.m : a.line < b.line;
    });
    const size_t before = errors_.size();
    for (size_t i = 1; i < entries_.size(); ++i) {
      const Trace::Entry &first = entries_[i - 1], &e = entries_[i];
      if (e.t != first.t || e.m != first.m) continue;
      size_t k = i - 1;
      while (k > 0 && entries_[k - 1].t == e.t && entries_[k - 1].m == e.m) --k;  // the first of them
      errors_.push_back({name_, e.line, 1,
                         "duplicate line for module " + std::to_string(e.m) + " at step " + std::to_string(e.t) +
                             " (first at line " + std::to_string(entries_[k].line) + ")"});
    }
    std::sort(errors_.begin() + ptrdiff_t(before), errors_.end(),
              [](const TraceError& a, const TraceError& b) { return a.line < b.line; });
    std::inplace_merge(errors_.begin(), errors_.begin() + ptrdiff_t(before), errors_.end(),
                       [](const TraceError& a, const TraceError& b) { return a.line < b.line; });
  }

  // The variable's index, in order of first appearance: a hash lookup, so that a line or a trace
  // naming a million variables reads in linear time.
  uint32_t intern(std::string_view name) {
    const auto [it, inserted] = index_.try_emplace(std::string(name), static_cast<uint32_t>(names_.size()));
    if (inserted) {
      names_.emplace_back(name);
      seen_on_line_.push_back(0);
    }
    return it->second;
  }

  static constexpr int64_t kMaxStep = Trace::kMaxStep;

  std::string name_;
  const simdjson::padded_string& text_;
  simdjson::dom::parser parser_;
  std::vector<Trace::Entry> entries_;
  std::vector<WatchSpec> watches_;
  std::vector<TraceIntervention> interventions_;
  std::optional<TracePause> paused_;
  uint64_t paused_line_ = 0;
  Where paused_at_;
  std::vector<TraceError> errors_;
  std::vector<std::string> names_;
  std::unordered_map<std::string, uint32_t> index_;  // name -> index into names_
  std::vector<uint64_t> seen_on_line_;               // per variable: the last line naming it
  uint64_t line_ = 0;
};

}  // namespace

std::string TraceError::format() const {
  if (line == 0) return file + ": error: " + message;
  return file + ":" + std::to_string(line) + ":" + std::to_string(column) + ": error: " + message;
}

std::variant<Trace, std::vector<TraceError>> read_trace_text(const std::string& name, const std::string& text) {
  simdjson::padded_string padded(text);
  return TraceReader(name, padded).run();
}

size_t trace_limit() {
  // The text (held once, in its padded buffer) and what is read from it must fit in what the
  // machine has free: reading a trace of short lines peaks at about four times its size (a
  // 1.8 GB trace of 40 million lines: 7.1 GB).
  const size_t available = available_memory();
  return available > 0 ? available / 5 : size_t(2) << 30;
}

std::variant<Trace, std::vector<TraceError>> read_trace(const std::string& path) {
  std::string error;
  std::optional<ReadBlocks> read = read_file_blocks(path, &error, trace_limit());
  if (!read) return std::vector<TraceError>{{path, 0, 0, error}};
  // Joined straight into simdjson's padded buffer, each block let go once copied.
  simdjson::padded_string padded(read->size);
  size_t at = 0;
  for (std::string& block : read->blocks) {
    std::memcpy(padded.data() + at, block.data(), block.size());
    at += block.size();
    std::string().swap(block);
  }
  return TraceReader(path, padded).run();
}

}  // namespace dw::sim
