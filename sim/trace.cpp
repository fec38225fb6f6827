#include "sim/trace.h"

#include "sim/read_file.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <unordered_map>

namespace dw::sim {

namespace {

// Dense indices for module ids: every id that `each_id` visits (calling back for each), ascending,
// in `ids`. A table when the ids are compact, a hash map otherwise.
class DenseIds {
 public:
  template <class EachId>
  DenseIds(watch::ModuleId largest, size_t lines, EachId&& each_id, std::vector<watch::ModuleId>& ids)
      : compact_(largest < 4 * lines + 1024) {
    if (compact_) {
      constexpr uint32_t kUnseen = UINT32_MAX;
      table_.assign(static_cast<size_t>(largest) + 1, kUnseen);
      each_id([&](watch::ModuleId m) { table_[m] = 0; });
      for (size_t m = 0; m < table_.size(); ++m)
        if (table_[m] != kUnseen) {
          table_[m] = static_cast<uint32_t>(ids.size());
          ids.push_back(static_cast<watch::ModuleId>(m));
        }
    } else {
      each_id([&](watch::ModuleId m) { ids.push_back(m); });
      std::sort(ids.begin(), ids.end());
      ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
      map_.reserve(ids.size());
      for (uint32_t i = 0; i < ids.size(); ++i) map_.emplace(ids[i], i);
    }
  }
  uint32_t operator()(watch::ModuleId m) const { return compact_ ? table_[m] : map_.at(m); }

 private:
  bool compact_;
  std::vector<uint32_t> table_;  // id -> dense index, when ids are compact
  std::unordered_map<watch::ModuleId, uint32_t> map_;
};

}  // namespace

std::pair<uint64_t, uint64_t> Trace::lines_at(int64_t t) const {
  const auto at = std::lower_bound(busy_steps_.begin(), busy_steps_.end(), t);
  if (at == busy_steps_.end() || *at != t) return {0, 0};
  const auto i = static_cast<size_t>(at - busy_steps_.begin());
  return {busy_begin_[i], busy_begin_[i + 1]};
}

std::optional<uint64_t> Trace::line_of(int64_t t, uint32_t m) const {
  const auto [first, last] = lines_at(t);
  const auto begin = line_module_.begin() + static_cast<ptrdiff_t>(first),
             end = line_module_.begin() + static_cast<ptrdiff_t>(last);
  const auto at = std::lower_bound(begin, end, m);
  if (at == end || *at != m) return std::nullopt;
  return static_cast<uint64_t>(at - line_module_.begin());
}

std::optional<int64_t> Trace::value(uint64_t line, uint32_t var) const {
  for (uint64_t k = value_begin_[line]; k < value_begin_[line + 1]; ++k)
    if (value_var_[k] == var) return value_[k];
  return std::nullopt;
}

std::vector<Trace::Read> Trace::received(uint64_t line) const {
  std::vector<Read> read;
  if (recv_begin_.empty()) return read;
  for (uint64_t k = recv_begin_[line]; k < recv_begin_[line + 1]; ++k)
    read.push_back({recv_from_[k],
                    recv_sent_[k],
                    {recv_words_.data() + recv_words_begin_[k], recv_words_begin_[k + 1] - recv_words_begin_[k]}});
  return read;
}

Trace Trace::build(std::vector<Entry> entries, std::vector<std::string> variable_names) {
  Trace trace;
  trace.universe_.variables = std::move(variable_names);
  int64_t last_step = -1;
  watch::ModuleId largest = 0;
  for (const Entry& e : entries) {
    largest = std::max(largest, e.m);
    for (watch::ModuleId n : e.nbrs) largest = std::max(largest, n);
    last_step = std::max(last_step, e.t);
  }
  // Every module that has a line or is someone's neighbour (it may never have a line of its own).
  const DenseIds dense(
      largest, entries.size(),
      [&](auto&& fn) {
        for (const Entry& e : entries) {
          fn(e.m);
          for (watch::ModuleId n : e.nbrs) fn(n);
          for (const Received& r : e.recv) fn(r.from);
        }
      },
      trace.universe_.module_ids);
  // Lines sorted by (step, module): each step's lines then come out in module order.
  std::sort(entries.begin(), entries.end(),
            [](const Entry& a, const Entry& b) { return a.t != b.t ? a.t < b.t : a.m < b.m; });
  // Only the steps with lines are indexed: a trace whose one line is at step 9,999,999 is small.
  trace.step_count_ = last_step + 1;
  std::vector<uint8_t> has_line(trace.universe_.module_ids.size(), 0);
  size_t values = 0, nbrs = 0;
  for (size_t i = 0; i < entries.size(); ++i) {
    if (i == 0 || entries[i].t != entries[i - 1].t) {
      trace.busy_steps_.push_back(entries[i].t);
      trace.busy_begin_.push_back(i);
    }
    values += entries[i].vars.size();
    nbrs += entries[i].nbrs.size();
  }
  trace.busy_begin_.push_back(entries.size());
  trace.line_module_.reserve(entries.size());
  trace.value_begin_.reserve(entries.size() + 1);
  trace.nbr_begin_.reserve(entries.size() + 1);
  trace.value_var_.reserve(values);
  trace.value_.reserve(values);
  trace.nbrs_.reserve(nbrs);
  const bool with_messages = std::any_of(entries.begin(), entries.end(), [](const Entry& e) { return e.has_recv; });
  if (with_messages) trace.recv_words_begin_.push_back(0);
  for (Entry& e : entries) {
    if (with_messages) {
      trace.recv_begin_.push_back(trace.recv_from_.size());
      for (const Received& r : e.recv) {
        trace.recv_from_.push_back(dense(r.from));
        trace.recv_sent_.push_back(r.sent);
        trace.recv_words_.insert(trace.recv_words_.end(), r.words.begin(), r.words.end());
        trace.recv_words_begin_.push_back(trace.recv_words_.size());
      }
    }
    const uint32_t m = dense(e.m);
    has_line[m] = 1;
    trace.line_module_.push_back(m);
    trace.value_begin_.push_back(trace.value_.size());
    for (const auto& [var, value] : e.vars) {
      trace.value_var_.push_back(var);
      trace.value_.push_back(value);
    }
    trace.nbr_begin_.push_back(trace.nbrs_.size());
    for (watch::ModuleId n : e.nbrs) trace.nbrs_.push_back(dense(n));
    e = Entry{};  // its memory goes back as the flat arrays grow
  }
  trace.value_begin_.push_back(trace.value_.size());
  trace.nbr_begin_.push_back(trace.nbrs_.size());
  if (with_messages) trace.recv_begin_.push_back(trace.recv_from_.size());
  trace.modules_with_lines_ = static_cast<uint32_t>(std::count(has_line.begin(), has_line.end(), 1));
  return trace;
}

std::variant<Trace, std::string> Trace::from_columns(const Columns& c) {
  const size_t lines = c.t.size();
  const auto count = [](size_t n) { return std::to_string(n); };
  if (c.m.size() != lines) return "\"m\" has " + count(c.m.size()) + " entries and \"t\" " + count(lines);
  if (c.nbr_begin.size() != lines + 1)
    return "the neighbour offsets have " + count(c.nbr_begin.size()) + " entries: one more than the lines (" +
           count(lines + 1) + ") are needed";
  if ((!c.nbr_begin.empty() && c.nbr_begin.front() != 0) ||
      (!c.nbr_begin.empty() && c.nbr_begin.back() != static_cast<int64_t>(c.nbrs.size())))
    return "the neighbour offsets must start at 0 and end at the number of neighbours (" + count(c.nbrs.size()) + ")";
  for (size_t v = 0; v < c.variables.size(); ++v) {
    if (c.values[v].size() != lines)
      return "variable '" + c.variables[v] + "' has " + count(c.values[v].size()) + " values for " + count(lines) +
             " lines";
    if (std::find(c.variables.begin(), c.variables.begin() + static_cast<ptrdiff_t>(v), c.variables[v]) !=
        c.variables.begin() + static_cast<ptrdiff_t>(v))
      return "variable '" + c.variables[v] + "' appears twice";
  }

  // Each line checked as the file reader checks one; the order noted on the way.
  const auto line = [&](size_t i) {
    return "line " + count(i) + " (t=" + std::to_string(c.t[i]) + ", m=" + std::to_string(c.m[i]) + "): ";
  };
  int64_t last_step = -1;
  watch::ModuleId largest = 0;
  bool sorted = true;
  std::vector<int64_t> scratch;
  for (size_t i = 0; i < lines; ++i) {
    if (c.t[i] < 0) return line(i) + "step \"t\" must be 0 or more";
    if (c.t[i] > kMaxStep) return line(i) + "step \"t\" is beyond " + std::to_string(kMaxStep);
    if (c.m[i] < 0 || c.m[i] > UINT32_MAX) return line(i) + "module id \"m\" must be in 0..4294967295";
    const int64_t begin = c.nbr_begin[i], end = c.nbr_begin[i + 1];
    if (end < begin || end > static_cast<int64_t>(c.nbrs.size()))
      return line(i) + "its neighbour offsets " + std::to_string(begin) + ".." + std::to_string(end) +
             " are not a range of the neighbours";
    scratch.assign(c.nbrs.begin() + begin, c.nbrs.begin() + end);
    for (int64_t n : scratch) {
      if (n < 0 || n > UINT32_MAX) return line(i) + "neighbour id must be in 0..4294967295";
      if (n == c.m[i]) return line(i) + "module " + std::to_string(n) + " lists itself as a neighbour";
      largest = std::max(largest, static_cast<watch::ModuleId>(n));
    }
    std::sort(scratch.begin(), scratch.end());
    if (std::adjacent_find(scratch.begin(), scratch.end()) != scratch.end())
      return line(i) + "a neighbour appears twice in \"nbrs\"";
    largest = std::max(largest, static_cast<watch::ModuleId>(c.m[i]));
    last_step = std::max(last_step, c.t[i]);
    if (i > 0 && !(c.t[i - 1] < c.t[i] || (c.t[i - 1] == c.t[i] && c.m[i - 1] < c.m[i]))) sorted = false;
  }
  // Lines in (step, module) order; sorted already, a duplicate cannot hide.
  std::vector<size_t> order(lines);
  for (size_t i = 0; i < lines; ++i) order[i] = i;
  if (!sorted) {
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return c.t[a] != c.t[b] ? c.t[a] < c.t[b] : c.m[a] < c.m[b]; });
    for (size_t k = 1; k < lines; ++k)
      if (c.t[order[k]] == c.t[order[k - 1]] && c.m[order[k]] == c.m[order[k - 1]])
        return line(order[k]) + "duplicate line for module " + std::to_string(c.m[order[k]]) + " at step " +
               std::to_string(c.t[order[k]]) + " (first at line " + count(order[k - 1]) + ")";
  }

  Trace trace;
  trace.universe_.variables = c.variables;
  const DenseIds dense(
      largest, lines,
      [&](auto&& fn) {
        for (size_t i = 0; i < lines; ++i) fn(static_cast<watch::ModuleId>(c.m[i]));
        for (int64_t n : c.nbrs) fn(static_cast<watch::ModuleId>(n));
      },
      trace.universe_.module_ids);
  trace.step_count_ = last_step + 1;
  const size_t variables = c.variables.size();
  trace.line_module_.resize(lines);
  trace.value_begin_.resize(lines + 1);
  trace.value_var_.resize(lines * variables);
  trace.value_.resize(lines * variables);
  trace.nbr_begin_.resize(lines + 1);
  trace.nbrs_.resize(c.nbrs.size());
  std::vector<uint8_t> has_line(trace.universe_.module_ids.size(), 0);
  uint64_t nbr_at = 0;
  for (size_t k = 0; k < lines; ++k) {
    const size_t i = order[k];
    if (k == 0 || c.t[i] != c.t[order[k - 1]]) {
      trace.busy_steps_.push_back(c.t[i]);
      trace.busy_begin_.push_back(k);
    }
    const uint32_t m = dense(static_cast<watch::ModuleId>(c.m[i]));
    has_line[m] = 1;
    trace.line_module_[k] = m;
    trace.value_begin_[k] = k * variables;
    for (size_t v = 0; v < variables; ++v) {
      trace.value_var_[k * variables + v] = static_cast<uint32_t>(v);
      trace.value_[k * variables + v] = c.values[v][i];
    }
    trace.nbr_begin_[k] = nbr_at;
    for (int64_t j = c.nbr_begin[i]; j < c.nbr_begin[i + 1]; ++j)
      trace.nbrs_[nbr_at++] = dense(static_cast<watch::ModuleId>(c.nbrs[static_cast<size_t>(j)]));
  }
  trace.busy_begin_.push_back(lines);
  trace.value_begin_[lines] = lines * variables;
  trace.nbr_begin_[lines] = nbr_at;
  trace.modules_with_lines_ = static_cast<uint32_t>(std::count(has_line.begin(), has_line.end(), 1));
  return trace;
}

double default_frame_budget() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return 2.0 * (1ull << 30);
  return static_cast<double>(pages) * static_cast<double>(page) / 4;
}

std::variant<FrameReader, std::string> FrameReader::make(const Trace& trace,
                                                         const std::optional<std::vector<std::string>>& variables,
                                                         double max_frame_bytes) {
  FrameReader reader(trace);
  reader.universe_.module_ids = trace.universe_.module_ids;
  const std::vector<std::string>& all = trace.universe_.variables;
  reader.column_of_.assign(all.size(), -1);
  for (size_t v = 0; v < all.size(); ++v) {
    if (variables && std::find(variables->begin(), variables->end(), all[v]) == variables->end()) continue;
    reader.column_of_[v] = static_cast<int32_t>(reader.universe_.variables.size());
    reader.universe_.variables.push_back(all[v]);
  }
  const double modules = static_cast<double>(reader.universe_.module_ids.size());
  const double vars = static_cast<double>(reader.universe_.variables.size());
  const double frame_bytes = modules * (9.0 * vars + 5.0);
  if (frame_bytes > max_frame_bytes) {
    return "one frame of the trace needs " + size_text(static_cast<size_t>(frame_bytes)) + " (" +
           std::to_string(reader.universe_.module_ids.size()) + " modules x " +
           std::to_string(reader.universe_.variables.size()) + " variables); at most " +
           size_text(static_cast<size_t>(max_frame_bytes)) + " is allowed (--max-frame-memory)";
  }
  return reader;
}

watch::Frame FrameReader::frame(int64_t step, FrameBuffer& b) const {
  const Trace& t = *trace_;
  const size_t modules = universe_.module_ids.size(), vars = universe_.variables.size();
  b.present.assign(modules, 0);
  b.values.assign(modules * vars, 0);
  b.has_value.assign(modules * vars, 0);
  b.nbr_begin.assign(modules + 1, 0);
  b.nbrs.clear();
  uint64_t first = 0, last = 0;  // the step's lines, none when it has no line
  const auto busy = std::lower_bound(t.busy_steps_.begin(), t.busy_steps_.end(), step);
  if (busy != t.busy_steps_.end() && *busy == step) {
    const size_t i = static_cast<size_t>(busy - t.busy_steps_.begin());
    first = t.busy_begin_[i];
    last = t.busy_begin_[i + 1];
  }
  // Lines are in module order: the neighbour lists are laid out in that order too.
  for (uint64_t line = first; line < last; ++line) {
    const uint32_t m = t.line_module_[line];
    b.present[m] = 1;
    for (uint64_t i = t.value_begin_[line]; i < t.value_begin_[line + 1]; ++i) {
      const int32_t c = column_of_[t.value_var_[i]];
      if (c < 0) continue;
      b.values[m * vars + static_cast<size_t>(c)] = t.value_[i];
      b.has_value[m * vars + static_cast<size_t>(c)] = 1;
    }
    b.nbr_begin[m + 1] = static_cast<uint32_t>(t.nbr_begin_[line + 1] - t.nbr_begin_[line]);
    b.nbrs.insert(b.nbrs.end(), t.nbrs_.begin() + static_cast<ptrdiff_t>(t.nbr_begin_[line]),
                  t.nbrs_.begin() + static_cast<ptrdiff_t>(t.nbr_begin_[line + 1]));
  }
  for (size_t m = 0; m < modules; ++m) b.nbr_begin[m + 1] += b.nbr_begin[m];
  watch::Frame f;
  f.step = step;
  f.present = b.present;
  f.values = b.values;
  f.has_value = b.has_value;
  f.nbr_begin = b.nbr_begin;
  f.nbrs = b.nbrs;
  f.variable_count = static_cast<uint32_t>(vars);
  return f;
}

}  // namespace dw::sim
