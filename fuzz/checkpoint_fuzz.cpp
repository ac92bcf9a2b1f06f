// libFuzzer target: a checkpoint altered (fuzz/hostile_file.hpp) and resumed with
// `qmaps run --resume`. It must resume or throw qmaps::Error: any other exception, a crash or a
// sanitizer report is a finding.
#include <cstdint>
#include <filesystem>
#include <sstream>

#include "core/error.hpp"
#include "fuzz_files.hpp"
#include "hostile_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace qmaps;
  fuzz::scratch();
  std::filesystem::copy_file("stopped.h5.ckpt", "input.h5.ckpt",
                             std::filesystem::copy_options::overwrite_existing);
  if (!fuzz::alter("input.h5.ckpt", data, size)) return 0;
  std::ostringstream log;
  RunOptions run;
  run.resume = "input.h5.ckpt";
  run.source.threads = 1;
  run.session.quiet = true;
  try {
    run_command(run, log);
  } catch (const Error&) {
  }
  return 0;
}
