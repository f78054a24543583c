#pragma once
// acuity/file.hpp — whole-file reads and atomic writes, for the offline libraries and tools (never the runtime).
#include <cstddef>
#include <string>

#include "acuity/blob.hpp"

namespace acuity {

// Reads the whole file, which must be a regular file: a directory, FIFO or device is refused
// without waiting on it (opened non-blocking, then checked with fstat). Returns false and sets
// *error ("path: reason") when it cannot.
bool read_file(const std::string& path, Blob* out, std::string* error);

// Writes to a temporary file beside `path`, flushes it, then renames it over `path`: readers see
// the old file or the whole new one, never a part. Returns false and sets *error on failure, and
// then leaves no temporary behind. The file gets mode 0644. An existing `path` that is not a
// regular file (a device such as /dev/null, a FIFO, a directory, a symbolic link) is refused, not
// replaced. SIGINT, SIGTERM, SIGHUP and SIGQUIT are held while the temporary exists (delivered on
// return), so a signal never leaves one behind.
bool write_file_atomically(const std::string& path, const void* data, std::size_t size, std::string* error);

}  // namespace acuity
