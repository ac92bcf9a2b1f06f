// libFuzzer target: a set of shard files of one run, one of them altered (fuzz/hostile_file.hpp)
// and the set itself chosen by the input (a shard left out, given twice, or a checkpoint among
// them), joined with `qmaps merge`. It must merge or throw qmaps::Error: any other exception, a
// crash or a sanitizer report is a finding.
#include <cstdint>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "fuzz_files.hpp"
#include "hostile_file.hpp"

namespace {

// The three shards of the scratch folder's run (made once).
const std::vector<std::string>& shards() {
  static const std::vector<std::string> made = [] {
    std::vector<std::string> names;
    for (int k = 1; k <= 3; ++k) {
      std::ostringstream log;
      qmaps::RunOptions run;
      run.source.config_path = "base.toml";
      run.source.sets = {"output.file=\"base.h5\""};  // the run's output, which every shard names
      run.source.shard = std::to_string(k) + "/3";
      run.source.out = "shard-" + std::to_string(k) + ".h5";
      run.source.threads = 1;
      run.session.quiet = true;
      if (qmaps::run_command(run, log) != 0) std::abort();
      names.push_back(run.source.out);
    }
    return names;
  }();
  return made;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace qmaps;
  fuzz::scratch();
  if (size < 2) return 0;
  const auto& made = shards();
  // The first byte: which shard is altered, and how the set is given.
  const unsigned altered = data[0] % 3, set = data[0] / 3 % 5;
  std::vector<std::string> given;
  for (unsigned k = 0; k < 3; ++k) {
    const std::string copy = "input-" + std::to_string(k + 1) + ".h5";
    std::filesystem::copy_file(made[k], copy, std::filesystem::copy_options::overwrite_existing);
    given.push_back(copy);
  }
  if (!fuzz::alter(given[altered], data + 1, size - 1)) return 0;
  if (set == 1) given.pop_back();                     // one missing
  if (set == 2) given.push_back(given.front());      // one twice
  if (set == 3) given.push_back("stopped.h5.ckpt");  // a checkpoint among the shards
  if (set == 4) std::swap(given.front(), given.back());
  std::ostringstream log;
  MergeOptions merge;
  merge.shards = given;
  merge.out = "merged.h5";
  try {
    merge_command(merge, log);
  } catch (const Error&) {
  }
  return 0;
}
