#pragma once
// A structure-aware mutator for the HDF5 fuzz targets: the fuzzer's bytes choose how a valid run
// file or checkpoint written by qmaps is altered through the HDF5 API (an attribute replaced by an
// array or a hostile value, a dataset by one of another length, possibly a huge unwritten one, an
// element by NaN, inf or an extreme number), so that qmaps' readers, not libhdf5's own format
// parser, meet hostile content. Four bytes per alteration: operation, target, two of value.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include <hdf5.h>

namespace qmaps::fuzz {

struct Objects {
  std::vector<std::string> datasets;
  std::vector<std::pair<std::string, std::string>> attributes;  // (object, name)
};

inline Objects objects_of(hid_t file) {
  Objects o;
  const auto attributes_of = [&](const std::string& object) {
    const hid_t id = H5Oopen(file, object.c_str(), H5P_DEFAULT);
    if (id < 0) return;
    struct Names {
      Objects* o;
      std::string object;
    } names{&o, object};
    H5Aiterate2(
        id, H5_INDEX_NAME, H5_ITER_INC, nullptr,
        [](hid_t, const char* name, const H5A_info_t*, void* data) -> herr_t {
          auto* n = static_cast<Names*>(data);
          n->o->attributes.emplace_back(n->object, name);
          return 0;
        },
        &names);
    H5Oclose(id);
  };
  attributes_of("/");
  std::vector<std::pair<std::string, bool>> links;  // (path, is a dataset)
  H5Lvisit(
      file, H5_INDEX_NAME, H5_ITER_INC,
      [](hid_t g, const char* name, const H5L_info_t*, void* data) -> herr_t {
        H5O_info_t info;
        if (H5Oget_info_by_name2(g, name, &info, H5O_INFO_BASIC, H5P_DEFAULT) >= 0)
          static_cast<std::vector<std::pair<std::string, bool>>*>(data)->emplace_back(
              std::string("/") + name, info.type == H5O_TYPE_DATASET);
        return 0;
      },
      &links);
  for (const auto& [path, dataset] : links) {
    if (dataset) o.datasets.push_back(path);
    attributes_of(path);
  }
  return o;
}

inline double hostile_double(unsigned v) {
  const double values[] = {std::numeric_limits<double>::quiet_NaN(),
                           std::numeric_limits<double>::infinity(), -1.0, 0.0, 1e308, -1e308,
                           4.9e-324, 4611686018427387904.0, 255.0, 1e-300};
  return values[v % std::size(values)];
}

inline std::int64_t hostile_int(unsigned v) {
  const std::int64_t values[] = {-1, 0, 1, 255, std::int64_t{1} << 40, std::int64_t{1} << 62,
                                 std::numeric_limits<std::int64_t>::min(), 7, 100000, -2};
  return values[v % std::size(values)];
}

// Replaces `name` under `parent` by a one-dimensional dataset of n elements of `type` (chunked
// and never written when n is huge), filled with `fill`.
inline void replace_dataset(hid_t file, const std::string& path, hsize_t n, hid_t type,
                            double fill) {
  H5Ldelete(file, path.c_str(), H5P_DEFAULT);
  const hid_t space = H5Screate_simple(1, &n, nullptr);
  const hid_t plist = H5Pcreate(H5P_DATASET_CREATE);
  const bool huge = n > (hsize_t{1} << 20);
  if (huge) {
    const hsize_t chunk = 1 << 16;
    H5Pset_chunk(plist, 1, &chunk);
  }
  const hid_t set = H5Dcreate2(file, path.c_str(), type, space, H5P_DEFAULT, plist, H5P_DEFAULT);
  if (set >= 0 && !huge && n > 0) {
    std::vector<double> values(n, fill);
    H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
  }
  if (set >= 0) H5Dclose(set);
  H5Pclose(plist);
  H5Sclose(space);
}

// Alters the file at `path` as data[0, size) says; returns false if it cannot be opened.
inline bool alter(const std::string& path, const std::uint8_t* data, std::size_t size) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  if (file < 0) return false;
  const Objects o = objects_of(file);
  for (std::size_t i = 0; i + 4 <= size && i < 64; i += 4) {
    const unsigned op = data[i] % 5, target = data[i + 1], v = data[i + 2] | (data[i + 3] << 8);
    if (op <= 1 && !o.attributes.empty()) {  // an attribute: an array, or a hostile number
      const auto& [object, name] = o.attributes[target % o.attributes.size()];
      const hid_t id = H5Oopen(file, object.c_str(), H5P_DEFAULT);
      if (id < 0) continue;
      H5Adelete(id, name.c_str());
      const hsize_t n = op == 0 ? 2 + v % 4 : 1;
      const hid_t space = op == 0 ? H5Screate_simple(1, &n, nullptr) : H5Screate(H5S_SCALAR);
      const bool as_int = v & 1;
      const hid_t a = H5Acreate2(id, name.c_str(), as_int ? H5T_NATIVE_INT64 : H5T_NATIVE_DOUBLE,
                                 space, H5P_DEFAULT, H5P_DEFAULT);
      if (a >= 0) {
        std::vector<std::int64_t> ints(n, hostile_int(v >> 1));
        std::vector<double> doubles(n, hostile_double(v >> 1));
        if (as_int)
          H5Awrite(a, H5T_NATIVE_INT64, ints.data());
        else
          H5Awrite(a, H5T_NATIVE_DOUBLE, doubles.data());
        H5Aclose(a);
      }
      H5Sclose(space);
      H5Oclose(id);
    } else if (op == 2 && !o.datasets.empty()) {  // a dataset of another length
      const std::string& set = o.datasets[target % o.datasets.size()];
      const hsize_t lengths[] = {0, 1, 3, 15, 17, 1000, hsize_t{1} << 36};
      replace_dataset(file, set, lengths[v % std::size(lengths)],
                      (v >> 4) & 1 ? H5T_NATIVE_INT64 : H5T_NATIVE_DOUBLE, hostile_double(v >> 5));
    } else if (!o.datasets.empty()) {  // one element of a dataset, or all of it
      const std::string& path_of_set = o.datasets[target % o.datasets.size()];
      const hid_t set = H5Dopen2(file, path_of_set.c_str(), H5P_DEFAULT);
      if (set < 0) continue;
      const hid_t space = H5Dget_space(set);
      const hssize_t n = H5Sget_simple_extent_npoints(space);
      if (n > 0 && n < (1 << 20)) {
        std::vector<double> values(static_cast<std::size_t>(n));
        if (H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) >= 0) {
          if (op == 3)
            values[v % static_cast<std::size_t>(n)] = hostile_double(v >> 8);
          else
            for (auto& x : values) x = hostile_double(v);
          H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
        }
      }
      H5Sclose(space);
      H5Dclose(set);
    }
  }
  H5Fclose(file);
  return true;
}

}  // namespace qmaps::fuzz
