#include "ensembles/io/h5.hpp"

#include <algorithm>

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <type_traits>

#include "core/error.hpp"
#include "ensembles/io/files.hpp"
#include "ensembles/io/h5_writing_driver.hpp"
#include "ensembles/io/ranks.hpp"

namespace qmaps::h5 {
namespace {

// HDF5 prints its error stack by default, in each thread until told otherwise there (a
// thread-safe build keeps the setting per thread); qmaps reports errors itself. Every file is
// created or opened through quiet().
void quiet() {
  thread_local const bool silenced = [] {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    return true;
  }();
  (void)silenced;
}

Error failure(const std::string& what) { return Error(ExitCode::io, "HDF5: " + what); }

hid_t checked(hid_t id, const std::string& what) {
  if (id < 0) throw failure(what);
  return id;
}

void checked(herr_t status, const std::string& what, int) {
  if (status < 0) throw failure(what);
}

// How a dataset of shape `dims` is stored: contiguous (deflate 0), or in chunks of at most 2^16
// elements along the first axis, shuffled and gzip-compressed at level `deflate`. Never filled
// with a fill value first: every dataset is written in full before its file is committed, so
// filling would only write the file twice.
Handle creation_properties(std::span<const hsize_t> dims, int deflate) {
  Handle plist(checked(H5Pcreate(H5P_DATASET_CREATE), "dataset properties"), H5Pclose);
  checked(H5Pset_fill_time(plist.id(), H5D_FILL_TIME_NEVER), "fill time", 0);
  hsize_t elements = 1;
  for (hsize_t d : dims) elements *= d;
  if (deflate > 0 && elements > 0) {
    std::vector<hsize_t> chunk(dims.begin(), dims.end());
    const hsize_t row = elements / dims[0];
    chunk[0] = std::max<hsize_t>(1, std::min<hsize_t>(dims[0], (hsize_t{1} << 16) / row));
    checked(H5Pset_chunk(plist.id(), static_cast<int>(chunk.size()), chunk.data()), "chunks", 0);
    checked(H5Pset_shuffle(plist.id()), "shuffle filter", 0);
    checked(H5Pset_deflate(plist.id(), static_cast<unsigned>(deflate)), "gzip filter", 0);
  }
  return plist;
}

// The transfer properties of a file's writes and reads: collective where the file is shared.
Handle transfer(bool shared) {
  Handle plist(checked(H5Pcreate(H5P_DATASET_XFER), "transfer properties"), H5Pclose);
  if (shared) {
#ifdef H5_HAVE_PARALLEL
    checked(H5Pset_dxpl_mpio(plist.id(), H5FD_MPIO_COLLECTIVE), "collective transfer", 0);
#else
    throw failure("a shared file needs parallel HDF5");
#endif
  }
  return plist;
}

// Rank 0's values, on every rank (as many on each): what a shared file records is rank 0's.
template <class T>
void rank0s(std::span<T> values) {
  ranks::from_root(std::as_writable_bytes(values));
}

// Selects nothing of `space`: a rank's part of a collective transfer where it has none.
void select_none(hid_t space, const std::string& what) {
  checked(H5Sselect_none(space), "selection in " + what, 0);
}

// A new dataset of shape `dims` (on a shared file, rank 0's), not yet written.
Handle create_nd(hid_t parent, const std::string& what, const std::string& name, hid_t type,
                 std::span<const hsize_t> dims_given, int deflate, bool shared) {
  std::vector<hsize_t> dims(dims_given.begin(), dims_given.end());
  if (shared) rank0s(std::span(dims));
  Handle space(checked(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr),
                       "dataspace"),
               H5Sclose);
  const Handle properties = creation_properties(dims, deflate);
  return Handle(checked(H5Dcreate2(parent, name.c_str(), type, space.id(), H5P_DEFAULT,
                                   properties.id(), H5P_DEFAULT),
                        "cannot create dataset " + what),
                H5Dclose);
}

// A dataset of shape `dims` holding `data`; on a shared file, rank 0's shape and data.
template <class T>
void write_nd(hid_t parent, const std::string& where, const std::string& name, hid_t type,
              std::span<const T> data, std::span<const hsize_t> dims, int deflate, bool shared) {
  const std::string what = where + "/" + name;
  const Handle set = create_nd(parent, what, name, type, dims, deflate, shared);
  Handle space(checked(H5Dget_space(set.id()), "dataspace of " + what), H5Sclose);
  if (H5Sget_simple_extent_npoints(space.id()) == 0) return;
  if (!shared) {
    checked(H5Dwrite(set.id(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()),
            "cannot write dataset " + what, 0);
    return;
  }
  Handle memory_space(checked(H5Scopy(space.id()), "dataspace"), H5Sclose);
  const T none{};
  if (!ranks::root()) {
    select_none(space.id(), what);
    select_none(memory_space.id(), what);
  }
  const Handle xfer = transfer(true);
  checked(H5Dwrite(set.id(), type, memory_space.id(), space.id(), xfer.id(),
                   ranks::root() ? data.data() : &none),
          "cannot write dataset " + what, 0);
}
template <class T>
void write_1d(hid_t parent, const std::string& where, const std::string& name, hid_t type,
              std::span<const T> data, int deflate, bool shared) {
  const hsize_t dims[1] = {data.size()};
  write_nd(parent, where, name, type, data, std::span<const hsize_t>(dims), deflate, shared);
}

// The dataset `name`, which must hold `expected` elements (its shape is checked before anything
// is allocated or read: a file's own sizes are not trusted).
template <class T>
std::vector<T> read_1d(hid_t parent, const std::string& where, const std::string& name,
                       hid_t type, std::size_t expected) {
  Handle set(checked(H5Dopen2(parent, name.c_str(), H5P_DEFAULT),
                     "no dataset " + where + "/" + name),
             H5Dclose);
  Handle space(checked(H5Dget_space(set.id()), "dataspace of " + name), H5Sclose);
  const hssize_t n = H5Sget_simple_extent_npoints(space.id());  // every element, row-major
  if (n < 0 || static_cast<std::size_t>(n) != expected)
    throw failure("dataset " + where + "/" + name + " holds " + std::to_string(n) +
                  " elements, not " + std::to_string(expected));
  std::vector<T> out(static_cast<std::size_t>(n));
  if (n > 0)
    checked(H5Dread(set.id(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()),
            "cannot read " + where + "/" + name, 0);
  return out;
}

template <class T>
hid_t native_type() {
  if constexpr (std::is_same_v<T, double>) return H5T_NATIVE_DOUBLE;
  else if constexpr (std::is_same_v<T, std::int64_t>) return H5T_NATIVE_INT64;
  else return H5T_NATIVE_UINT8;
}

// The dataset `name` of `parent` with elements [first, first + count) selected in its file space,
// and a memory space of count elements; the transfer `io` (H5Dwrite or H5Dread) runs on them
// with the transfer properties it is given. On a shared file every rank runs it, collectively,
// an empty part selecting nothing.
template <class Transfer>
void transfer_part(hid_t parent, const std::string& where, const std::string& name,
                   std::size_t first, std::size_t count, bool shared, Transfer io) {
  const std::string what = where + "/" + name;
  Handle set(checked(H5Dopen2(parent, name.c_str(), H5P_DEFAULT), "no dataset " + what),
             H5Dclose);
  Handle file_space(checked(H5Dget_space(set.id()), "dataspace of " + what), H5Sclose);
  const hsize_t start[1] = {first}, size[1] = {count};
  if (H5Sget_simple_extent_ndims(file_space.id()) != 1 ||
      first + count > static_cast<std::size_t>(H5Sget_simple_extent_npoints(file_space.id())))
    throw failure("elements [" + std::to_string(first) + ", " + std::to_string(first + count) +
                  ") are not in the one-dimensional dataset " + what);
  if (count == 0 && !shared) return;
  Handle memory_space(checked(H5Screate_simple(1, size, nullptr), "dataspace"), H5Sclose);
  if (count == 0) {
    select_none(file_space.id(), what);
    select_none(memory_space.id(), what);
  } else {
    checked(H5Sselect_hyperslab(file_space.id(), H5S_SELECT_SET, start, nullptr, size, nullptr),
            "selection in " + what, 0);
  }
  const Handle xfer = transfer(shared);
  errno = 0;
  if (io(set.id(), memory_space.id(), file_space.id(), xfer.id()) < 0) {
    // The reason of a write the file system refused (a full disk, a file-size limit).
    const int err = errno;
    const bool refused = err == ENOSPC || err == EFBIG || err == EDQUOT || err == EIO;
    throw failure("cannot transfer " + what + (refused ? ": " + files::reason(err) : ""));
  }
}

void write_attr(hid_t obj, const std::string& name, hid_t type, hid_t space, const void* value) {
  if (H5Aexists(obj, name.c_str()) > 0) H5Adelete(obj, name.c_str());
  Handle a(checked(H5Acreate2(obj, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT),
                   "cannot create attribute " + name),
           H5Aclose);
  checked(H5Awrite(a.id(), type, value), "cannot write attribute " + name, 0);
}

// The attribute `name` of obj, which must hold one value (an array is refused before any read).
Handle open_attr(hid_t obj, const std::string& where, const std::string& name) {
  Handle a(checked(H5Aopen(obj, name.c_str(), H5P_DEFAULT), "no attribute '" + name + "' on " + where),
           H5Aclose);
  Handle space(checked(H5Aget_space(a.id()), "dataspace of attribute " + name), H5Sclose);
  const hssize_t n = H5Sget_simple_extent_npoints(space.id());
  if (n != 1)
    throw failure("attribute '" + name + "' on " + where + " holds " + std::to_string(n) +
                  " values, not one");
  return a;
}

}  // namespace

Handle& Handle::operator=(Handle&& o) noexcept {
  if (this != &o) {
    reset();
    id_ = o.id_;
    close_ = o.close_;
    o.id_ = H5I_INVALID_HID;
  }
  return *this;
}

herr_t Handle::close() {
  const auto close = close_;
  const hid_t id = release();
  return id >= 0 && close ? close(id) : 0;
}

void Handle::reset() {
  // A group or dataset closed already with its file (H5F_CLOSE_STRONG) is not closed again.
  if (id_ >= 0 && close_ && H5Iis_valid(id_) > 0) close_(id_);
  id_ = H5I_INVALID_HID;
}

Group Group::create_group(const std::string& name) const {
  return Group(Handle(checked(H5Gcreate2(id(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT,
                                         H5P_DEFAULT),
                              "cannot create group " + path_ + "/" + name),
                      H5Gclose),
               path_ == "/" ? "/" + name : path_ + "/" + name, deflate_, shared_);
}

Group Group::open_group(const std::string& name) const {
  return Group(Handle(checked(H5Gopen2(id(), name.c_str(), H5P_DEFAULT),
                              "no group " + path_ + "/" + name),
                      H5Gclose),
               path_ == "/" ? "/" + name : path_ + "/" + name, deflate_, shared_);
}

Group Group::group_at(const std::string& path) const {
  const std::size_t slash = path.find('/');
  const std::string name = path.substr(0, slash);
  Group g = has(name) ? open_group(name) : create_group(name);
  return slash == std::string::npos ? std::move(g) : g.group_at(path.substr(slash + 1));
}

bool Group::has(const std::string& name) const { return H5Lexists(id(), name.c_str(), H5P_DEFAULT) > 0; }

bool Group::has_group(const std::string& name) const {
  H5L_info_t link{};
  if (!has(name) || H5Lget_info(id(), name.c_str(), &link, H5P_DEFAULT) < 0 ||
      link.type != H5L_TYPE_HARD)
    return false;
  H5O_info_t object{};
  return H5Oget_info_by_name2(id(), name.c_str(), &object, H5O_INFO_BASIC, H5P_DEFAULT) >= 0 &&
         object.type == H5O_TYPE_GROUP;
}

Error Group::error(const std::string& what) const { return failure(path_ + ": " + what); }

std::vector<std::string> Group::members() const {
  std::vector<std::string> out;
  H5Literate(
      id(), H5_INDEX_NAME, H5_ITER_INC, nullptr,
      [](hid_t, const char* name, const H5L_info_t*, void* data) -> herr_t {
        static_cast<std::vector<std::string>*>(data)->emplace_back(name);
        return 0;
      },
      &out);
  return out;
}

void Group::write(const std::string& name, std::span<const double> data) const {
  write_1d(id(), path_, name, H5T_NATIVE_DOUBLE, data, deflate_, shared_);
}
void Group::write(const std::string& name, std::span<const std::int64_t> data) const {
  write_1d(id(), path_, name, H5T_NATIVE_INT64, data, deflate_, shared_);
}
void Group::write(const std::string& name, std::span<const std::uint8_t> data) const {
  write_1d(id(), path_, name, H5T_NATIVE_UINT8, data, deflate_, shared_);
}
void Group::write(const std::string& name, std::span<const std::int64_t> data,
                  std::span<const hsize_t> dims) const {
  write_nd(id(), path_, name, H5T_NATIVE_INT64, data, dims, deflate_, shared_);
}

std::vector<hsize_t> Group::shape(const std::string& name) const {
  Handle set(checked(H5Dopen2(id(), name.c_str(), H5P_DEFAULT), "no dataset " + path_ + "/" + name),
             H5Dclose);
  Handle space(checked(H5Dget_space(set.id()), "dataspace of " + name), H5Sclose);
  std::vector<hsize_t> dims(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space.id())));
  H5Sget_simple_extent_dims(space.id(), dims.data(), nullptr);
  return dims;
}

template <class T>
void Group::create_column(const std::string& name, std::size_t n) const {
  const hsize_t dims[1] = {n};
  create_nd(id(), path_ + "/" + name, name, native_type<T>(), std::span<const hsize_t>(dims),
            deflate_, shared_);
}

template <class T>
void Group::write_part(const std::string& name, std::size_t first, std::span<const T> data) const {
  transfer_part(id(), path_, name, first, data.size(), shared_,
                [&](hid_t set, hid_t memory, hid_t file, hid_t xfer) {
                  return H5Dwrite(set, native_type<T>(), memory, file, xfer, data.data());
                });
}

template <class T>
void Group::read_part(const std::string& name, std::size_t first, std::span<T> out) const {
  transfer_part(id(), path_, name, first, out.size(), shared_,
                [&](hid_t set, hid_t memory, hid_t file, hid_t xfer) {
                  return H5Dread(set, native_type<T>(), memory, file, xfer, out.data());
                });
}

#define QMAPS_H5_COLUMN(T)                                                                  \
  template void Group::create_column<T>(const std::string&, std::size_t) const;             \
  template void Group::write_part<T>(const std::string&, std::size_t, std::span<const T>) const; \
  template void Group::read_part<T>(const std::string&, std::size_t, std::span<T>) const;
QMAPS_H5_COLUMN(double)
QMAPS_H5_COLUMN(std::int64_t)
QMAPS_H5_COLUMN(std::uint8_t)
#undef QMAPS_H5_COLUMN

std::vector<double> Group::read_doubles(const std::string& name, std::size_t expected) const {
  return read_1d<double>(id(), path_, name, H5T_NATIVE_DOUBLE, expected);
}
std::vector<std::int64_t> Group::read_int64(const std::string& name, std::size_t expected) const {
  return read_1d<std::int64_t>(id(), path_, name, H5T_NATIVE_INT64, expected);
}
std::vector<std::uint8_t> Group::read_uint8(const std::string& name, std::size_t expected) const {
  return read_1d<std::uint8_t>(id(), path_, name, H5T_NATIVE_UINT8, expected);
}

void Group::attr(const std::string& name, const std::string& given) const {
  const std::string value = shared_ ? ranks::from_root(given) : given;
  Handle type(checked(H5Tcopy(H5T_C_S1), "string type"), H5Tclose);
  H5Tset_size(type.id(), value.empty() ? 1 : value.size());
  H5Tset_cset(type.id(), H5T_CSET_UTF8);
  Handle space(checked(H5Screate(H5S_SCALAR), "scalar space"), H5Sclose);
  write_attr(id(), name, type.id(), space.id(), value.empty() ? "" : value.data());
}
void Group::attr(const std::string& name, double value) const {
  if (shared_) rank0s(std::span(&value, 1));
  Handle space(checked(H5Screate(H5S_SCALAR), "scalar space"), H5Sclose);
  write_attr(id(), name, H5T_NATIVE_DOUBLE, space.id(), &value);
}
void Group::attr(const std::string& name, std::int64_t value) const {
  if (shared_) rank0s(std::span(&value, 1));
  Handle space(checked(H5Screate(H5S_SCALAR), "scalar space"), H5Sclose);
  write_attr(id(), name, H5T_NATIVE_INT64, space.id(), &value);
}

bool Group::has_attr(const std::string& name) const { return H5Aexists(id(), name.c_str()) > 0; }

std::string Group::attr_string(const std::string& name) const {
  Handle a = open_attr(id(), path_, name);
  Handle type(checked(H5Aget_type(a.id()), "attribute type"), H5Tclose);
  if (H5Tget_class(type.id()) != H5T_STRING) throw failure("attribute " + name + " is not a string");
  if (H5Tis_variable_str(type.id()) > 0) {
    char* text = nullptr;
    Handle mem(checked(H5Tcopy(H5T_C_S1), "string type"), H5Tclose);
    H5Tset_size(mem.id(), H5T_VARIABLE);
    checked(H5Aread(a.id(), mem.id(), &text), "cannot read attribute " + name, 0);
    std::string out = text ? text : "";
    H5free_memory(text);
    return out;
  }
  const std::size_t n = H5Tget_size(type.id());
  std::string out(n, '\0');
  checked(H5Aread(a.id(), type.id(), out.data()), "cannot read attribute " + name, 0);
  out.resize(std::strlen(out.c_str()));
  return out;
}

double Group::attr_double(const std::string& name) const {
  Handle a = open_attr(id(), path_, name);
  double v = 0;
  checked(H5Aread(a.id(), H5T_NATIVE_DOUBLE, &v), "cannot read attribute " + name, 0);
  return v;
}

std::int64_t Group::attr_int64(const std::string& name) const {
  Handle a = open_attr(id(), path_, name);
  std::int64_t v = 0;
  checked(H5Aread(a.id(), H5T_NATIVE_INT64, &v), "cannot read attribute " + name, 0);
  return v;
}

std::vector<std::string> Group::attr_names() const {
  std::vector<std::string> out;
  H5Aiterate2(
      id(), H5_INDEX_NAME, H5_ITER_INC, nullptr,
      [](hid_t, const char* name, const H5A_info_t*, void* data) -> herr_t {
        static_cast<std::vector<std::string>*>(data)->emplace_back(name);
        return 0;
      },
      &out);
  return out;
}

namespace {

// A new file whose close() closes it whatever groups and datasets of it are still open (they
// are closed with it): a file is complete on disk, its errors reported, when close() returns,
// and not only when the last of its groups goes.
// Shared: every rank's call, through MPI-IO.
hid_t create_file(const std::string& path, bool shared = false) {
  quiet();
  const Handle access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  if (access.id() < 0 || H5Pset_fclose_degree(access.id(), H5F_CLOSE_STRONG) < 0) return -1;
  if (shared) {
#ifdef H5_HAVE_PARALLEL
    if (H5Pset_fapl_mpio(access.id(), MPI_COMM_WORLD, MPI_INFO_NULL) < 0) return -1;
#else
    return -1;
#endif
  } else if (!use_writing_driver(access.id())) {
    return -1;
  }
  return H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.id());
}

// Closes a file written by this process alone, its flush first: a write that fails leaves the
// rest of the file to be discarded by its driver (ensembles/io/h5_writing_driver.hpp), so that the
// close itself succeeds, and the driver names the failure (errno). A shared file (MPI-IO) is
// closed by H5Fclose, in one collective call.
herr_t close_written(hid_t id) {
  const bool flushed = H5Fflush(id, H5F_SCOPE_LOCAL) >= 0;
  const bool closed = H5Fclose(id) >= 0;
  errno = last_close_error();
  return flushed && closed && errno == 0 ? 0 : -1;
}

}  // namespace

File File::create(const std::string& path) {
  const hid_t id = create_file(path);
  if (id < 0) throw Error(ExitCode::io, "cannot create output file '" + path + "'");
  return File(Handle(id, close_written), path);
}

void File::close() {
  errno = 0;
  if (h_.close() < 0) {
    const int err = errno;
    throw Error(ExitCode::io, "cannot complete '" + path_ + "'" +
                                  (err ? std::string(": ") + std::strerror(err) : std::string()));
  }
}

File File::open_read(const std::string& path) {
  files::check_regular_input(path, "");
  quiet();
  errno = 0;
  const hid_t id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (id < 0 && (errno == EMFILE || errno == ENFILE))
    throw Error(ExitCode::io, "cannot read " + files::open_failure(path, errno));
  if (id < 0) throw Error(ExitCode::io, "'" + path + "' is not an HDF5 file");
  return File(Handle(id, H5Fclose), path);
}

Group File::root() const {
  return Group(Handle(checked(H5Gopen2(h_.id(), "/", H5P_DEFAULT), "root group of " + path_),
                      H5Gclose),
               "/", deflate_, shared_);
}

AtomicFile::AtomicFile(std::string path, bool shared) : path_(std::move(path)), shared_(shared) {
  const std::string pid = std::to_string(getpid());
  temporary_ = path_ + ".tmp-" + (shared_ ? ranks::from_root(pid) : pid);
  check_writable(path_);  // on every rank, before any of them creates the file
}

void AtomicFile::check_writable(const std::string& path) { files::check_output_target(path); }

File AtomicFile::create_hdf5(int deflate) const {
  errno = 0;
  const hid_t id = create_file(temporary_, shared_);
  if (id < 0) {
    const int err = errno;
    throw Error(ExitCode::io, "cannot create output file '" + path_ + "'" +
                                  (err ? ": " + files::reason(err) : std::string()));
  }
  return File(Handle(id, shared_ ? H5Fclose : close_written), temporary_, deflate, shared_);
}

AtomicFile::~AtomicFile() { discard(); }

void AtomicFile::discard() {
  if (!committed_ && (!shared_ || ranks::root())) std::remove(temporary_.c_str());
}

void AtomicFile::commit() {
  ranks::Failure failure;
  if (!shared_ || ranks::root()) try {
      files::check_output_target(path_);  // what the name holds now: still no link or device
    } catch (const Error& e) {
      failure = {static_cast<int>(ExitCode::io), e.what()};
    }
  if (failure.code == 0 && (!shared_ || ranks::root()) && std::rename(temporary_.c_str(), path_.c_str()) != 0)
    failure = {static_cast<int>(ExitCode::io), "cannot rename '" + temporary_ + "' to '" + path_ +
                                                   "': " + std::strerror(errno)};
  if (shared_) failure = ranks::first_failure(failure);
  if (failure.code != 0 && shared_) throw ranks::FailedOnEveryRank(ExitCode::io, failure.message);
  if (failure.code != 0) throw Error(ExitCode::io, failure.message);
  committed_ = true;
}

}  // namespace qmaps::h5
