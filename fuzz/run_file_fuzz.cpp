// libFuzzer target: a run file altered (fuzz/hostile_file.hpp), read by `qmaps info` and as the
// initial conditions of another run (`[ensemble] kind = "file"`). Each must succeed or throw
// qmaps::Error: any other exception, a crash or a sanitizer report is a finding.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "fuzz_files.hpp"
#include "hostile_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace qmaps;
  fuzz::scratch();
  std::filesystem::copy_file("base.h5", "input.h5",
                             std::filesystem::copy_options::overwrite_existing);
  if (!fuzz::alter("input.h5", data, size)) return 0;
  std::ostringstream out;
  try {
    info_command("input.h5", out);
  } catch (const Error&) {
  }
  static const bool written = [] {
    std::string config = fuzz::base_config();
    config.replace(config.find("kind = \"box\""), 12, "kind = \"file\"\npath = \"input.h5\"");
    std::ofstream("again.toml") << config;
    return true;
  }();
  (void)written;
  RunOptions run;
  run.source.config_path = "again.toml";
  run.source.out = "again.h5";
  run.source.threads = 1;
  run.session.quiet = true;
  try {
    run_command(run, out);
  } catch (const Error&) {
  }
  return 0;
}
