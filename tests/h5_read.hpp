#pragma once
// Whole datasets of a file this program wrote, their length taken from the file itself (the
// program's own readers are told the length they expect); two files' datasets compared byte for
// byte.
#include <gtest/gtest.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "ensembles/io/h5.hpp"

namespace qmaps::testing {

inline std::size_t elements(const h5::Group& g, const std::string& name) {
  std::size_t n = 1;
  for (const auto d : g.shape(name)) n *= static_cast<std::size_t>(d);
  return n;
}
inline std::vector<double> all_doubles(const h5::Group& g, const std::string& name) {
  return g.read_doubles(name, elements(g, name));
}
inline std::vector<std::int64_t> all_int64(const h5::Group& g, const std::string& name) {
  return g.read_int64(name, elements(g, name));
}

// Every dataset of a file, by path, as its raw bytes in the file's type.
inline std::map<std::string, std::vector<char>> datasets(const std::string& path) {
  const h5::File file = h5::File::open_read(path);
  std::vector<std::string> names;
  H5Ovisit(
      file.root().id(), H5_INDEX_NAME, H5_ITER_INC,
      [](hid_t, const char* name, const H5O_info_t* info, void* data) -> herr_t {
        if (info->type == H5O_TYPE_DATASET) static_cast<std::vector<std::string>*>(data)->push_back(name);
        return 0;
      },
      &names);
  std::map<std::string, std::vector<char>> out;
  for (const auto& name : names) {
    h5::Handle set(H5Dopen2(file.root().id(), name.c_str(), H5P_DEFAULT), H5Dclose);
    h5::Handle type(H5Dget_type(set.id()), H5Tclose);
    h5::Handle space(H5Dget_space(set.id()), H5Sclose);
    auto& bytes = out[name];
    bytes.resize(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.id())) *
                 H5Tget_size(type.id()));
    if (!bytes.empty()) {
      EXPECT_GE(H5Dread(set.id(), type.id(), H5S_ALL, H5S_ALL, H5P_DEFAULT, bytes.data()), 0);
    }
  }
  return out;
}

// EXPECT_TRUE(SameDatasets(a, b)): the same dataset paths (or, for a `subset`, some of b's), each
// with the same bytes.
inline ::testing::AssertionResult SameDatasets(const std::string& a, const std::string& b,
                                        bool subset = false) {
  const auto x = datasets(a), y = datasets(b);
  if (x.empty()) return ::testing::AssertionFailure() << a << " has no dataset";
  if (subset ? x.size() > y.size() : x.size() != y.size())
    return ::testing::AssertionFailure() << x.size() << " datasets against " << y.size();
  for (const auto& [name, bytes] : x) {
    const auto it = y.find(name);
    if (it == y.end()) return ::testing::AssertionFailure() << b << " lacks " << name;
    if (it->second != bytes) return ::testing::AssertionFailure() << name << " differs";
  }
  return ::testing::AssertionSuccess() << x.size() << " datasets";
}

}  // namespace qmaps::testing
