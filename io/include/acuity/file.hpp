#pragma once
// acuity/file.hpp — the offline libraries' one file seam (never the runtime): bounded reads of
// regular files, optionally confined to a folder; the checks an output path passes before any work;
// atomic writes (temporary file, fsync, rename); a file's extension. POSIX.
//
// Errors: every function here reports a failure by throwing acuity::io::Error, which carries the
// path at fault and what is wrong with it (what() is "path: reason"). None returns a status. A
// caller that may go on without the file (a cache probe) catches io::Error; the others let it
// reach the command, which prints what() (the Python module raises it as acuity.FileError, a
// ValueError).
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "acuity/blob.hpp"

namespace acuity::io {

// A file that cannot be read or written as asked: which file, and why.
class Error : public std::runtime_error {
 public:
  Error(const std::string& path, const std::string& reason);
  const std::string& path() const noexcept { return path_; }      // as the caller gave it
  const std::string& reason() const noexcept { return reason_; }  // e.g. "is a FIFO, not a regular file"

 private:
  std::string path_, reason_;
};

// What a read may take, and from where.
struct ReadLimits {
  // Larger files are refused before a byte is read. [Unit: bytes]
  std::uint64_t max_bytes = std::numeric_limits<std::uint64_t>::max();
  // Names the limit in the error: "N bytes, more than <max_bytes_name> (max_bytes)".
  std::string max_bytes_name = "the size limit";
  // When not empty: the file, with ".." and symbolic links resolved, must lie inside this folder
  // (itself resolved), and is opened without following a symbolic link in its last component.
  std::string root;
};

// Reads the whole file. It must be a regular file: a directory, FIFO or device is refused without
// waiting on it (opened non-blocking, then checked with fstat on the open descriptor, so the
// check and the read see the same file), as is one larger than limits.max_bytes or outside
// limits.root. Throws Error naming the path: missing, unreadable, not regular, too large, outside
// the root, or changed while read.
Blob read_file(const std::string& path, const ReadLimits& limits = {});
// The same read into bytes (what tinygltf's callbacks take).
void read_file(const std::string& path, const ReadLimits& limits, std::vector<unsigned char>* out);

// The checks read_file makes (regular file, size, root), without reading; returns the file's size
// in bytes. For readers that must open the file themselves (OpenMesh). Throws Error as read_file.
std::uint64_t check_input(const std::string& path, const ReadLimits& limits = {});

// `path` with "." , ".." and symbolic links resolved (weakly: a missing tail is kept as written),
// when it lies inside the folder `root` (resolved the same way; a file is inside when it is below
// the folder, never the folder itself). Throws Error naming `path` otherwise.
std::string confine(const std::string& path, const std::string& root);

// Throws Error unless `output` may be written: an existing output must be a regular file (never a
// device, FIFO, directory or symbolic link) and not the same file (device and inode) as any of
// `inputs`, nor the same path; its folder must exist and be writable; when `extensions` is not
// empty, lower_extension(output) must be one of them (lower case, with the dot).
void check_output(const std::string& output, const std::vector<std::string>& inputs,
                  const std::vector<std::string>& extensions = {});

// Throws Error unless files can be written into `folder`: an existing one must be a writable
// directory; else its nearest existing ancestor must be (the folder is created later). An empty
// `folder` (no output) passes.
void check_output_folder(const std::string& folder);

// Writes to a temporary file beside `path`, flushes it, then renames it over `path`: readers see
// the old file or the whole new one, never a part. On failure throws Error and leaves no temporary
// behind. The file gets mode 0644. An existing `path` that is not a regular file (a device such as
// /dev/null, a FIFO, a directory, a symbolic link) is refused, not replaced (checked before the
// temporary is made and again just before the rename). SIGINT, SIGTERM, SIGHUP and SIGQUIT are
// held while the temporary exists (delivered on return), so a signal never leaves one behind.
void write_file_atomically(const std::string& path, const void* data, std::size_t size);
inline void write_file_atomically(const std::string& path, std::string_view bytes) {
  write_file_atomically(path, bytes.data(), bytes.size());
}

// The file's extension in lower case with its dot (".glb" for "a/B.GLB"), or "" when it has none.
std::string lower_extension(const std::string& path);

}  // namespace acuity::io

namespace acuity {

// The status-returning form of io::read_file, kept for one release for code written against it
// (integrations/osg/examples/hello_osg.cpp): false with *error = what() of the io::Error.
// New code calls io::read_file.
inline bool read_file(const std::string& path, Blob* out, std::string* error) {
  try {
    *out = io::read_file(path);
    return true;
  } catch (const io::Error& e) {
    *error = e.what();
    return false;
  }
}

}  // namespace acuity
