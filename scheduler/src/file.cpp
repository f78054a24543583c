#include "acuity/file.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace acuity {

bool read_file(const std::string& path, Blob* out, std::string* error) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) { *error = path + ": " + std::strerror(errno); return false; }
  bool ok = std::fseek(f, 0, SEEK_END) == 0;
  const long size = ok ? std::ftell(f) : -1;
  ok = ok && size >= 0 && std::fseek(f, 0, SEEK_SET) == 0;
  if (ok) {
    out->size = static_cast<std::size_t>(size);
    out->storage.assign((out->size + 7) / 8, 0);
    ok = std::fread(out->storage.data(), 1, out->size, f) == out->size;
  }
  std::fclose(f);
  if (!ok) *error = path + ": cannot read (not a regular file, or it changed while reading)";
  return ok;
}

bool write_file_atomically(const std::string& path, const void* data, std::size_t size, std::string* error) {
  std::string tmp = path + ".tmp.XXXXXX";
  const int fd = ::mkstemp(tmp.data());
  if (fd < 0) { *error = path + ": cannot create a temporary beside it: " + std::strerror(errno); return false; }
  ::fchmod(fd, 0644);  // mkstemp makes it private; the result is an ordinary file others may read
  const auto* bytes = static_cast<const unsigned char*>(data);
  std::size_t done = 0;
  while (done < size) {
    const ssize_t n = ::write(fd, bytes + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    done += static_cast<std::size_t>(n);
  }
  const bool written = done == size && ::fsync(fd) == 0;
  const int saved = errno;
  ::close(fd);
  if (!written || ::rename(tmp.c_str(), path.c_str()) != 0) {
    *error = path + ": write failed: " + std::strerror(written ? errno : saved);
    ::unlink(tmp.c_str());
    return false;
  }
  return true;
}

}  // namespace acuity
