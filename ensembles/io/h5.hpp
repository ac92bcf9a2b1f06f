#pragma once
// HDF5 (C API) with RAII: every handle closes itself; every failure is a qmaps::Error naming the
// file and the object. AtomicFile writes under a temporary name and renames when complete.
// A shared file (qmaps-mpi, parallel HDF5) is written by every rank together (ensembles/io/ranks.hpp):
// each call on it is collective; whole datasets are rank 0's, and each rank writes its own part
// of a column, with as many write_part calls on every rank (empty ones where it has no more).
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <hdf5.h>

#include "core/error.hpp"
#include "ensembles/io/ranks.hpp"

namespace qmaps::h5 {

// An HDF5 identifier and the function that closes it.
class Handle {
 public:
  Handle() = default;
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  Handle(Handle&& o) noexcept : id_(o.id_), close_(o.close_) { o.id_ = H5I_INVALID_HID; }
  Handle& operator=(Handle&& o) noexcept;
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { reset(); }
  hid_t id() const { return id_; }
  void reset();
  herr_t close();  // closes now (the close's status; 0 where there was nothing to close)
  hid_t release() {  // gives up the id without closing it
    const hid_t id = id_;
    id_ = H5I_INVALID_HID;
    return id;
  }

 private:
  hid_t id_ = H5I_INVALID_HID;
  herr_t (*close_)(hid_t) = nullptr;
};

// A group (or the file's root group) and what qmaps writes into and reads from it.
class Group {
 public:
  // `deflate`: the gzip level (1-9) of the datasets written here and in groups created from
  // here, chunked and shuffled; 0: contiguous and uncompressed.
  Group(Handle h, std::string path, int deflate = 0, bool shared = false)
      : h_(std::move(h)), path_(std::move(path)), deflate_(deflate), shared_(shared) {}
  Group create_group(const std::string& name) const;
  Group open_group(const std::string& name) const;
  // The group at a relative path "a/b/c", each group on the way that is missing created.
  Group group_at(const std::string& path) const;
  bool has(const std::string& name) const;
  bool has_group(const std::string& name) const;  // a member that is a group (a hard link to one)
  std::vector<std::string> members() const;
  const std::string& path() const { return path_; }
  // An io error about this group: "HDF5: <path>: <what>".
  Error error(const std::string& what) const;

  void write(const std::string& name, std::span<const double> data) const;
  void write(const std::string& name, std::span<const std::int64_t> data) const;
  void write(const std::string& name, std::span<const std::uint8_t> data) const;
  // A dataset of shape `dims` (row-major data).
  void write(const std::string& name, std::span<const std::int64_t> data,
             std::span<const hsize_t> dims) const;
  std::vector<hsize_t> shape(const std::string& name) const;
  // A one-dimensional dataset of n elements of T (double, std::int64_t or std::uint8_t), created
  // empty, then written (and read) in parts, so that no full-size copy is ever needed.
  template <class T>
  void create_column(const std::string& name, std::size_t n) const;
  template <class T>
  void write_part(const std::string& name, std::size_t first, std::span<const T> data) const;
  template <class T>
  void read_part(const std::string& name, std::size_t first, std::span<T> out) const;
  // Whole datasets of exactly `expected` elements; any other size is an error before any read.
  std::vector<double> read_doubles(const std::string& name, std::size_t expected) const;
  std::vector<std::int64_t> read_int64(const std::string& name, std::size_t expected) const;
  std::vector<std::uint8_t> read_uint8(const std::string& name, std::size_t expected) const;

  void attr(const std::string& name, const std::string& value) const;
  void attr(const std::string& name, const char* value) const { attr(name, std::string(value)); }
  void attr(const std::string& name, double value) const;
  void attr(const std::string& name, std::int64_t value) const;
  bool has_attr(const std::string& name) const;
  std::string attr_string(const std::string& name) const;
  double attr_double(const std::string& name) const;
  std::int64_t attr_int64(const std::string& name) const;
  std::vector<std::string> attr_names() const;

  hid_t id() const { return h_.id(); }

 private:
  Handle h_;
  std::string path_;
  int deflate_ = 0;
  bool shared_ = false;
};

class File {
 public:
  static File create(const std::string& path);     // truncates
  static File open_read(const std::string& path);
  Group root() const;
  // Closes the file, flushing it: a failure (a full disk, a file-size limit) is an io error
  // naming the file, so that an incomplete file is never committed.
  void close();
  const std::string& path() const { return path_; }

 private:
  friend class AtomicFile;
  File(Handle h, std::string path, int deflate = 0, bool shared = false)
      : h_(std::move(h)), path_(std::move(path)), deflate_(deflate), shared_(shared) {}
  Handle h_;
  std::string path_;
  int deflate_ = 0;  // the gzip level of the datasets written from root() on (0: none)
  bool shared_ = false;
};

// A file written under "<path>.tmp-<pid>" and renamed to <path> by commit(); destroyed without
// commit, the temporary is removed. A killed process leaves no file under the final name.
// Constructed, it has checked that <path> can be replaced (ensembles/io/files.hpp: a regular file or
// none, in a folder that can be written); commit() checks it again just before the rename.
// Construct it under the output's lock (ensembles/io/output_lock.hpp). Shared (by default where
// there are several ranks; every rank's call), the temporary is named by rank 0's pid, and rank
// 0 alone renames or removes it.
class AtomicFile {
 public:
  explicit AtomicFile(std::string path, bool shared = ranks::count() > 1);
  // Throws the io error the constructor would for `path` (ensembles/io/files.hpp's
  // check_output_target), with no other effect.
  static void check_writable(const std::string& path);
  // The HDF5 file at the temporary, its datasets gzip-compressed at level `deflate` (1-9; 0:
  // none); errors name <path>.
  File create_hdf5(int deflate = 0) const;
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();
  const std::string& temporary() const { return temporary_; }
  const std::string& path() const { return path_; }
  void commit();
  // Removes the temporary now, as destruction would, for an output that will not be committed;
  // the file open on it stays usable until closed.
  void discard();

 private:
  std::string path_, temporary_;
  bool shared_ = false;
  bool committed_ = false;
};

}  // namespace qmaps::h5
