#pragma once
// acuity/lodgen/output.hpp — the checks every offline command makes on an output path before it
// starts work (the write itself is acuity::write_file_atomically, acuity/file.hpp).
#include <string>
#include <vector>

namespace acuity::lodgen {

// Throws InputError unless `output` may be written: an existing output must be a regular file
// (never a device, FIFO, directory or symbolic link) and not the same file (device and inode) as
// any of `inputs`, nor the same path; its folder must exist and be writable; when `extensions` is
// not empty, its extension (lower case, with the dot) must be one of them.
void check_output(const std::string& output, const std::vector<std::string>& inputs,
                  const std::vector<std::string>& extensions = {});

// Throws InputError unless files can be written into `folder`: an existing one must be a writable
// directory; else its nearest existing ancestor must be (the folder is created later).
void check_output_folder(const std::string& folder);

}  // namespace acuity::lodgen
