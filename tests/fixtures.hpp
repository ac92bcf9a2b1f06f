#pragma once
// The configurations that the C++ tests, the Python tests (small_run.fixture) and the fuzzers
// share: tests/fixtures/<name>, in the folder QMAPS_FIXTURES_DIR, which CMake defines for each
// target that reads one (fuzz/CMakeLists.txt for the fuzz targets).
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#ifndef QMAPS_FIXTURES_DIR
#error "QMAPS_FIXTURES_DIR (the folder tests/fixtures) must be defined by the target"
#endif

namespace qmaps::testing {

// The text of the fixture `name` ("small-suris-box.toml"): a regular file of at most 64 KiB, or
// std::runtime_error naming the path and what is wrong.
inline std::string fixture(const std::string& name) {
  constexpr std::size_t kLimit = 64 << 10;
  const std::filesystem::path path = std::filesystem::path(QMAPS_FIXTURES_DIR) / name;
  const auto refused = [&](const std::string& why) {
    return std::runtime_error("test fixture '" + path.string() + "' " + why);
  };
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status)) throw refused("does not exist");
  if (!std::filesystem::is_regular_file(status)) throw refused("is not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw refused("cannot be opened");
  std::string text(kLimit + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (in.bad()) throw refused("cannot be read");
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.size() > kLimit) throw refused("is larger than 64 KiB");
  return text;
}

}  // namespace qmaps::testing
