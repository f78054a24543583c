#include "acuity/lodgen/mesh.hpp"

#include "acuity/file.hpp"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#if defined(__unix__) || defined(__APPLE__)
#define ACUITY_HAVE_FORK 1
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>
#endif

namespace acuity::lodgen {
namespace {
using OmMesh = OpenMesh::TriMesh_ArrayKernelT<>;

// The element counts an OFF or PLY header declares (0 when there is none), checked against what
// the file's size can hold, so a lying header cannot make the reader reserve absurd memory.
std::size_t declared_faces(const std::string& path, std::uintmax_t size) {
  std::ifstream in(path, std::ios::binary);
  const std::string ext = io::lower_extension(path);
  std::size_t faces = 0;
  auto check = [&](const char* what, unsigned long long count, unsigned long long min_bytes) {
    if (count > size / min_bytes)
      throw InputError(path + ": header declares " + std::to_string(count) + " " + what + ", more than its " +
                       std::to_string(size) + " bytes can hold");
  };
  if (ext == ".off") {
    std::string word;
    in >> word;  // OFF, COFF, NOFF, "OFF BINARY", ...
    if (word.find("OFF") == std::string::npos) return 0;
    const bool binary = in.peek() == ' ' && (in >> word, word == "BINARY");
    long long nv = -1, nf = -1, ne = -1;
    in >> nv >> nf >> ne;
    if (!in || nv < 0 || nf < 0) throw InputError(path + ": malformed OFF header");
    check("vertices", static_cast<unsigned long long>(nv), binary ? 12 : 6);
    check("faces", static_cast<unsigned long long>(nf), binary ? 16 : 7);
    faces = static_cast<std::size_t>(nf);
  } else if (ext == ".ply") {
    // OpenMesh's PLY reader loops forever on some malformed headers (no end_header, junk after
    // the format or end_header line, a non-numeric count): accept only well-formed ones.
    std::string line;
    std::getline(in, line);
    if (line != "ply" && line != "ply\r") throw InputError(path + ": not a PLY file (no 'ply' line)");
    bool format = false, ended = false, vertices = false;
    std::string element;
    int properties = 0;
    long long count = 0;
    auto flush = [&] {
      if (element.empty()) return;
      check(element.c_str(), static_cast<unsigned long long>(count),
            static_cast<unsigned long long>(std::max(1, properties)));
      if (element == "face") faces = static_cast<std::size_t>(count);
    };
    auto malformed = [&](const std::string& l) {
      throw InputError(path + ": malformed PLY header line '" + l + "'");
    };
    static const char* const kTypes[] = {"char",  "uchar",  "short",   "ushort", "int",   "uint",
                                         "float", "double", "int8",    "uint8",  "int16", "uint16",
                                         "int32", "uint32", "float32", "float64"};
    auto is_type = [&](const std::string& t) {
      return std::find(std::begin(kTypes), std::end(kTypes), t) != std::end(kTypes);
    };
    while (std::getline(in, line)) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (line == "end_header") {
        ended = true;
        break;
      }
      std::istringstream words(line);
      std::string key, a, b, c, extra;
      words >> key;
      if (key == "comment" || key == "obj_info") continue;
      if (key == "format") {
        if (!(words >> a >> b) || (words >> extra) || b != "1.0" ||
            (a != "ascii" && a != "binary_little_endian" && a != "binary_big_endian"))
          malformed(line);
        format = true;
      } else if (key == "element") {
        flush();
        long long n = -1;
        if (!(words >> a >> n) || n < 0 || (words >> extra)) malformed(line);
        element = a;
        count = n;
        properties = 0;
        vertices |= a == "vertex";
      } else if (key == "property") {
        if (element.empty() || !(words >> a)) malformed(line);
        if (a == "list" ? !(words >> b >> c >> extra) || !is_type(b) || !is_type(c) || (words >> extra)
                        : !is_type(a) || !(words >> b) || (words >> extra))
          malformed(line);
        ++properties;
      } else {
        // A line with no keyword (Blender 2.4 wrote "Created by Blender3D ..." without "comment"):
        // a comment, as assimp reads it. OpenMesh skips such words one by one, so a keyword later
        // in the line would be taken as one: reject those.
        static const char* const kKeywords[] = {"ply",        "format",  "element", "property",
                                                "end_header", "comment", "obj_info"};
        for (std::istringstream all(line); all >> a;)
          if (std::find(std::begin(kKeywords), std::end(kKeywords), a) != std::end(kKeywords))
            malformed(line);
      }
    }
    if (!format || !ended || !vertices)
      throw InputError(path +
                       ": PLY header is incomplete (format, a vertex element and end_header are needed)");
    flush();
  }
  return faces;
}
}  // namespace

namespace {

// OpenMesh's read, in whichever process runs it. Throws InputError.
Mesh read_openmesh(const std::string& path, std::size_t declared) {
  OmMesh om;
  OpenMesh::IO::Options options;
  if (!OpenMesh::IO::read_mesh(om, path, options))
    throw InputError(path + ": not a readable OFF, OBJ, PLY or STL mesh");
  if (declared > 0 && om.n_faces() < declared)
    throw InputError(path + ": header declares " + std::to_string(declared) + " faces, read " +
                     std::to_string(om.n_faces()) + " (truncated, or a malformed number)");
  Mesh mesh;
  mesh.positions.reserve(om.n_vertices() * 3);
  for (const auto vh : om.vertices()) {
    const auto& p = om.point(vh);
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(p[k]))
        throw InputError(path + ": vertex " + std::to_string(vh.idx()) + " has a non-finite coordinate");
      mesh.positions.push_back(p[k]);
    }
  }
  mesh.indices.reserve(om.n_faces() * 3);
  for (const auto fh : om.faces())
    for (const auto vh : om.fv_range(fh)) mesh.indices.push_back(static_cast<std::uint32_t>(vh.idx()));
  if (mesh.indices.empty())
    throw InputError(
        path + ": no triangles could be read (faces with missing vertices or malformed lines are dropped)");
  return mesh;
}

// The file's size and the face count its header declares, after the header checks.
std::size_t checked_declared_faces(const std::string& path, std::uintmax_t* size) {
  *size = io::check_input(path);  // a regular file (a FIFO would block OpenMesh's open)
  return declared_faces(path, *size);
}

#ifdef ACUITY_HAVE_FORK
bool write_all(int fd, const void* data, std::size_t size) {
  const auto* p = static_cast<const char*>(data);
  while (size) {
    const ssize_t n = ::write(fd, p, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n;
    size -= std::size_t(n);
  }
  return true;
}
#endif

}  // namespace

Mesh load_mesh(const std::string& path) {
  std::uintmax_t size = 0;
  const std::size_t declared = checked_declared_faces(path, &size);
  return read_openmesh(path, declared);
}

#ifdef ACUITY_HAVE_FORK
namespace {

struct ReaderTimedOut : InputError {
  using InputError::InputError;
};

// One isolated read: the child reads and sends, the parent waits with a deadline. Message: u8 ok,
// then u64 float count + floats and u64 index count + indices, or u64 length + text.
Mesh read_isolated_once(const std::string& path, std::size_t declared, std::uintmax_t size) {
  int fds[2];
  if (::pipe(fds) != 0)
    throw std::runtime_error(path + ": cannot isolate the mesh reader (pipe: " + std::strerror(errno) + ")");
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int e = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    throw std::runtime_error(path + ": cannot isolate the mesh reader (fork: " + std::strerror(e) + ")");
  }
  if (pid == 0) {  // child: read, send, leave without running the parent's destructors
    ::close(fds[0]);
    std::uint8_t ok = 1;
    try {
      const Mesh m = read_openmesh(path, declared);
      const std::uint64_t nf = m.positions.size(), ni = m.indices.size();
      const bool sent = write_all(fds[1], &ok, 1) && write_all(fds[1], &nf, 8) &&
                        write_all(fds[1], m.positions.data(), nf * 4) && write_all(fds[1], &ni, 8) &&
                        write_all(fds[1], m.indices.data(), ni * 4);
      ::_exit(sent ? 0 : 2);
    } catch (const std::exception& e) {
      ok = 0;
      const std::string text = e.what();
      const std::uint64_t n = text.size();
      ::_exit(write_all(fds[1], &ok, 1) && write_all(fds[1], &n, 8) && write_all(fds[1], text.data(), n) ? 0
                                                                                                         : 2);
    }
  }
  ::close(fds[1]);
  // Generous for real files (a second per 4 MB on top of 3 s), short for a stuck reader.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(3000 + size / 4000);
  std::string bytes;
  char chunk[65536];
  bool timed_out = false;
  while (true) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now())
            .count();
    if (left <= 0) {
      timed_out = true;
      break;
    }
    pollfd pfd{fds[0], POLLIN, 0};
    const int r = ::poll(&pfd, 1, int(std::min<long long>(left, 1000)));
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) break;
    if (r == 0) continue;
    const ssize_t n = ::read(fds[0], chunk, sizeof chunk);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    bytes.append(chunk, std::size_t(n));
  }
  ::close(fds[0]);
  if (timed_out) ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
  if (timed_out) throw ReaderTimedOut(path + ": the reader did not finish in time (a malformed file)");
  if (WIFSIGNALED(status))
    throw InputError(path + ": the reader failed on this file (malformed; signal " +
                     std::to_string(WTERMSIG(status)) + ")");
  auto take = [&](std::size_t& at, void* out, std::size_t n) {
    if (bytes.size() - at < n)
      throw InputError(path + ": the reader failed on this file (incomplete result)");
    std::memcpy(out, bytes.data() + at, n);
    at += n;
  };
  std::size_t at = 0;
  std::uint8_t ok = 0;
  std::uint64_t n = 0;
  take(at, &ok, 1);
  take(at, &n, 8);
  if (!ok) {
    std::string text(n <= bytes.size() - at ? n : 0, '\0');
    take(at, text.data(), text.size());
    throw InputError(text);
  }
  Mesh mesh;
  if (n > (bytes.size() - at) / 4)
    throw InputError(path + ": the reader failed on this file (incomplete result)");
  mesh.positions.resize(n);
  take(at, mesh.positions.data(), n * 4);
  take(at, &n, 8);
  if (n > (bytes.size() - at) / 4)
    throw InputError(path + ": the reader failed on this file (incomplete result)");
  mesh.indices.resize(n);
  take(at, mesh.indices.data(), n * 4);
  return mesh;
}

}  // namespace
#endif

Mesh load_mesh_isolated(const std::string& path) {
#ifndef ACUITY_HAVE_FORK
  throw std::runtime_error(
      path + ": load_mesh_isolated needs fork(), which this system lacks; use load_mesh for trusted files");
#else
  std::uintmax_t size = 0;
  const std::size_t declared = checked_declared_faces(path, &size);
  // A child forked from a multi-threaded process (acuity bake's threads) can stall on a lock another
  // thread held at the fork (seen under AddressSanitizer's allocator): one timeout is retried once,
  // so only a reader stuck twice calls the file malformed.
  try {
    return read_isolated_once(path, declared, size);
  } catch (const ReaderTimedOut&) { return read_isolated_once(path, declared, size); }
#endif
}

double diameter(const Mesh& mesh) {
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    lo[i % 3] = std::min(lo[i % 3], double(mesh.positions[i]));
    hi[i % 3] = std::max(hi[i % 3], double(mesh.positions[i]));
  }
  double r2 = 0;
  for (std::size_t i = 0; i + 2 < mesh.positions.size(); i += 3) {
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
      const double d = mesh.positions[i + k] - 0.5 * (lo[k] + hi[k]);
      d2 += d * d;
    }
    r2 = std::max(r2, d2);
  }
  return 2 * std::sqrt(r2);
}

}  // namespace acuity::lodgen
