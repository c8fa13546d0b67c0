// Putting the finished file in place, durably: its data reaches the disk before its name does,
// and the name before the caller removes the journal (a node crash in between must not leave a
// truncated file and no journal). Both throw std::runtime_error with the reason.
#pragma once

#include <string>

namespace cs {

// Without `replace`, a file that appeared at `final_path` while the run computed is never
// replaced: link() fails if the name exists, where rename() would silently overwrite it.
void place_durably(const std::string& partial_path, const std::string& final_path, bool replace);

// Makes the entries of the directory `path` (a file just named in it, a directory just made in
// it) survive a power cut.
void sync_directory(const std::string& path);

// Proves the disk (and the user's quota, which free-space figures do not show) has room
// for the whole file before HDF5 writes a byte of it. HDF5 does not recover from a full disk in
// the middle of a file, so the space is claimed with fallocate and released right before HDF5
// creates the file. Another program may take it in between: that rare case still fails cleanly
// (see hdf5_files_left_open).
void check_room_for(const std::string& path, double bytes);

}  // namespace cs
