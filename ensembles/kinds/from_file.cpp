#include "ensembles/kinds/from_file.hpp"

#include <cmath>
#include <cstring>

#include "core/error.hpp"
#include "core/escape.hpp"
#include "ensembles/io/h5.hpp"
#include "ensembles/io/file_orbits.hpp"
#include "ensembles/io/output.hpp"

namespace qmaps {
namespace {

// "suris (A = 0.7, B = 0.3, alpha = 0.9, h = 0.1)"
std::string map_text(const std::string& name, const std::vector<std::string>& params,
                     const std::vector<double>& values) {
  std::string text = name + " (";
  for (std::size_t k = 0; k < params.size(); ++k)
    text += (k ? ", " : "") + params[k] + " = " + number_text(values[k]);
  return text + ")";
}

bool same(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

}  // namespace

FromFile::FromFile(const Config& config, const Model& model) : model_(model) {
  path_ = config.string("ensemble", "path");
  const std::string group = config.string_or("ensemble", "group", "final");
  if (group != "final" && group != "initial")
    throw usage_error(config.where("ensemble", "group") + " must be \"final\" or \"initial\"");
  final_ = group == "final";
  const std::string where = config.where("ensemble", "path") + ": ";
  try {
    const auto file = h5::File::open_read(path_);
    const auto root = file.root();
    if (!root.has_attr("schema_version") || !root.has_attr("map") || !root.has("initial"))
      throw Error(ExitCode::io, "'" + path_ +
                                    "' is not a qmaps output file (no schema_version, "
                                    "map or /initial)");
    check_schema(root, path_);
    // The file's map and parameters against the run's.
    const std::string map = root.attr_string("map");
    std::vector<std::string> names, file_names;
    std::vector<double> values, file_values;
    bool match = map == model.name();
    const auto specs = model.param_specs();
    for (std::size_t k = 0; k < specs.size(); ++k) {
      names.emplace_back(specs[k].name);
      values.push_back(model.param_values()[k]);
      const std::string attr = "param." + names.back();
      match = match && root.has_attr(attr) && same(root.attr_double(attr), values.back());
    }
    for (const auto& attr : root.attr_names())
      if (attr.rfind("param.", 0) == 0) {
        file_names.push_back(attr.substr(6));
        file_values.push_back(root.attr_double(attr));
      }
    if (!match || file_names.size() != names.size())
      throw usage_error("'" + path_ + "' holds a run of " + map_text(map, file_names, file_values) +
                        ", not of this run's " +
                        map_text(std::string(model.name()), names, values));
    const std::size_t columns = final_ ? model.state_names().size() + 2 : phase_names.size();
    orbits_ = orbits_in(root, path_, 8.0 * static_cast<double>(columns));
    step_ = root.attr_int64("steps");
    if (final_) {
      const auto state = root.open_group("final").open_group("state");
      for (const auto& name : model.state_names())
        columns_.push_back(state.read_doubles(std::string(name), orbits_));
      const auto escape = root.open_group("escape");
      escape_step_ = escape.read_int64("step", orbits_);
      escape_reason_ = escape.read_int64("reason", orbits_);
      for (std::size_t i = 0; i < orbits_; ++i)
        if (escape_step_[i] >= 0 &&
            (escape_reason_[i] < 1 || escape_reason_[i] > last_escape_reason))
          throw Error(ExitCode::io, "'" + path_ + "': orbit " + std::to_string(i) +
                                        " escaped with the unknown reason " +
                                        std::to_string(escape_reason_[i]));
    } else {
      const auto initial = root.open_group("initial");
      for (const auto name : phase_names)
        columns_.push_back(initial.read_doubles(std::string(name), orbits_));
    }
  } catch (const Error& e) {
    const std::string what = e.what();
    const std::string file = "'" + path_ + "'";
    throw Error(e.code(), where + (what.find(file) == std::string::npos ? file + ": " : "") + what);
  }
  if (orbits_ == 0) throw usage_error(where + "'" + path_ + "' holds no orbits");
}

Drawn FromFile::draw(std::size_t orbit) const {
  if (!final_)
    return {{columns_[0][orbit], columns_[1][orbit], columns_[2][orbit], columns_[3][orbit]}};
  std::vector<double> state(columns_.size());
  for (std::size_t k = 0; k < state.size(); ++k) state[k] = columns_[k][orbit];
  return {model_.phase_of(state)};
}

void FromFile::continue_into(Ensemble& e, std::size_t first, double escape_bound) const {
  std::vector<std::vector<double>> columns;
  for (const auto& c : columns_)
    columns.emplace_back(c.begin() + static_cast<std::ptrdiff_t>(first),
                         c.begin() + static_cast<std::ptrdiff_t>(first + e.orbits));
  model_.start_from_state(e, columns, escape_bound);
  for (std::size_t i = 0; i < e.orbits; ++i) {
    if (escape_step_[first + i] >= 0) {
      e.escape_step[i] = 0;
      e.escape_reason[i] = static_cast<std::uint8_t>(escape_reason_[first + i]);
    } else if (const auto why = model_.invalid_record(e, i); !why.empty()) {
      throw Error(ExitCode::io, "'" + path_ + "': /final/state: orbit " +
                                    std::to_string(first + i) + ": " + why);
    }
  }
}

std::string FromFile::description() const {
  return "file: " + std::to_string(orbits_) + " orbits of '" + path_ + "', " +
         (final_ ? "continued from its final state (step " + std::to_string(step_) + ")"
                 : std::string("started from its initial points"));
}

}  // namespace qmaps
