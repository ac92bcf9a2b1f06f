#include "ensembles/io/h5_writing_driver.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <mutex>
#include <new>

namespace qmaps::h5 {
namespace {

thread_local int close_error = 0;

#if H5_VERSION_GE(1, 13, 0)
// HDF5 1.13 and later close a file whose flush failed without keeping its identifier, and their
// driver interface differs: their sec2 driver serves.
#else

struct WritingFile {
  H5FD_t base;  // HDF5's part, first
  int fd = -1;
  haddr_t eoa = 0, eof = 0;
  dev_t device = 0;
  ino_t inode = 0;
  int failure = 0;  // the errno of the first write that failed: the rest is not written
};

WritingFile* of(H5FD_t* f) { return reinterpret_cast<WritingFile*>(f); }
const WritingFile* of(const H5FD_t* f) { return reinterpret_cast<const WritingFile*>(f); }

// The failing call's errno stays for the caller's message (ensembles/io/h5.cpp).
herr_t failed(WritingFile* f) {
  f->failure = errno ? errno : EIO;
  errno = f->failure;
  return -1;
}

H5FD_t* open_file(const char* name, unsigned flags, hid_t, haddr_t) {
  int mode = (flags & H5F_ACC_RDWR) ? O_RDWR : O_RDONLY;
  if (flags & H5F_ACC_TRUNC) mode |= O_TRUNC;
  if (flags & H5F_ACC_CREAT) mode |= O_CREAT;
  if (flags & H5F_ACC_EXCL) mode |= O_EXCL;
  const int fd = ::open(name, mode | O_NOFOLLOW | O_CLOEXEC, 0666);
  if (fd < 0) return nullptr;
  struct stat info {};
  if (::fstat(fd, &info) != 0) {
    const int err = errno;
    ::close(fd);
    errno = err;
    return nullptr;
  }
  auto* f = new (std::nothrow) WritingFile{};  // no exception may cross HDF5
  if (!f) {
    ::close(fd);
    errno = ENOMEM;
    return nullptr;
  }
  f->fd = fd;
  f->eof = static_cast<haddr_t>(info.st_size);
  f->device = info.st_dev;
  f->inode = info.st_ino;
  return &f->base;
}

herr_t close_file(H5FD_t* file) {
  WritingFile* f = of(file);
  // HDF5 passes over some failed writes (a metadata flush's): the first is reported here.
  const bool closed = ::close(f->fd) == 0;
  close_error = f->failure ? f->failure : closed ? 0 : errno;
  delete f;
  return 0;
}

int compare(const H5FD_t* a, const H5FD_t* b) {
  const auto* x = of(a);
  const auto* y = of(b);
  if (x->device != y->device) return x->device < y->device ? -1 : 1;
  if (x->inode != y->inode) return x->inode < y->inode ? -1 : 1;
  return 0;
}

herr_t query(const H5FD_t*, unsigned long* flags) {
  if (flags)
    *flags = H5FD_FEAT_AGGREGATE_METADATA | H5FD_FEAT_ACCUMULATE_METADATA | H5FD_FEAT_DATA_SIEVE |
             H5FD_FEAT_AGGREGATE_SMALLDATA | H5FD_FEAT_POSIX_COMPAT_HANDLE |
             H5FD_FEAT_DEFAULT_VFD_COMPATIBLE;
  return 0;
}

haddr_t get_eoa(const H5FD_t* f, H5FD_mem_t) { return of(f)->eoa; }
herr_t set_eoa(H5FD_t* f, H5FD_mem_t, haddr_t addr) {
  of(f)->eoa = addr;
  return 0;
}
haddr_t get_eof(const H5FD_t* f, H5FD_mem_t) { return of(f)->eof; }

herr_t get_handle(H5FD_t* f, hid_t, void** handle) {
  *handle = &of(f)->fd;
  return 0;
}

// Past the end of the file a read gives zeros, as sec2's.
herr_t read(H5FD_t* file, H5FD_mem_t, hid_t, haddr_t addr, size_t size, void* buffer) {
  WritingFile* f = of(file);
  auto* out = static_cast<unsigned char*>(buffer);
  while (size > 0) {
    const ssize_t n = ::pread(f->fd, out, size, static_cast<off_t>(addr));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return -1;
    if (n == 0) {
      std::memset(out, 0, size);
      break;
    }
    out += n;
    addr += static_cast<haddr_t>(n);
    size -= static_cast<size_t>(n);
  }
  return 0;
}

herr_t write(H5FD_t* file, H5FD_mem_t, hid_t, haddr_t addr, size_t size, const void* buffer) {
  WritingFile* f = of(file);
  if (f->failure) return 0;
  const auto* in = static_cast<const unsigned char*>(buffer);
  while (size > 0) {
    const ssize_t n = ::pwrite(f->fd, in, size, static_cast<off_t>(addr));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (n == 0) errno = ENOSPC;
      return failed(f);
    }
    in += n;
    addr += static_cast<haddr_t>(n);
    size -= static_cast<size_t>(n);
  }
  if (addr > f->eof) f->eof = addr;
  return 0;
}

herr_t truncate(H5FD_t* file, hid_t, hbool_t) {
  WritingFile* f = of(file);
  if (f->failure || f->eoa == f->eof) return 0;
  if (::ftruncate(f->fd, static_cast<off_t>(f->eoa)) != 0) return failed(f);
  f->eof = f->eoa;
  return 0;
}

herr_t lock(H5FD_t* f, hbool_t rw) {
  if (::flock(of(f)->fd, (rw ? LOCK_EX : LOCK_SH) | LOCK_NB) == 0) return 0;
  return errno == ENOSYS ? 0 : -1;  // a file system without locks (as sec2)
}

herr_t unlock(H5FD_t* f) {
  if (::flock(of(f)->fd, LOCK_UN) == 0) return 0;
  return errno == ENOSYS ? 0 : -1;
}

const H5FD_class_t writing_class = {
    "qmaps_writing",                        // name
    static_cast<haddr_t>(INT64_MAX),        // maxaddr: off_t's
    H5F_CLOSE_WEAK,                         // fc_degree
    nullptr,                                // terminate
    nullptr, nullptr, nullptr,              // sb_size, sb_encode, sb_decode
    0, nullptr, nullptr, nullptr,           // fapl
    0, nullptr, nullptr,                    // dxpl
    open_file, close_file, compare, query,  //
    nullptr,                                // get_type_map
    nullptr, nullptr,                       // alloc, free
    get_eoa, set_eoa, get_eof, get_handle,  //
    read, write,                            //
    nullptr,                                // flush: nothing is buffered here
    truncate, lock, unlock,                 //
    H5FD_FLMAP_DICHOTOMY,                   // fl_map
};

hid_t writing_driver() {
  static std::mutex registering;
  static hid_t id = H5I_INVALID_HID;
  const std::lock_guard hold(registering);
  if (id < 0 || H5Iis_valid(id) <= 0) id = H5FDregister(&writing_class);
  return id;
}

#endif

}  // namespace

bool use_writing_driver(hid_t access) {
#if H5_VERSION_GE(1, 13, 0)
  (void)access;
  return true;
#else
  const hid_t driver = writing_driver();
  return driver >= 0 && H5Pset_driver(access, driver, nullptr) >= 0;
#endif
}

int last_close_error() {
  const int err = close_error;
  close_error = 0;
  return err;
}

}  // namespace qmaps::h5
