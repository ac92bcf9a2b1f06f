#include "ensembles/config/config.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

#include <toml++/toml.h>

#include "core/error.hpp"
#include "ensembles/io/files.hpp"

namespace qmaps {
namespace {

std::string dotted(std::string_view section, std::string_view key) {
  return std::string(section) + "." + std::string(key);
}

std::string type_name(const toml::node& n) {
  if (n.is_string()) return "a string";
  if (n.is_integer()) return "an integer";
  if (n.is_floating_point()) return "a number";
  if (n.is_boolean()) return "a boolean";
  if (n.is_array()) return "an array";
  if (n.is_table()) return "a table";
  return "a value";
}

// The Levenshtein distance of a and b, counting an adjacent swap as one edit.
std::size_t edits(std::string_view a, std::string_view b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1,
                          d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

// Text without the blanks around it.
std::string trimmed(std::string_view text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t");
  return std::string(text.substr(first, last - first + 1));
}

}  // namespace

// The parsed TOML, and the look-ups that mark keys used.
struct Config::Document {
  toml::table table;
  const toml::table* section_table(std::string_view section) const;
  const toml::node* find(const Config& c, std::string_view section, std::string_view key) const;
  const toml::node& node(const Config& c, std::string_view section, std::string_view key) const;
};

Config::Config() : doc_(std::make_unique<Document>()) {}
Config::~Config() = default;
Config::Config(Config&&) noexcept = default;
Config& Config::operator=(Config&&) noexcept = default;
Config::Config(const Config& other)
    : doc_(std::make_unique<Document>(*other.doc_)),
      text_(other.text_),
      source_(other.source_),
      overridden_(other.overridden_),
      lines_(other.lines_),
      used_(other.used_),
      used_sections_(other.used_sections_) {}

// "name" is a [section]; "name[i]" the i-th table of an array of tables [[name]].
const toml::table* Config::Document::section_table(std::string_view section) const {
  const auto open = section.find('[');
  if (open == std::string_view::npos) return table.get_as<toml::table>(section);
  const auto* array = table.get_as<toml::array>(section.substr(0, open));
  const auto index = std::stoul(std::string(section.substr(open + 1)));
  return array && index < array->size() ? (*array)[index].as_table() : nullptr;
}

std::size_t Config::entries(std::string_view array) const {
  used_sections_.insert(std::string(array));
  const auto* a = doc_->table.get_as<toml::array>(array);
  return a ? a->size() : 0;
}

namespace {

constexpr std::size_t max_config_bytes = std::size_t{1} << 20;

// A configuration is small: at most 1 MiB, in lines of at most 4096 characters. Checked before
// the TOML parser sees it, which recurses on nested headers and values.
void check_size(std::string_view text, const std::string& source) {
  constexpr std::size_t max_line = 4096;
  if (text.size() > max_config_bytes)
    throw usage_error(source + ": " + std::to_string(text.size()) +
                      " bytes; a configuration may have at most " + std::to_string(max_config_bytes));
  std::size_t line = 1, start = 0;
  for (std::size_t i = 0; i <= text.size(); ++i)
    if (i == text.size() || text[i] == '\n') {
      if (i - start > max_line)
        throw usage_error(source + ":" + std::to_string(line) + ": a line of " +
                          std::to_string(i - start) + " characters; at most " +
                          std::to_string(max_line));
      ++line;
      start = i + 1;
    }
}

}  // namespace

Config Config::parse(std::string_view text, std::string source) {
  check_size(text, source);
  Config c;
  c.text_ = std::string(text);
  c.source_ = std::move(source);
  try {
    c.doc_->table = toml::parse(c.text_, c.source_);
  } catch (const toml::parse_error& e) {
    std::ostringstream msg;
    msg << c.source_ << ':' << e.source().begin.line << ':' << e.source().begin.column
        << ": malformed TOML: " << e.description();
    throw usage_error(msg.str());
  }
  for (const auto& [name, value] : c.doc_->table)
    if (!value.is_table() && !value.is_array_of_tables())
      throw usage_error(c.source_ + ":" + std::to_string(value.source().begin.line) + ": '" +
                        std::string(name.str()) + "' must be a [section] or [[table array]]");
  // The lines, kept apart from the document: a copy of a TOML node has no source (a sweep's
  // points are copies), and messages must still name the line.
  const auto keep = [&c](const std::string& section, const toml::table& t) {
    c.lines_[section] = t.source().begin.line;
    for (const auto& [key, v] : t) c.lines_[dotted(section, key.str())] = v.source().begin.line;
  };
  for (const auto& [name, value] : c.doc_->table) {
    const std::string section(name.str());
    c.lines_[section] = value.source().begin.line;
    if (const auto* array = value.as_array())
      for (std::size_t i = 0; i < array->size(); ++i)
        keep(section + "[" + std::to_string(i) + "]", *(*array)[i].as_table());
    else
      keep(section, *value.as_table());
  }
  return c;
}

std::size_t Config::line_of(const std::string& name) const {
  const auto at = lines_.find(name);
  return at == lines_.end() ? 0 : at->second;
}

Config Config::load(const std::string& path) {
  return parse(files::read_regular_file(path, max_config_bytes, "config file"), path);
}

void Config::set(std::string_view assignment, bool by_user) {
  const auto eq = assignment.find('=');
  const auto dot = assignment.find('.');
  if (eq == std::string_view::npos || dot == std::string_view::npos || dot > eq || dot == 0 ||
      dot + 1 == eq)
    throw usage_error("--set expects section.key=value, got '" + std::string(assignment) + "'");
  // "run.steps = 100" as "run.steps=100": the blanks around the names and the value go.
  const std::string section = trimmed(assignment.substr(0, dot));
  const std::string key = trimmed(assignment.substr(dot + 1, eq - dot - 1));
  const std::string value = trimmed(assignment.substr(eq + 1));
  if (section.empty() || key.empty())
    throw usage_error("--set expects section.key=value, got '" + std::string(assignment) + "'");
  toml::table parsed;
  try {
    check_size(value, "--set " + section + "." + key);
    parsed = toml::parse("v = " + value);
  } catch (const toml::parse_error&) {
    // Nineteen digits or more that TOML does not read are an integer beyond its 64 bits, not a
    // bare string.
    const std::size_t sign = !value.empty() && (value[0] == '+' || value[0] == '-');
    if (value.size() >= sign + 19 &&
        value.find_first_not_of("0123456789", sign) == std::string::npos)
      throw usage_error("--set " + section + "." + key + "=" + value +
                        ": an integer must be -2^63 to 2^63 - 1 (9223372036854775807)");
    parsed = toml::table{{"v", value}};
  }
  toml::table* target = nullptr;
  if (const auto open = section.find('['); open != std::string::npos) {  // "name[i]": [[name]] i
    const std::string name = section.substr(0, open);
    auto* array = doc_->table[name].as_array();
    const std::string index_text = section.substr(open + 1, section.size() - open - 2);
    std::size_t used = 0;
    std::size_t index = 0;
    try {
      index = std::stoul(index_text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (section.back() != ']' || used == 0 || used != index_text.size())
      throw usage_error("--set " + section + "." + key + ": expected " + name + "[index]");
    if (!array || !array->is_array_of_tables() || index >= array->size())
      throw usage_error("--set " + section + "." + key + ": there is no [[" + name + "]] number " +
                        index_text + " (tables are counted from 0; the config has " +
                        std::to_string(array ? array->size() : 0) + ")");
    target = (*array)[index].as_table();
  } else {
    target = doc_->table[section].as_table();
  }
  if (!target) {
    if (doc_->table.contains(section))
      throw usage_error("--set " + section + "." + key + ": '" + section +
                        "' is an array of tables [[" + section + "]]: name one as " + section +
                        "[i]." + key + " (i from 0)");
    doc_->table.insert(section, toml::table{});
    target = doc_->table[section].as_table();
  }
  target->insert_or_assign(key, std::move(*parsed.get("v")));
  if (by_user) overridden_.insert(dotted(section, key));
}

const toml::node* Config::Document::find(const Config& c, std::string_view section,
                                         std::string_view key) const {
  c.used_sections_.insert(std::string(section.substr(0, section.find('['))));
  const auto* s = section_table(section);
  if (!s) return nullptr;
  const auto* n = s->get(key);
  if (n) c.used_.insert(dotted(section, key));
  return n;
}

const toml::node& Config::Document::node(const Config& c, std::string_view section,
                                         std::string_view key) const {
  const auto* n = find(c, section, key);
  if (n) return *n;
  // A key of the section that no reader asked for, within two edits of the missing one (of 4
  // letters or more), is named first: "stpes = 2000" is a misspelt key before a missing one.
  const auto* s = key.size() >= 4 ? section_table(section) : nullptr;
  if (s)
    for (const auto& [other, value] : *s)
      if (!c.used_.count(dotted(section, other.str())) && edits(other.str(), key) <= 2)
        throw usage_error(c.source_ + ":" +
                          std::to_string(c.line_of(dotted(section, other.str()))) + ": [" +
                          std::string(section) + "] unknown key '" + std::string(other.str()) +
                          "' (did you mean '" + std::string(key) + "'?)");
  throw usage_error(c.source_ + ": missing key '" + std::string(key) + "' in [" +
                    std::string(section) + "]");
}

bool Config::has(std::string_view section, std::string_view key) const {
  return doc_->find(*this, section, key) != nullptr;
}

bool Config::has_section(std::string_view section) const {
  used_sections_.insert(std::string(section));
  return doc_->section_table(section) != nullptr;
}

std::string Config::where(std::string_view section, std::string_view key) const {
  const std::string name = dotted(section, key);
  if (overridden_.count(name)) return "--set " + name;
  // The key's line, else its table's (a key the file lacks).
  const auto line = lines_.count(name) ? line_of(name) : line_of(std::string(section));
  return source_ + ":" + std::to_string(line) + ": [" + std::string(section) + "] " +
         std::string(key);
}

std::string Config::where(std::string_view section) const {
  if (const auto set = set_in(section)) return "--set " + *set + ": [" + std::string(section) + "]";
  std::string text = source_ + ":" + std::to_string(line_of(std::string(section))) + ": [" +
                     std::string(section) + "]";
  // A message about the table as a whole may be about a value --set gave it: name those too.
  const std::string prefix = std::string(section) + ".";
  std::string sets;
  for (const auto& name : overridden_)
    if (name.compare(0, prefix.size(), prefix) == 0) sets += (sets.empty() ? "" : ", ") + name;
  return sets.empty() ? text : text + " with --set " + sets;
}

std::optional<std::string> Config::set_in(std::string_view section) const {
  // A table the file lacks and --set made: its source has no line.
  const auto* s = doc_->section_table(section);
  if (s && line_of(std::string(section)) != 0) return std::nullopt;
  const std::string prefix = std::string(section) + ".";
  for (const auto& name : overridden_)
    if (name.compare(0, prefix.size(), prefix) == 0) return name;
  return std::nullopt;
}

double Config::number(std::string_view section, std::string_view key) const {
  const auto& n = doc_->node(*this, section, key);
  const auto v = n.value<double>();
  if (!v || !(n.is_number()))
    throw usage_error(where(section, key) + " must be a number, not " + type_name(n));
  if (!std::isfinite(*v)) throw usage_error(where(section, key) + " must be finite");
  return *v;
}

double Config::number_or(std::string_view section, std::string_view key, double fallback) const {
  return has(section, key) ? number(section, key) : fallback;
}

long long Config::integer(std::string_view section, std::string_view key) const {
  const auto& n = doc_->node(*this, section, key);
  if (!n.is_integer())
    throw usage_error(where(section, key) + " must be an integer, not " + type_name(n));
  return *n.value<long long>();
}

long long Config::integer_or(std::string_view section, std::string_view key,
                             long long fallback) const {
  return has(section, key) ? integer(section, key) : fallback;
}

bool Config::boolean_or(std::string_view section, std::string_view key, bool fallback) const {
  if (!has(section, key)) return fallback;
  const auto& n = doc_->node(*this, section, key);
  if (!n.is_boolean())
    throw usage_error(where(section, key) + " must be true or false, not " + type_name(n));
  return *n.value<bool>();
}

std::string Config::string(std::string_view section, std::string_view key) const {
  const auto& n = doc_->node(*this, section, key);
  if (!n.is_string())
    throw usage_error(where(section, key) + " must be a string, not " + type_name(n));
  return *n.value<std::string>();
}

std::string Config::string_or(std::string_view section, std::string_view key,
                              std::string fallback) const {
  return has(section, key) ? string(section, key) : fallback;
}

std::array<double, 2> Config::range(std::string_view section, std::string_view key) const {
  const auto& n = doc_->node(*this, section, key);
  if (n.is_number()) {
    const double x = number(section, key);
    return {x, x};
  }
  const auto* a = n.as_array();
  if (!a || a->size() != 2 || !(*a)[0].is_number() || !(*a)[1].is_number())
    throw usage_error(where(section, key) + " must be a range [lo, hi] or a number");
  const double lo = *(*a)[0].value<double>(), hi = *(*a)[1].value<double>();
  if (!std::isfinite(lo) || !std::isfinite(hi))
    throw usage_error(where(section, key) + " must have finite ends");
  if (lo > hi)
    throw usage_error(where(section, key) + " is an empty range: lo > hi (" +
                      number_text(lo) + " > " + number_text(hi) + ")");
  return {lo, hi};
}

std::vector<double> Config::numbers(std::string_view section, std::string_view key,
                                    std::size_t count) const {
  const auto* a = doc_->node(*this, section, key).as_array();
  std::vector<double> out;
  if (a && a->size() == count)
    for (const auto& item : *a)
      if (item.is_number() && std::isfinite(*item.value<double>()))
        out.push_back(*item.value<double>());
  if (out.size() != count)
    throw usage_error(where(section, key) + " must be an array of " + std::to_string(count) +
                      " finite numbers");
  return out;
}

std::vector<double> Config::numbers(std::string_view section, std::string_view key) const {
  const auto* a = doc_->node(*this, section, key).as_array();
  std::vector<double> out;
  if (a)
    for (const auto& item : *a)
      if (item.is_number() && std::isfinite(*item.value<double>()))
        out.push_back(*item.value<double>());
  if (!a || a->empty() || out.size() != a->size())
    throw usage_error(where(section, key) + " must be a non-empty array of finite numbers");
  return out;
}

std::vector<std::string> Config::strings(std::string_view section, std::string_view key,
                                         std::size_t count) const {
  const auto* a = doc_->node(*this, section, key).as_array();
  std::vector<std::string> out;
  if (a && a->size() == count)
    for (const auto& item : *a)
      if (item.is_string()) out.push_back(*item.value<std::string>());
  if (out.size() != count)
    throw usage_error(where(section, key) + " must be an array of " + std::to_string(count) +
                      " strings");
  return out;
}

std::vector<std::int64_t> Config::range_or_integer(std::string_view section,
                                                   std::string_view key) const {
  const auto& n = doc_->node(*this, section, key);
  if (n.is_integer()) return {*n.value<std::int64_t>()};
  std::vector<std::int64_t> out;
  if (const auto* a = n.as_array())
    for (const auto& item : *a) {
      if (!item.is_integer())
        throw usage_error(where(section, key) + " must hold integers, not " + type_name(item));
      out.push_back(*item.value<std::int64_t>());
    }
  else
    throw usage_error(where(section, key) + " must be an integer or an array of integers");
  return out;
}

std::vector<std::string> Config::keys(std::string_view section) const {
  std::vector<std::string> out;
  used_sections_.insert(std::string(section.substr(0, section.find('['))));
  if (const auto* s = doc_->section_table(section))
    for (const auto& [k, v] : *s) {
      out.emplace_back(k.str());
      used_.insert(dotted(section, k.str()));
    }
  return out;
}

void Config::reject_unknown() const {
  for (const auto& [section, value] : doc_->table) {
    const std::string name(section.str());
    if (!used_sections_.count(name)) {
      if (const auto set = set_in(name)) throw usage_error("--set " + *set + ": unknown section [" + name + "]");
      throw usage_error(source_ + ":" + std::to_string(line_of(name)) +
                        ": unknown section [" + name + "]");
    }
    const auto check = [&](const toml::table& t, const std::string& path) {
      for (const auto& [key, v] : t)
        if (!used_.count(dotted(path, key.str())))
          throw usage_error(where(path, key.str()) + ": unknown key");
    };
    if (const auto* array = value.as_array())
      for (std::size_t i = 0; i < array->size(); ++i)
        check(*(*array)[i].as_table(), name + "[" + std::to_string(i) + "]");
    else
      check(*value.as_table(), name);
  }
}

std::string Config::resolved() const {
  std::ostringstream out;
  out << toml::toml_formatter(doc_->table);
  return out.str();
}

}  // namespace qmaps
