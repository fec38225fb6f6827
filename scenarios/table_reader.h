// Reads one TOML table of a scenario file with types, ranges and positions: every mistake becomes
// a `file:line:col: error:` diagnostic with a caret, and keys nobody asked for are reported as
// unknown when the table is finished.
#pragma once

#include <toml++/toml.h>
#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "scenarios/limits.h"
#include "watch/diagnostic.h"
#include "watch/source.h"

namespace dw::scenarios {

// Diagnostics against the scenario file's text.
class FileDiagnostics {
 public:
  explicit FileDiagnostics(const watch::SourceText& source);
  const watch::SourceText& source() const { return source_; }
  void add(const toml::source_region& at, std::string message);
  void add(watch::Diagnostic d) { list_.push_back(std::move(d)); }
  watch::Span span(const toml::source_region& at) const;
  uint32_t offset(const toml::source_position& p) const;
  bool empty() const { return list_.empty(); }
  // The diagnostics in file order, at most kMaxShown of them, then how many more there are.
  static constexpr size_t kMaxShown = 20;
  std::string format() const;

 private:
  const watch::SourceText& source_;
  std::vector<uint32_t> line_starts_;
  std::vector<watch::Diagnostic> list_;
};

class TableReader {
 public:
  // `what` names the table in messages: "[lattice]", "[[program]] leader_election".
  TableReader(const toml::table& table, FileDiagnostics& diagnostics, std::string what);

  const toml::table& table() const { return table_; }
  const std::string& what() const { return what_; }
  bool has(std::string_view key) const { return table_.contains(key); }
  const toml::node* node(std::string_view key);  // marks the key as known

  // Each returns nothing when the key is absent or wrong (then an error was reported).
  std::optional<int64_t> integer(std::string_view key, int64_t min, int64_t max);
  std::optional<int64_t> integer(const IntegerRange& range) { return integer(range.key, range.min, range.max); }
  std::optional<bool> boolean(std::string_view key);
  std::optional<std::string> string(std::string_view key);
  std::optional<std::vector<int64_t>> integers(std::string_view key, int64_t min, int64_t max, size_t min_count,
                                               size_t max_count);
  std::optional<double> number(std::string_view key, double min, double max);
  // `count` numbers, each finite and within [min, max].
  std::optional<std::vector<double>> numbers(std::string_view key, size_t count, double min, double max);
  // An array of tables ([[key]]); empty when absent or wrong.
  std::vector<const toml::table*> tables(std::string_view key);
  const toml::table* table(std::string_view key);

  void error(std::string_view key, std::string message);  // at the key's value
  void missing(std::string_view key);                     // at the table
  // Reports every key that was never asked for.
  void finish();

 private:
  const toml::table& table_;
  FileDiagnostics& diagnostics_;
  std::string what_;
  std::set<std::string, std::less<>> known_;
};

}  // namespace dw::scenarios
