// qmaps._engine: the commands of the qmaps program as Python functions, in process. The package
// (python/qmaps/__init__.py) wraps them; docs/python.md documents both.
//   read_spec(...)   qmaps run's spec: the configuration read once and checked, nothing run
//   describe(spec)   what it runs: map, parameters, orbits, steps, sweep points, measurements
//   run(spec, ...)   its session: the same runner and the same file as qmaps run
//   orbit(...)  qmaps orbit's table as a (rows, columns) float64 array
//   maps()      qmaps list's catalogue
//   integrability(...)  qmaps integrability's report as text, its evidence written to `out`
// qmaps::Error becomes the package's ConfigError (bad configuration or parameters), FileError
// (a file that cannot be read or written), UnsupportedError (an ISA this CPU lacks) or Error; a
// signal (SIGINT, SIGTERM, SIGHUP) during a call stops it and becomes KeyboardInterrupt.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>

#include "core/error.hpp"
#include "core/memory_limit.hpp"
#include "core/version.hpp"
#include "ensembles/program/commands.hpp"
#include "ensembles/program/interrupt.hpp"
#include "ensembles/program/run_spec.hpp"
#include "kernels/catalogue.hpp"

namespace py = pybind11;

namespace {

using qmaps::ExitCode;

// The package's exception class for an exit code (qmaps/errors.py).
py::object error_class(ExitCode code) {
  const py::module_ errors = py::module_::import("qmaps.errors");
  switch (code) {
    case ExitCode::usage: return errors.attr("ConfigError");
    case ExitCode::io: return errors.attr("FileError");
    case ExitCode::unsupported: return errors.attr("UnsupportedError");
    default: return errors.attr("Error");
  }
}

std::shared_ptr<const std::vector<qmaps::Phase>> points_of(
    const py::array_t<double, py::array::c_style | py::array::forcecast>& points) {
  if (points.ndim() != 2 || points.shape(1) != 4) {
    std::string shape;
    for (py::ssize_t k = 0; k < points.ndim(); ++k) {
      if (k > 0) shape += ", ";
      shape += std::to_string(points.shape(k));
    }
    throw qmaps::usage_error("initial conditions: expected shape (orbits, 4), got (" + shape + ")");
  }
  auto out = std::make_shared<std::vector<qmaps::Phase>>(static_cast<std::size_t>(points.shape(0)));
  const auto rows = points.unchecked<2>();
  for (py::ssize_t i = 0; i < rows.shape(0); ++i)
    (*out)[static_cast<std::size_t>(i)] = {rows(i, 0), rows(i, 1), rows(i, 2), rows(i, 3)};
  return out;
}

// A run as qmaps::read_spec reads it, with the options of its session.
struct Spec {
  qmaps::RunSpec spec;
  qmaps::SessionOptions session;
};

// The run a configuration describes, read and checked (every key, before anything runs), to be
// written to `write_to`.
std::shared_ptr<Spec> read_spec(
    const std::string& config_path, const std::string& config_text,
    const std::string& config_source, const std::vector<std::string>& sets,
    const std::string& write_to, int threads, const std::string& simd,
    const std::optional<py::array_t<double, py::array::c_style | py::array::forcecast>>& points,
    const std::string& command_line) {
  const qmaps::SpecSource source{.config_path = config_path,
                                 .config_text = config_text,
                                 .config_source = config_source,
                                 .sets = sets,
                                 .write_to = write_to,
                                 .points = points ? points_of(*points) : nullptr,
                                 .threads = threads,
                                 .threads_given_as = "threads=",
                                 .simd = simd};
  const qmaps::SessionOptions session{
      .quiet = true, .command_line = command_line, .checkpoint_on_interrupt = false};
  const qmaps::InterruptGuard interrupt;  // a signal stops a long draw (a shell's)
  const py::gil_scoped_release released;
  return std::make_shared<Spec>(Spec{qmaps::read_spec(source), session});
}

// Runs the spec (its session); returns the log it wrote (the summary lines), or raises.
std::string run(Spec& s, const py::object& progress) {
  qmaps::SessionOptions session = s.session;
  if (!progress.is_none())
    session.on_segment = [&progress](long long step, long long total) {
      const py::gil_scoped_acquire gil;
      progress(step, total);
    };
  std::ostringstream log;
  int code = 0;
  // Held over the whole call, so that a signal after the last step (while the file is written)
  // is not lost when the run's own guard ends.
  const qmaps::InterruptGuard interrupt;
  {
    const py::gil_scoped_release released;  // other Python threads run while this one steps
    code = qmaps::run_spec(s.spec, session, interrupt, log);
  }
  std::string message = log.str();
  while (!message.empty() && message.back() == '\n') message.pop_back();
  if (code == 0 && interrupt.requested())
    message = std::string("qmaps: ") + qmaps::signal_name(interrupt.signal()) +
              " while the run's file was written: stopped, nothing kept";
  if (code == static_cast<int>(ExitCode::interrupted) || interrupt.requested()) {
    PyErr_SetString(PyExc_KeyboardInterrupt, message.c_str());
    throw py::error_already_set();
  }
  return log.str();
}

// What a spec runs: {map, params, orbits, steps, stride, points, measured}.
py::dict describe(const Spec& s) {
  const qmaps::Run& r = s.spec.points.front().run;
  py::dict params;
  const auto specs = r.model->param_specs();
  const auto values = r.model->param_values();
  for (std::size_t k = 0; k < specs.size(); ++k) params[py::str(std::string(specs[k].name))] = values[k];
  std::size_t orbits = 0;
  for (const auto& p : s.spec.points) orbits += p.run.total;
  py::dict d;
  d["map"] = std::string(r.model->name());
  d["params"] = params;
  d["orbits"] = orbits;
  d["steps"] = r.plan.total;
  d["stride"] = r.plan.stride;
  d["points"] = s.spec.points.size();
  d["invariants"] = r.model->invariant_names();
  d["measured"] = r.measured;
  return d;
}

// qmaps orbit's rows: (columns, values of shape (rows, columns), why the rows stopped early).
py::tuple orbit(const std::string& map, const std::vector<std::string>& sets, const std::string& ic,
                long long steps, long long every, const std::string& start, double escape_bound,
                bool chaos, std::optional<double> energy) {
  const qmaps::OrbitOptions o{.map = map,
                              .sets = sets,
                              .ic = ic,
                              .steps = steps,
                              .every = every,
                              .start = start,
                              .escape_bound = escape_bound,
                              .chaos = chaos,
                              .energy = energy};
  std::vector<std::string> columns;
  std::vector<double> values;
  std::string escaped;
  // The table is kept whole (qmaps orbit streams it): it must fit in memory twice, as rows and
  // as the array, before any is made; its rows are reserved once it does.
  const auto take_columns = [&](const std::vector<std::string>& c) {
    columns = c;
    const double rows = static_cast<double>(std::max(0LL, steps) / std::max(1LL, every)) + 1;
    const double bytes = 2 * rows * static_cast<double>(c.size()) * sizeof(double);
    char need[100];
    std::snprintf(need, sizeof need, "%.0f rows of %zu columns", rows, c.size());
    qmaps::check_fits(bytes, "orbit", need, "; keep fewer rows with every");
    values.reserve(static_cast<std::size_t>(rows) * c.size());
  };
  {
    const qmaps::InterruptGuard interrupt;  // a signal stops the orbit (orbit_rows looks)
    const py::gil_scoped_release released;
    escaped = qmaps::orbit_rows(o, take_columns, [&](std::span<const double> row) {
      values.insert(values.end(), row.begin(), row.end());
    });
  }
  const auto width = static_cast<py::ssize_t>(columns.size());
  py::array_t<double> table({static_cast<py::ssize_t>(values.size()) / width, width});
  std::memcpy(table.mutable_data(), values.data(), values.size() * sizeof(double));
  return py::make_tuple(columns, table, escaped);
}

py::list maps() {
  py::list out;
  for (const auto& m : qmaps::catalogue()) {
    py::list params;
    for (const auto& p : m.params) {
      py::dict d;
      d["name"] = std::string(p.name);
      d["meaning"] = std::string(p.meaning);
      d["default"] = std::isnan(p.default_value) ? py::object(py::none()) : py::float_(p.default_value);
      d["required"] = p.required();
      params.append(d);
    }
    py::dict d;
    d["name"] = std::string(m.name);
    d["summary"] = std::string(m.summary);
    d["equations"] = std::string(m.equations);
    d["invariants"] = std::string(m.invariant_summary);
    d["parameters"] = params;
    out.append(d);
  }
  return out;
}

std::string integrability(const std::string& map, const std::vector<std::string>& sets, int steps,
                          long degree_cap, const std::vector<std::uint64_t>& degree_primes,
                          int lines, const std::vector<std::uint64_t>& field_primes,
                          std::size_t orbits, std::uint64_t max_period, int height_steps,
                          double height_bits, std::uint64_t seed, const std::string& out) {
  qmaps::IntegrabilityCommandOptions o{.map = map, .sets = sets, .tests = {}, .output = out};
  o.tests = {.degree_primes = degree_primes, .lines = lines, .steps = steps,
             .degree_cap = degree_cap, .field_primes = field_primes, .orbits = orbits,
             .max_period = max_period, .height_steps = height_steps, .height_bits = height_bits,
             .seed = seed};
  std::ostringstream text;
  {
    const py::gil_scoped_release released;
    qmaps::integrability_command(o, text);
  }
  return text.str();
}

}  // namespace

PYBIND11_MODULE(_engine, m) {
  m.doc() = "The qmaps engine in process (the package qmaps wraps it; docs/python.md).";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const qmaps::Interrupted& e) {  // a signal before the run began
      PyErr_SetString(PyExc_KeyboardInterrupt, e.what());
    } catch (const qmaps::Error& e) {
      PyErr_SetString(error_class(e.code()).ptr(), e.what());
    }
  });
  py::class_<Spec, std::shared_ptr<Spec>>(m, "Spec",
                                          "A run read and checked (qmaps::read_spec); it runs once.");
  m.def("read_spec", &read_spec, py::arg("config_path"), py::arg("config_text"),
        py::arg("config_source"), py::arg("sets"), py::arg("write_to"), py::arg("threads"),
        py::arg("simd"), py::arg("points"), py::arg("command_line"));
  m.def("describe", &describe, py::arg("spec"));
  m.def("run", &run, py::arg("spec"), py::arg("progress"));
  m.def("orbit", &orbit, py::arg("map"), py::arg("sets"), py::arg("ic"), py::arg("steps"),
        py::arg("every"), py::arg("start"), py::arg("escape_bound"), py::arg("chaos"),
        py::arg("energy"));
  m.def("maps", &maps);
  m.def("integrability", &integrability, py::arg("map"), py::arg("sets"), py::arg("steps"),
        py::arg("degree_cap"), py::arg("degree_primes"), py::arg("lines"), py::arg("field_primes"),
        py::arg("orbits"), py::arg("max_period"), py::arg("height_steps"), py::arg("height_bits"),
        py::arg("seed"), py::arg("out"));
  m.attr("version") = qmaps::build::version;
  m.attr("commit") = qmaps::build::commit;
}
