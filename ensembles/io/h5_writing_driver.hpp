#pragma once
// The file driver of the HDF5 files one process writes: POSIX reads and writes, as HDF5's own
// sec2 driver, except that a file whose write has failed (a full disk, a file-size limit) is one
// qmaps discards, so every later write, flush and truncation of it succeeds without touching it.
// Its close then succeeds: HDF5 1.10 and 1.12 keep the identifier of a file whose close failed
// over freed memory, which their exit handler (or the next file opened) uses, ending the
// process (a Python interpreter) with SIGSEGV.
#include <hdf5.h>

namespace qmaps::h5 {

// Sets the driver on a file-access property list; false where HDF5 refuses it.
bool use_writing_driver(hid_t access);

// Why the last file of this driver closed on this thread is not complete (0: it is): the first
// write that failed, which HDF5 may have passed over, or close(2)'s error. HDF5 is not told at
// its close, which would then fail as above; File::close reports it.
int last_close_error();

}  // namespace qmaps::h5
