#include "scenarios/table_reader.h"

#include <algorithm>
#include <sstream>

#include "scenarios/limits.h"

namespace dw::scenarios {

FileDiagnostics::FileDiagnostics(const watch::SourceText& source) : source_(source) {
  line_starts_.push_back(0);
  const std::string& t = source.text();
  for (uint32_t i = 0; i < t.size(); ++i)
    if (t[i] == '\n') line_starts_.push_back(i + 1);
}

uint32_t FileDiagnostics::offset(const toml::source_position& p) const {
  if (p.line == 0 || p.line > line_starts_.size()) return static_cast<uint32_t>(source_.text().size());
  const uint32_t start = line_starts_[p.line - 1];
  return std::min<uint32_t>(start + (p.column ? p.column - 1 : 0), static_cast<uint32_t>(source_.text().size()));
}

watch::Span FileDiagnostics::span(const toml::source_region& at) const {
  const uint32_t begin = offset(at.begin);
  uint32_t end = at.end.line == at.begin.line ? offset(at.end) : begin + 1;
  if (end <= begin) end = begin + 1;
  return {begin, end};
}

void FileDiagnostics::add(const toml::source_region& at, std::string message) {
  list_.push_back({span(at), std::move(message)});
}

std::string FileDiagnostics::format() const {
  std::vector<watch::Diagnostic> sorted = list_;
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const watch::Diagnostic& a, const watch::Diagnostic& b) { return a.span.begin < b.span.begin; });
  // The first ones only, as a compiler stops at its error limit: 100,000 mistakes made 20 MB of
  // messages, and placing each one (a scan of the text) took minutes.
  if (sorted.size() <= kMaxShown) return watch::format_diagnostics(source_, sorted);
  const size_t more = sorted.size() - kMaxShown;
  sorted.resize(kMaxShown);
  return watch::format_diagnostics(source_, sorted) + source_.name() + ": " + std::to_string(more) + " more error" +
         (more == 1 ? "" : "s") + " not shown (the first " + std::to_string(kMaxShown) + " are above)\n";
}

TableReader::TableReader(const toml::table& table, FileDiagnostics& diagnostics, std::string what)
    : table_(table), diagnostics_(diagnostics), what_(std::move(what)) {}

const toml::node* TableReader::node(std::string_view key) {
  known_.insert(std::string(key));
  return table_.get(key);
}

void TableReader::error(std::string_view key, std::string message) {
  const toml::node* n = table_.get(key);
  diagnostics_.add(n ? n->source() : table_.source(), std::move(message));
}

void TableReader::missing(std::string_view key) {
  diagnostics_.add(table_.source(), what_ + " needs the key '" + std::string(key) + "'");
}

namespace {
const char* type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a floating-point number";
    case toml::node_type::boolean: return "a boolean";
    default: return "a date or time";
  }
}
}  // namespace

std::optional<int64_t> TableReader::integer(std::string_view key, int64_t min, int64_t max) {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  if (!n->is_integer()) {
    error(key, "'" + std::string(key) + "' must be an integer, not " + type_name(*n));
    return std::nullopt;
  }
  const int64_t v = n->as_integer()->get();
  if (v < min || v > max) {
    error(key, out_of_range_message(key, min, max, std::to_string(v)));
    return std::nullopt;
  }
  return v;
}

std::optional<bool> TableReader::boolean(std::string_view key) {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  if (!n->is_boolean()) {
    error(key, "'" + std::string(key) + "' must be true or false, not " + type_name(*n));
    return std::nullopt;
  }
  return n->as_boolean()->get();
}

std::optional<std::string> TableReader::string(std::string_view key) {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  if (!n->is_string()) {
    error(key, "'" + std::string(key) + "' must be a string, not " + type_name(*n));
    return std::nullopt;
  }
  return n->as_string()->get();
}

std::optional<std::vector<int64_t>> TableReader::integers(std::string_view key, int64_t min, int64_t max,
                                                          size_t min_count, size_t max_count) {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  const std::string k(key);
  const toml::array* a = n->as_array();
  if (!a) {
    error(key, "'" + k + "' must be an array of integers, not " + type_name(*n));
    return std::nullopt;
  }
  if (a->size() < min_count || a->size() > max_count) {
    error(key, "'" + k + "' must have " +
                   (min_count == max_count ? std::to_string(min_count)
                                           : std::to_string(min_count) + " to " + std::to_string(max_count)) +
                   " elements, not " + std::to_string(a->size()));
    return std::nullopt;
  }
  std::vector<int64_t> out;
  bool ok = true;
  for (const toml::node& e : *a) {
    if (!e.is_integer()) {
      diagnostics_.add(e.source(), "'" + k + "' must hold integers, not " + type_name(e));
      ok = false;
      continue;
    }
    const int64_t v = e.as_integer()->get();
    if (v < min || v > max) {
      diagnostics_.add(e.source(), "each of '" + k + "' must be between " + std::to_string(min) + " and " +
                                       std::to_string(max) + ", not " + std::to_string(v));
      ok = false;
      continue;
    }
    out.push_back(v);
  }
  if (!ok) return std::nullopt;
  return out;
}

std::optional<double> TableReader::number(std::string_view key, double min, double max) {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  const std::string k(key);
  std::optional<double> v;
  if (n->is_integer()) v = double(n->as_integer()->get());
  else if (n->is_floating_point()) v = n->as_floating_point()->get();
  if (!v) {
    error(key, "'" + k + "' must be a number, not " + type_name(*n));
    return std::nullopt;
  }
  if (!(*v >= min && *v <= max)) {  // NaN fails too
    std::ostringstream range;
    range << "'" << k << "' must be between " << min << " and " << max << ", not " << *v;
    error(key, range.str());
    return std::nullopt;
  }
  return v;
}

std::vector<const toml::table*> TableReader::tables(std::string_view key) {
  const toml::node* n = node(key);
  if (!n) return {};
  const toml::array* a = n->as_array();
  std::vector<const toml::table*> out;
  if (a && a->is_array_of_tables())
    for (const toml::node& e : *a) out.push_back(e.as_table());
  else
    error(key,
          "'" + std::string(key) + "' must be an array of tables ([[" + std::string(key) + "]]), not " + type_name(*n));
  return out;
}

std::optional<std::vector<double>> TableReader::numbers(std::string_view key, size_t count, double min, double max) {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  const std::string k(key);
  const toml::array* a = n->as_array();
  if (!a || a->size() != count) {
    error(key, "'" + k + "' must be an array of " + std::to_string(count) + " numbers");
    return std::nullopt;
  }
  std::vector<double> out;
  for (const toml::node& e : *a) {
    if (e.is_integer()) out.push_back(double(e.as_integer()->get()));
    else if (e.is_floating_point()) out.push_back(e.as_floating_point()->get());
    else {
      diagnostics_.add(e.source(), "'" + k + "' must hold numbers, not " + type_name(e));
      return std::nullopt;
    }
    if (!(out.back() >= min && out.back() <= max)) {  // NaN fails too
      std::ostringstream range;
      range << "each of '" << k << "' must be between " << min << " and " << max << ", not " << out.back();
      diagnostics_.add(e.source(), range.str());
      return std::nullopt;
    }
  }
  return out;
}

const toml::table* TableReader::table(std::string_view key) {
  const toml::node* n = node(key);
  if (!n) return nullptr;
  if (!n->is_table()) {
    error(key, "'" + std::string(key) + "' must be a table, not " + type_name(*n));
    return nullptr;
  }
  return n->as_table();
}

void TableReader::finish() {
  for (auto&& [key, value] : table_) {
    if (known_.count(key.str())) continue;
    std::string known;
    for (const std::string& k : known_) known += (known.empty() ? "" : ", ") + k;
    diagnostics_.add(key.source(), "unknown key '" + std::string(key.str()) + "' in " + what_ +
                                       (known.empty() ? "" : " (known keys: " + known + ")"));
  }
}

}  // namespace dw::scenarios
