#pragma once
// A run's configuration: a TOML document plus `--set section.key=value` overrides. Readers take
// keys through the accessors, which mark them used; any key left unused is unknown, and
// reject_unknown() names it with its line. Every error names the source, the line and the key.
// A section argument "name" is a [name] table; "name[i]" the i-th table of an array [[name]].
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>


namespace qmaps {

class Config {
 public:
  Config();
  ~Config();
  Config(const Config& other);
  Config(Config&&) noexcept;
  Config& operator=(Config&&) noexcept;

  // Parses TOML text; `source` names it in messages (a path, or "<defaults>").
  static Config parse(std::string_view text, std::string source);
  static Config load(const std::string& path);  // throws an io error for an unreadable file

  // "section.key=value": value is read as a TOML value (number, string, array, boolean), and
  // as a bare string when it is not one, so --set output.file=run.h5 needs no quotes. The section
  // "name[i]" is the i-th table (from 0) of an array of tables [[name]], e.g. histogram[0].bins.
  // `by_user` false: a value qmaps itself gives (a sweep's point), which messages do not name as
  // a --set.
  void set(std::string_view assignment, bool by_user = true);

  bool has(std::string_view section, std::string_view key) const;
  bool has_section(std::string_view section) const;  // a [section] table, perhaps empty
  std::size_t entries(std::string_view array) const;  // tables in [[array]] (0 when absent)
  double number(std::string_view section, std::string_view key) const;
  double number_or(std::string_view section, std::string_view key, double fallback) const;
  long long integer(std::string_view section, std::string_view key) const;
  long long integer_or(std::string_view section, std::string_view key, long long fallback) const;
  bool boolean_or(std::string_view section, std::string_view key, bool fallback) const;
  std::string string(std::string_view section, std::string_view key) const;
  std::string string_or(std::string_view section, std::string_view key, std::string fallback) const;
  // [lo, hi] with lo ≤ hi, both finite; a single number x means [x, x].
  std::array<double, 2> range(std::string_view section, std::string_view key) const;
  // An array of `count` finite numbers (e.g. a phase-space point [q1, q2, p1, p2]).
  std::vector<double> numbers(std::string_view section, std::string_view key,
                              std::size_t count) const;
  // A non-empty array of finite numbers, of any length (e.g. a sweep's values).
  std::vector<double> numbers(std::string_view section, std::string_view key) const;
  // An array of `count` strings (e.g. axes = ["q1", "p1"]).
  std::vector<std::string> strings(std::string_view section, std::string_view key,
                                   std::size_t count) const;
  // An integer n, or an array of integers (e.g. bins = [nx, ny]).
  std::vector<std::int64_t> range_or_integer(std::string_view section, std::string_view key) const;
  // Every key of a section (each is then marked used).
  std::vector<std::string> keys(std::string_view section) const;

  // Throws a usage error naming the first section or key no reader asked for, and its line.
  void reject_unknown() const;

  const std::string& text() const { return text_; }  // as given
  std::string resolved() const;                         // after overrides, as TOML

  // "source:line: [section] key" for messages about this key's value.
  std::string where(std::string_view section, std::string_view key) const;
  std::string where(std::string_view section) const;  // "source:line: [section]"

 private:
  // For a table only --set made (none in the file): the first "section.key" set in it.
  std::optional<std::string> set_in(std::string_view section) const;

  struct Document;  // the parsed TOML (ensembles/config/config.cpp): toml++ stays out of here
  std::unique_ptr<Document> doc_;
  std::string text_;
  std::string source_;
  std::set<std::string> overridden_;
  // The file's line of each "section", "name[i]" and "section.key" (0: not in the file).
  std::map<std::string, std::size_t> lines_;
  std::size_t line_of(const std::string& name) const;
  mutable std::set<std::string> used_;
  mutable std::set<std::string> used_sections_;
};

}  // namespace qmaps
