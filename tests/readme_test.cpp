// The README and docs/getting-started.md never lie: every command of their sh blocks runs as
// written (from a scratch folder, with build/, ensembles/ and tools/ pointing into this tree) and
// exits 0, each distinct command once. The set-up (`bash tools/setup`, alone or as a prefix) is what
// built this test; the test and benchmark commands are left to CI and to bench/.
#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "run_process.hpp"

namespace qmaps::testing {
namespace {

// The lines of the sh blocks of the page `page` (a path relative to the source tree).
std::vector<std::string> sh_commands(const std::string& page) {
  std::ifstream in(std::string(QMAPS_SOURCE_DIR) + "/" + page);
  std::vector<std::string> out;
  bool in_sh = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("```", 0) == 0) {
      in_sh = !in_sh && line == "```sh";
      continue;
    }
    if (in_sh && !line.empty()) out.push_back(line);
  }
  return out;
}

std::string replace_all(const std::string& text, const std::string& from, const std::string& to) {
  std::string out;
  std::size_t done = 0;
  for (auto at = text.find(from); at != std::string::npos; at = text.find(from, done)) {
    out.append(text, done, at - done).append(to);
    done = at + from.size();
  }
  return out.append(text, done);
}

TEST(Readme, EveryExampleCommandRunsAsWritten) {
  auto commands = sh_commands("README.md");
  ASSERT_GE(commands.size(), 3u) << "the README's sh blocks were not found";
  const std::string setup = "bash tools/setup && ";
  EXPECT_EQ(commands[0].rfind(setup + "build/qmaps run ", 0), 0u) << commands[0];
  EXPECT_EQ(commands[1], "bash tools/setup --all && ctest --test-dir build --output-on-failure -j2");
  const auto tutorial = sh_commands("docs/getting-started.md");
  ASSERT_GE(tutorial.size(), 5u) << "docs/getting-started.md's sh blocks were not found";
  commands.insert(commands.end(), tutorial.begin(), tutorial.end());
  std::set<std::string> done;
  int ran = 0;
  for (std::string command : commands) {
    if (command.rfind(setup, 0) == 0) command = command.substr(setup.size());
    if (command.rfind("bash tools/setup --all && ", 0) == 0) continue;  // the test suite itself
    if (command == "bash tools/setup" || command == "bash tools/setup --mpi") continue;
    if (!done.insert(command).second) continue;  // run once already
    if (command.rfind("ctest ", 0) == 0 || command.rfind("build/bench/", 0) == 0 ||
        command.rfind("bench/report", 0) == 0)
      continue;
    ASSERT_TRUE(command.rfind("build/qmaps ", 0) == 0 || command.rfind("tools/qmaps-plot ", 0) == 0)
        << "unexpected command in the README or docs/getting-started.md: " << command;
    TempDir dir;
    const std::string binary = std::string(QMAPS_BINARY) + " ";
    const std::string presets = std::string(" ") + QMAPS_SOURCE_DIR + "/ensembles/";
    const std::string plot = std::string(QMAPS_SOURCE_DIR) + "/tools/qmaps-plot ";
    std::string shell = "cd '";
    shell.append(dir.path().string()).append("' && ");
    shell.append(replace_all(
        replace_all(replace_all(command, "build/qmaps ", binary), " ensembles/", presets),
        "tools/qmaps-plot ", plot));
    shell.append(" > out.txt 2> err.txt");
    const int status = std::system(shell.c_str());
    EXPECT_EQ(status, 0) << command << "\n" << read_text(dir / "err.txt");
    ++ran;
  }
  EXPECT_GE(ran, 10);
}

}  // namespace
}  // namespace qmaps::testing
