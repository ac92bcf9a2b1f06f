#pragma once
// Running the qmaps binary (QMAPS_BINARY) from the tests: each test gets a fresh directory, the
// process runs in it with stdout and stderr captured to files, and the directory goes at the end.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace qmaps::testing {

namespace fs = std::filesystem;

// EXPECT_TRUE(Contains(text, part)): whether `text` contains `part`, showing both when not.
inline ::testing::AssertionResult Contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "'" << text << "' does not contain '" << part << "'";
}

// A fresh directory under /tmp, removed with everything in it.
class TempDir {
 public:
  TempDir() {
    std::string name = "/tmp/qmaps-test-XXXXXX";
    if (!mkdtemp(name.data())) throw std::runtime_error("mkdtemp failed");
    path_ = name;
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  const fs::path& path() const { return path_; }
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }

  // The names of the entries in the directory.
  std::vector<std::string> entries() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(path_)) out.push_back(e.path().filename().string());
    return out;
  }
  // Whether an entry's name contains `part` (e.g. ".tmp-", an AtomicFile's temporary).
  bool has_entry_containing(const std::string& part) const {
    for (const auto& name : entries())
      if (name.find(part) != std::string::npos) return true;
    return false;
  }

 private:
  fs::path path_;
};

inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

inline void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path);
}

// `text` with its one line that starts with `prefix` replaced by `line` ("" deletes it).
inline std::string with_line(const std::string& text, const std::string& prefix,
                             const std::string& line) {
  std::istringstream in(text);
  std::string out, current;
  int found = 0;
  while (std::getline(in, current)) {
    if (current.rfind(prefix, 0) == 0) {
      ++found;
      if (!line.empty()) out += line + '\n';
    } else {
      out += current + '\n';
    }
  }
  if (found != 1) throw std::runtime_error("no unique line starting with '" + prefix + "'");
  return out;
}

// The 1-based number of the one line of `text` that starts with `prefix`.
inline int line_of(const std::string& text, const std::string& prefix) {
  std::istringstream in(text);
  std::string current;
  for (int n = 1; std::getline(in, current); ++n)
    if (current.rfind(prefix, 0) == 0) return n;
  throw std::runtime_error("no line starting with '" + prefix + "'");
}

// The shipped preset, shrunk to `orbits` × `steps` and writing to `output`.
// The Suris preset's map, ensemble, run and output (its observers left out), with these values.
inline std::string preset_config(const std::string& output, long long orbits = 100,
                                 long long steps = 50) {
  std::string text = read_text(QMAPS_SOURCE_DIR "/ensembles/presets/suris.toml");
  text = text.substr(0, text.find("\n[["));
  text = with_line(text, "orbits = ", "orbits = " + std::to_string(orbits));
  text = with_line(text, "steps = ", "steps = " + std::to_string(steps));
  return with_line(text, "file = ", "file = \"" + output + "\"");
}

struct Result {
  int status = -1;  // the exit code, or 128 + the signal that ended the process
  std::string out, err;
};

// Starts QMAPS_BINARY with `args` in directory `dir`, stdout and stderr to dir/.stdout,
// dir/.stderr. `signal_at` ("STEP:INT", "STEP:TERM", "STEP:KILL"): the run signals itself on
// reaching that step (QMAPS_SIGNAL_AT_STEP), so an interruption happens where the test says.
inline pid_t spawn(const std::vector<std::string>& args, const TempDir& dir,
                   const std::string& signal_at = "") {
  const std::string out = dir / ".stdout", err = dir / ".stderr";
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    std::vector<char*> argv{const_cast<char*>(QMAPS_BINARY)};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    const int o = open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (o < 0 || e < 0 || dup2(o, 1) < 0 || dup2(e, 2) < 0 || chdir(dir.path().c_str()) != 0)
      _exit(127);
    if (!signal_at.empty()) setenv("QMAPS_SIGNAL_AT_STEP", signal_at.c_str(), 1);
    execv(QMAPS_BINARY, argv.data());
    _exit(127);
  }
  return pid;
}

// Waits for a spawned process and collects what it printed.
inline Result finish(pid_t pid, const TempDir& dir) {
  int raw = 0;
  if (waitpid(pid, &raw, 0) != pid) throw std::runtime_error("waitpid failed");
  Result r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
  r.out = read_text(dir / ".stdout");
  r.err = read_text(dir / ".stderr");
  fs::remove(dir / ".stdout");
  fs::remove(dir / ".stderr");
  return r;
}

inline Result run(const std::vector<std::string>& args, const TempDir& dir,
                  const std::string& signal_at = "") {
  return finish(spawn(args, dir, signal_at), dir);
}

}  // namespace qmaps::testing
