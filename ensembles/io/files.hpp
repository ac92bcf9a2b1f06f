#pragma once
// The file system as qmaps meets it on shared machines: inputs are regular files read with a
// bound; an output replaces only a regular file (never a link, a device, a FIFO or a folder) in a
// folder where the final rename is permitted; temporaries of dead writers are removed. Every
// failure is a qmaps::Error(io) naming the path and the reason.
#include <cstddef>
#include <string>

namespace qmaps::files {

// Throws unless `path` names a regular file that can be opened for reading (it is opened without
// blocking, so a FIFO is refused rather than waited on); `what` names it in messages ("config
// file"; empty: the path alone).
void check_regular_input(const std::string& path, const std::string& what);

// The whole of the regular file `path`, refused (usage error) when it holds more than
// `max_bytes`: never more than max_bytes + 1 bytes are read, whatever the file claims.
std::string read_regular_file(const std::string& path, std::size_t max_bytes,
                              const std::string& what);

// Throws unless `path` can become a run's output by a rename at the end: where it exists it is
// a regular file (not a link, device, FIFO or folder) that this user may replace (in a sticky
// folder, the user's own or the folder's owner's), and its folder exists and can be written.
void check_output_target(const std::string& path);

// Removes "<path>.tmp-<digits>" files other than this process's: call it only while holding the
// output's lock (ensembles/io/output_lock.hpp), so that no live writer owns them.
void remove_stale_temporaries(const std::string& path);

// strerror(error), with the open-file limit named where that is the reason (EMFILE).
std::string reason(int error);
// "'path': " + reason(error).
std::string open_failure(const std::string& path, int error);

}  // namespace qmaps::files
