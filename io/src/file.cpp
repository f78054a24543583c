#include "acuity/file.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>

namespace acuity {
namespace {

// Why `path` is not something we read or replace, or "" when it is a regular file.
std::string not_regular(const struct stat& st) {
  if (S_ISREG(st.st_mode)) return {};
  if (S_ISDIR(st.st_mode)) return "is a directory, not a regular file";
  if (S_ISFIFO(st.st_mode)) return "is a FIFO, not a regular file";
  if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode)) return "is a device, not a regular file";
  if (S_ISLNK(st.st_mode)) return "is a symbolic link, not a regular file";
  return "is not a regular file";
}

// Blocks the signals that end a process from a terminal or a job manager while a temporary file
// exists; they are delivered when the scope ends, after the temporary was renamed or removed.
struct SignalsHeld {
  sigset_t old{};
  SignalsHeld() {
    sigset_t set;
    sigemptyset(&set);
    for (int s : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) sigaddset(&set, s);
    pthread_sigmask(SIG_BLOCK, &set, &old);
  }
  ~SignalsHeld() { pthread_sigmask(SIG_SETMASK, &old, nullptr); }
  SignalsHeld(const SignalsHeld&) = delete;
  SignalsHeld& operator=(const SignalsHeld&) = delete;
};

}  // namespace

bool read_file(const std::string& path, Blob* out, std::string* error) {
  // O_NONBLOCK: opening a FIFO without a writer must not wait; fstat then refuses it.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    *error = path + ": " + std::strerror(errno);
    return false;
  }
  struct stat st {};
  const std::string why = ::fstat(fd, &st) != 0 ? std::string(std::strerror(errno)) : not_regular(st);
  if (!why.empty()) {
    *error = path + ": " + why;
    ::close(fd);
    return false;
  }
  out->size = static_cast<std::size_t>(st.st_size);
  out->storage.assign((out->size + 7) / 8, 0);
  auto* bytes = reinterpret_cast<unsigned char*>(out->storage.data());
  std::size_t done = 0;
  bool ok = true;
  while (done < out->size) {
    const ssize_t n = ::read(fd, bytes + done, out->size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      ok = false;
      break;
    }
    done += static_cast<std::size_t>(n);
  }
  ::close(fd);
  if (!ok) *error = path + ": cannot read (it changed while reading)";
  return ok;
}

bool write_file_atomically(const std::string& path, const void* data, std::size_t size, std::string* error) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) == 0 && !not_regular(st).empty()) {
    *error = path + ": " + not_regular(st) + "; refusing to replace it";
    return false;
  }
  const SignalsHeld held;  // no temporary is left behind by SIGINT/SIGTERM/SIGHUP/SIGQUIT
  std::string tmp = path + ".tmp.XXXXXX";
  const int fd = ::mkstemp(tmp.data());
  if (fd < 0) {
    *error = path + ": cannot create a temporary beside it: " + std::strerror(errno);
    return false;
  }
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
  // Checked again just before the rename: the target may have been replaced meanwhile.
  if (written && ::lstat(path.c_str(), &st) == 0 && !not_regular(st).empty()) {
    *error = path + ": " + not_regular(st) + "; refusing to replace it";
    ::unlink(tmp.c_str());
    return false;
  }
  if (!written || ::rename(tmp.c_str(), path.c_str()) != 0) {
    *error = path + ": write failed: " + std::strerror(written ? errno : saved);
    ::unlink(tmp.c_str());
    return false;
  }
  return true;
}

}  // namespace acuity
