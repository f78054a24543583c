#pragma once
// acuity/file.hpp — whole-file reads and atomic writes, shared by the runtime and the offline tools.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace acuity {

// Bytes in 8-byte-aligned memory (what open_profile() needs): a file read, or an encoded profile.
struct Blob {
  std::vector<std::uint64_t> storage;
  std::size_t size = 0;
  const void* data() const { return storage.data(); }
};

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
