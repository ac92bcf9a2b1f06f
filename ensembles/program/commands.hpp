#pragma once
// The qmaps subcommands, as functions of their parsed options (ensembles/program/main.cpp parses them).
#include <functional>
#include <iosfwd>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/params.hpp"
#include "core/phase.hpp"
#include "integrability/options.hpp"

namespace qmaps {
namespace exact {
class ExactMap;
struct Report;
}  // namespace exact

// Where a run's spec comes from (read_spec): its configuration and overrides, and the path it
// takes.
struct SpecSource {
  std::string config_path{};        // the TOML file, or
  std::string config_text{};        // the configuration itself (a caller in the same process),
  std::string config_source{};      // and the name its messages give it
  std::vector<std::string> sets{};  // "section.key=value"
  std::string out{};                // overrides [output] file when not empty
  std::string shard{};              // "k/K": only orbit range k of K, into a shard file
  std::string write_to{};           // the file written, [output] file left as configured
  std::shared_ptr<const std::vector<Phase>> points{};  // the orbits' starting points ([ensemble])
  int threads = 0;                  // 0: all the cores OpenMP offers (core/thread_limit.hpp)
  std::string threads_given_as = "--threads ";  // how messages name it: "--threads 8"
  std::string simd = "auto";
};

// How a run's session goes (a new run's, or a resumed one's): what it shows and records, and
// what a signal leaves.
struct SessionOptions {
  bool quiet = false;
  std::string command_line{};
  bool checkpoint_on_interrupt = true;  // false: a signal stops the run with nothing written
  std::function<void(long long step, long long total)> on_segment{};  // after each segment
};

// qmaps run: a new run's source, or the checkpoint of one to continue (its path from the
// source's threads and simd), and the session.
struct RunOptions {
  SpecSource source;
  std::string resume;  // "<output>.ckpt", instead of a configuration
  SessionOptions session;
};

struct MergeOptions {
  std::vector<std::string> shards;  // the shard files, in any order
  std::string out;                  // the merged file
};

struct OrbitOptions {
  std::string map;
  std::vector<std::string> sets;  // "name=value" map parameters
  std::string ic;                 // "q1,q2,p1,p2"
  long long steps = 0;
  long long every = 1;
  std::string start = "taylor";
  double escape_bound = 1e8;
  bool chaos = false;  // also the chaos indicators' columns (docs/chaos.md)
  long long tunes = 0;  // the tunes' window N (docs/tunes.md; 0: none)
  std::optional<double> energy;  // p2 solved from H_cont(q1, q2, p1, p2) = E, its sign kept
};

struct CheckOptions {
  std::string map;
  std::vector<std::string> sets;  // "name=value" map parameters
  long long orbits = 1000;
  long long steps = 1000;
  long long seed = 1;
  double box = 0.5;               // orbits uniform in [−box, box]⁴
  double escape_bound = 1e8;
};

struct DiscoverOptions {
  std::string config_path;        // [map] and [ensemble] as `qmaps run` reads them
  std::vector<std::string> sets;  // "section.key=value"
  long long degree = 0;           // monomials of degree 1 … degree
  long long steps = 0;
  long long orbits = 100;         // the first orbits of the ensemble (all, if it has fewer)
  double threshold = 0;           // σ_i/σ_1 at or below it: the null space (0: at the largest gap)
  double drop = 1e-6;             // coefficients below it (relative to the largest), or below
                                  // their uncertainty 1/gap, not printed
  bool csv = false;               // the invariants as CSV rows instead of the report
};

struct IntegrabilityCommandOptions {
  std::string map;                // a built-in map's name or a formula map's .toml file
  std::vector<std::string> sets;  // "name=value" map parameters
  exact::IntegrabilityOptions tests;
  std::string output;             // the HDF5 file, or none
};

// Each returns the process exit code; errors are thrown as qmaps::Error.
int run_command(const RunOptions& options, std::ostream& log);
int orbit_command(const OrbitOptions& options, std::ostream& out, std::ostream& log);
// qmaps orbit's table, for a caller that keeps it: `columns` gets the names (n first), `row`
// each row's values in that order. Returns why the rows stopped early (an escape), or "".
using OrbitColumns = std::function<void(const std::vector<std::string>&)>;
using OrbitRow = std::function<void(std::span<const double>)>;
// The orbit's tunes over its first 2·tunes steps, as a line of text ("" without --tunes).
std::string orbit_tunes(const OrbitOptions& options);
std::string orbit_rows(const OrbitOptions& options, const OrbitColumns& columns,
                       const OrbitRow& row);
// The built-in maps, or the maps written as formulas in these TOML files.
int list_command(const std::vector<std::string>& files, std::ostream& out);
// A formula map's keys and their texts, a line each, indented (`qmaps list`, `qmaps info`).
void write_formulas(std::ostream& out,
                    const std::vector<std::pair<std::string, std::string>>& keys);
int info_command(const std::string& path, std::ostream& out);
int check_command(const CheckOptions& options, std::ostream& out);
int discover_command(const DiscoverOptions& options, std::ostream& out);
int integrability_command(const IntegrabilityCommandOptions& options, std::ostream& out);
// The map `--map` names (a built-in map, or a formula map's .toml file), to be evaluated exactly.
exact::ExactMap exact_map_named(const std::string& map, const ParamValues& params);
// The tests' report alone (the Python function).
exact::Report integrability_report(const IntegrabilityCommandOptions& options);
int merge_command(const MergeOptions& options, std::ostream& log);

}  // namespace qmaps
