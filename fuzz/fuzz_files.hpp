#pragma once
// What the HDF5 fuzz targets share: a scratch folder with a small valid run file (base.h5) and
// checkpoint (stopped.h5.ckpt) of a Suris run with a section, made once by qmaps itself, and the
// copy of one that each input alters (fuzz/hostile_file.hpp).
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "ensembles/program/commands.hpp"
#include "tests/fixtures.hpp"

namespace qmaps::fuzz {

// The configuration of that run (tests/fixtures/small-suris-box.toml).
inline const std::string& base_config() {
  static const std::string text = qmaps::testing::fixture("small-suris-box.toml");
  return text;
}

// The scratch folder (made once, the working directory from then on).
inline std::filesystem::path scratch() {
  static const std::filesystem::path dir = [] {
    char name[] = "/tmp/qmaps-fuzz-XXXXXX";
    const std::filesystem::path d = mkdtemp(name);
    std::filesystem::current_path(d);
    std::ofstream("base.toml") << base_config();
    std::ostringstream log;
    RunOptions run;
    run.source.config_path = "base.toml";
    run.source.out = "base.h5";
    run.source.threads = 1;
    run.session.quiet = true;
    if (run_command(run, log) != 0) std::abort();
    setenv("QMAPS_SIGNAL_AT_STEP", "6:TERM", 1);
    run.source.out = "stopped.h5";
    if (run_command(run, log) != 5) std::abort();
    unsetenv("QMAPS_SIGNAL_AT_STEP");
    return d;
  }();
  return dir;
}

}  // namespace qmaps::fuzz
