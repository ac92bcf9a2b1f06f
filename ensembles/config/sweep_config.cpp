#include "ensembles/config/sweep_config.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace qmaps {
namespace {

constexpr std::size_t max_points = 10000;  // each point is a group of the file

// The values of one [[sweep]] table: a list, or `points` values from `from` to `to`.
std::vector<double> axis_values(const Config& config, const std::string& table) {
  const bool listed = config.has(table, "values");
  const bool ranged = config.has(table, "from") || config.has(table, "to") ||
                      config.has(table, "points") || config.has(table, "scale");
  if (listed == ranged)
    throw usage_error(config.where(table) +
                      ": give either values = [...] or from, to and points (and scale)");
  if (listed) {
    auto values = config.numbers(table, "values");
    if (values.size() > max_points)
      throw usage_error(config.where(table, "values") + " has more than " +
                        std::to_string(max_points) + " values");
    return values;
  }
  const double from = config.number(table, "from"), to = config.number(table, "to");
  const long long points = config.integer(table, "points");
  const std::string scale = config.string_or(table, "scale", "linear");
  if (points < 1 || static_cast<std::size_t>(points) > max_points)
    throw usage_error(config.where(table, "points") + " must be 1 to " + std::to_string(max_points));
  if (points == 1 && from != to)
    throw usage_error(config.where(table, "points") + " is 1: from and to must be equal");
  if (scale != "linear" && scale != "log")
    throw usage_error(config.where(table, "scale") + ": '" + scale +
                      "' is not a scale (expected \"linear\" or \"log\")");
  if (scale == "log" && !(from > 0 && to > 0))
    throw usage_error(config.where(table, "scale") + " \"log\" needs from and to > 0");
  std::vector<double> values(static_cast<std::size_t>(points));
  const double n = static_cast<double>(points - 1);
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double f = static_cast<double>(i);
    values[i] = scale == "linear" ? from + (to - from) * f / n
                                  : from * std::pow(to / from, f / n);
  }
  values.front() = from;  // the ends exactly as written
  values.back() = to;
  return values;
}

}  // namespace

std::string SweepAxis::name() const {
  return denominator.empty() ? numerator : numerator + "_over_" + denominator;
}

std::optional<Sweep> Sweep::from_config(const Config& config, const Model& base) {
  const std::size_t tables = config.entries("sweep");
  if (tables == 0) {
    if (config.has_section("sweep"))
      throw usage_error(config.where("sweep") + ": a sweep is one [[sweep]] table per axis");
    return std::nullopt;
  }
  if (tables > 2)
    throw usage_error(config.where("sweep[2]") + ": a sweep has one or two axes, not " +
                      std::to_string(tables));
  Sweep s;
  for (const auto& spec : base.param_specs()) s.names_.emplace_back(spec.name);
  s.base_.assign(base.param_values().begin(), base.param_values().end());
  const auto known = [&](const std::string& name) {
    return std::find(s.names_.begin(), s.names_.end(), name) != s.names_.end();
  };
  std::string listing;
  for (const auto& name : s.names_) listing += (listing.empty() ? "" : ", ") + name;

  std::size_t points = 1;
  for (std::size_t k = 0; k < tables; ++k) {
    const std::string table = "sweep[" + std::to_string(k) + "]";
    SweepAxis axis;
    axis.parameter = config.string(table, "parameter");
    const auto slash = axis.parameter.find('/');
    axis.numerator = axis.parameter.substr(0, slash);
    if (slash != std::string::npos) axis.denominator = axis.parameter.substr(slash + 1);
    if (slash != std::string::npos && axis.denominator.empty())
      throw usage_error(config.where(table, "parameter") + ": '" + axis.parameter +
                        "' is a ratio without a denominator");
    for (const auto* name : {&axis.numerator, &axis.denominator})
      if ((name == &axis.numerator || !name->empty()) && !known(*name))
        throw usage_error(config.where(table, "parameter") + ": " + std::string(base.name()) +
                          " has no parameter '" + *name + "' (it has " + listing + ")");
    if (axis.numerator == axis.denominator)
      throw usage_error(config.where(table, "parameter") + ": a ratio of a parameter to itself");
    for (const auto& other : s.axes_)
      if (other.numerator == axis.numerator)
        throw usage_error(config.where(table, "parameter") + ": both axes set " + axis.numerator);
    axis.values = axis_values(config, table);
    points *= axis.values.size();
    if (points > max_points)
      throw usage_error(config.where(table) + ": the sweep would have more than " +
                        std::to_string(max_points) + " points");
    s.axes_.push_back(std::move(axis));
  }
  // A ratio's denominator is [map]'s value, or another axis's plain parameter; never a ratio's.
  for (std::size_t k = 0; k < s.axes_.size(); ++k) {
    const auto& axis = s.axes_[k];
    if (axis.denominator.empty()) continue;
    const std::string table = "sweep[" + std::to_string(k) + "]";
    for (const auto& other : s.axes_)
      if (other.numerator == axis.denominator && !other.denominator.empty())
        throw usage_error(config.where(table, "parameter") + ": its denominator " +
                          axis.denominator + " is itself swept as a ratio");
  }
  for (std::size_t p = 0; p < s.points(); ++p) {
    const auto values = s.parameters(p);
    for (std::size_t k = 0; k < s.axes_.size(); ++k) {
      const auto& axis = s.axes_[k];
      if (axis.denominator.empty()) continue;
      const auto at = std::find(s.names_.begin(), s.names_.end(), axis.denominator);
      const double d = values[static_cast<std::size_t>(at - s.names_.begin())];
      if (!(d != 0 && std::isfinite(d)))
        throw usage_error(config.where("sweep[" + std::to_string(k) + "]", "parameter") +
                          ": at " + s.label(p) + ", " + axis.denominator + " is " +
                          number_text(d) + "; a ratio needs a finite, non-zero denominator");
    }
  }
  return s;
}

std::size_t Sweep::points() const {
  std::size_t n = 1;
  for (const auto& axis : axes_) n *= axis.values.size();
  return n;
}

std::vector<std::size_t> Sweep::shape() const {
  std::vector<std::size_t> out;
  for (const auto& axis : axes_) out.push_back(axis.values.size());
  return out;
}

double Sweep::axis_value(std::size_t point, std::size_t axis) const {
  std::size_t stride = 1;
  for (std::size_t k = axis + 1; k < axes_.size(); ++k) stride *= axes_[k].values.size();
  return axes_[axis].values[point / stride % axes_[axis].values.size()];
}

std::string Sweep::label(std::size_t point) const {
  std::string out = "point " + std::to_string(point) + " (";
  for (std::size_t k = 0; k < axes_.size(); ++k)
    out += (k ? ", " : "") + axes_[k].parameter + " = " + number_text(axis_value(point, k));
  return out + ")";
}

std::vector<double> Sweep::parameters(std::size_t point) const {
  std::vector<double> values = base_;
  const auto index = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find(names_.begin(), names_.end(), name) - names_.begin());
  };
  for (int ratios = 0; ratios < 2; ++ratios)  // plain parameters first, then the ratios of them
    for (std::size_t k = 0; k < axes_.size(); ++k) {
      const auto& axis = axes_[k];
      if (axis.denominator.empty() == (ratios == 1)) continue;
      const double v = axis_value(point, k);
      values[index(axis.numerator)] = ratios ? v * values[index(axis.denominator)] : v;
    }
  return values;
}

Config Sweep::config_of(const Config& config, std::size_t point) const {
  Config out = config;
  const auto values = parameters(point);
  for (const auto& axis : axes_) {
    const auto at = std::find(names_.begin(), names_.end(), axis.numerator) - names_.begin();
    out.set("map." + axis.numerator + "=" + number_text(values[static_cast<std::size_t>(at)]),
            false);
  }
  return out;
}

}  // namespace qmaps
