#include "acuity/file.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace acuity::io {
namespace fs = std::filesystem;
namespace {

// Why `st` is not something we read or replace, or "" when it is a regular file.
std::string not_regular(const struct stat& st) {
  if (S_ISREG(st.st_mode)) return {};
  if (S_ISDIR(st.st_mode)) return "is a directory, not a regular file";
  if (S_ISFIFO(st.st_mode)) return "is a FIFO, not a regular file";
  if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode)) return "is a device, not a regular file";
  if (S_ISLNK(st.st_mode)) return "is a symbolic link, not a regular file";
  return "is not a regular file";
}

// Refuses to replace an existing `path` that is not a regular file (lstat: a link is not followed).
void refuse_non_regular_target(const std::string& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) == 0 && !not_regular(st).empty())
    throw Error(path, not_regular(st) + "; refusing to replace it");
}

// A descriptor closed when the scope ends.
struct Fd {
  int fd = -1;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

// Opens `path` for reading after every check of ReadLimits: non-blocking (a FIFO without a writer
// must not wait), then fstat on the descriptor, so the checks and the read see the same file.
// Returns the file's size.
std::uint64_t open_checked(const std::string& path, const ReadLimits& limits, Fd& file) {
  const std::string real = limits.root.empty() ? path : confine(path, limits.root);
  // Inside a root the path is resolved: a symbolic link in its last component now is one that
  // appeared since, and is not followed.
  const int flags = O_RDONLY | O_NONBLOCK | O_CLOEXEC | (limits.root.empty() ? 0 : O_NOFOLLOW);
  file.fd = ::open(real.c_str(), flags);
  if (file.fd < 0) throw Error(path, std::strerror(errno));
  struct stat st {};
  if (::fstat(file.fd, &st) != 0) throw Error(path, std::strerror(errno));
  if (const std::string why = not_regular(st); !why.empty()) throw Error(path, why);
  const auto size = static_cast<std::uint64_t>(st.st_size);
  if (size > limits.max_bytes)
    throw Error(path, std::to_string(size) + " bytes, more than " + limits.max_bytes_name + " (" +
                          std::to_string(limits.max_bytes) + ")");
  return size;
}

void read_all(const std::string& path, int fd, unsigned char* bytes, std::size_t size) {
  std::size_t done = 0;
  while (done < size) {
    const ssize_t n = ::read(fd, bytes + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw Error(path, "cannot read (it changed while reading)");
    done += static_cast<std::size_t>(n);
  }
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

Error::Error(const std::string& path, const std::string& reason)
    : std::runtime_error(path.empty() ? reason : path + ": " + reason), path_(path), reason_(reason) {}

std::uint64_t check_input(const std::string& path, const ReadLimits& limits) {
  Fd file;
  return open_checked(path, limits, file);
}

Blob read_file(const std::string& path, const ReadLimits& limits) {
  Fd file;
  Blob out;
  out.size = static_cast<std::size_t>(open_checked(path, limits, file));
  out.storage.assign((out.size + 7) / 8, 0);
  read_all(path, file.fd, reinterpret_cast<unsigned char*>(out.storage.data()), out.size);
  return out;
}

void read_file(const std::string& path, const ReadLimits& limits, std::vector<unsigned char>* out) {
  Fd file;
  out->resize(static_cast<std::size_t>(open_checked(path, limits, file)));
  read_all(path, file.fd, out->data(), out->size());
}

std::string confine(const std::string& path, const std::string& root) {
  std::error_code ec;
  const fs::path folder = fs::weakly_canonical(fs::absolute(fs::path(root), ec), ec);
  if (ec) throw Error(root, "cannot resolve the folder: " + ec.message());
  const fs::path real = fs::weakly_canonical(fs::absolute(fs::path(path), ec), ec);
  if (ec) throw Error(path, "cannot resolve the path: " + ec.message());
  const fs::path rel = real.lexically_relative(folder);
  if (rel.empty() || *rel.begin() == ".." || rel == ".")
    throw Error(path, "leads outside the folder " + folder.string() + " (a symbolic link?)");
  return real.string();
}

void check_output(const std::string& output, const std::vector<std::string>& inputs,
                  const std::vector<std::string>& extensions) {
  if (output.empty()) throw Error("", "the output path is empty");
  if (!extensions.empty() &&
      std::find(extensions.begin(), extensions.end(), lower_extension(output)) == extensions.end()) {
    std::string list;
    for (const std::string& e : extensions) list += (list.empty() ? "" : ", ") + e;
    throw Error(output, "the output must end in " + list);
  }
  struct stat out {};
  if (::lstat(output.c_str(), &out) == 0) {
    if (!S_ISREG(out.st_mode)) throw Error(output, not_regular(out) + "; refusing to replace it");
    for (const std::string& in : inputs) {
      struct stat st {};
      if (::stat(in.c_str(), &st) == 0 && st.st_dev == out.st_dev && st.st_ino == out.st_ino)
        throw Error(output, "is the input " + in + "; refusing to overwrite an input");
    }
  }
  for (const std::string& in : inputs)
    if (fs::path(in).lexically_normal() == fs::path(output).lexically_normal())
      throw Error(output, "is the input " + in + "; refusing to overwrite an input");
  const fs::path parent = fs::path(output).has_parent_path() ? fs::path(output).parent_path() : fs::path(".");
  struct stat dir {};
  if (::stat(parent.c_str(), &dir) != 0 || !S_ISDIR(dir.st_mode))
    throw Error(output, "its folder " + parent.string() + " does not exist");
  if (::access(parent.c_str(), W_OK | X_OK) != 0)
    throw Error(output, "its folder " + parent.string() + " is not writable");
}

void check_output_folder(const std::string& folder) {
  if (folder.empty()) return;
  fs::path at = fs::absolute(fs::path(folder)).lexically_normal();
  struct stat st {};
  while (::stat(at.c_str(), &st) != 0 && at.has_parent_path() && at.parent_path() != at)
    at = at.parent_path();
  if (!S_ISDIR(st.st_mode)) throw Error(folder, at.string() + " exists and is not a directory");
  if (::access(at.c_str(), W_OK | X_OK) != 0) throw Error(folder, at.string() + " is not writable");
}

void write_file_atomically(const std::string& path, const void* data, std::size_t size) {
  refuse_non_regular_target(path);
  const SignalsHeld held;  // no temporary is left behind by SIGINT/SIGTERM/SIGHUP/SIGQUIT
  std::string tmp = path + ".tmp.XXXXXX";
  const int fd = ::mkstemp(tmp.data());
  if (fd < 0) throw Error(path, std::string("cannot create a temporary beside it: ") + std::strerror(errno));
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
  try {
    refuse_non_regular_target(path);  // again just before the rename: it may have been replaced meanwhile
  } catch (const Error&) {
    ::unlink(tmp.c_str());
    throw;
  }
  if (!written || ::rename(tmp.c_str(), path.c_str()) != 0) {
    const int e = written ? errno : saved;
    ::unlink(tmp.c_str());
    throw Error(path, std::string("write failed: ") + std::strerror(e));
  }
}

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace acuity::io
