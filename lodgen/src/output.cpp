#include "acuity/lodgen/output.hpp"

#include "acuity/lodgen/mesh.hpp"
#include "path.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>

namespace acuity::lodgen {

void check_output(const std::string& output, const std::vector<std::string>& inputs,
                  const std::vector<std::string>& extensions) {
  namespace fs = std::filesystem;
  if (output.empty()) throw InputError("the output path is empty");
  if (!extensions.empty() &&
      std::find(extensions.begin(), extensions.end(), detail::lower_extension(output)) == extensions.end()) {
    std::string list;
    for (const std::string& e : extensions) list += (list.empty() ? "" : ", ") + e;
    throw InputError(output + ": the output must end in " + list);
  }
  struct stat out {};
  if (::lstat(output.c_str(), &out) == 0) {
    if (!S_ISREG(out.st_mode))
      throw InputError(output +
                       ": exists and is not a regular file (a device, FIFO, directory or symbolic link); "
                       "refusing to replace it");
    for (const std::string& in : inputs) {
      struct stat st {};
      if (::stat(in.c_str(), &st) == 0 && st.st_dev == out.st_dev && st.st_ino == out.st_ino)
        throw InputError(output + ": is the input " + in + "; refusing to overwrite an input");
    }
  }
  for (const std::string& in : inputs)
    if (fs::path(in).lexically_normal() == fs::path(output).lexically_normal())
      throw InputError(output + ": is the input " + in + "; refusing to overwrite an input");
  const fs::path parent = fs::path(output).has_parent_path() ? fs::path(output).parent_path() : fs::path(".");
  struct stat dir {};
  if (::stat(parent.c_str(), &dir) != 0 || !S_ISDIR(dir.st_mode))
    throw InputError(output + ": its folder " + parent.string() + " does not exist");
  if (::access(parent.c_str(), W_OK | X_OK) != 0)
    throw InputError(output + ": its folder " + parent.string() + " is not writable");
}

void check_output_folder(const std::string& folder) {
  namespace fs = std::filesystem;
  if (folder.empty()) return;
  fs::path at = fs::absolute(fs::path(folder)).lexically_normal();
  struct stat st {};
  while (::stat(at.c_str(), &st) != 0 && at.has_parent_path() && at.parent_path() != at)
    at = at.parent_path();
  if (!S_ISDIR(st.st_mode)) throw InputError(folder + ": " + at.string() + " exists and is not a directory");
  if (::access(at.c_str(), W_OK | X_OK) != 0)
    throw InputError(folder + ": " + at.string() + " is not writable");
}

}  // namespace acuity::lodgen
