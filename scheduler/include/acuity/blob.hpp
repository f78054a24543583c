#pragma once
// acuity/blob.hpp — bytes in 8-byte-aligned memory, what open_profile() needs (acuity/profile.hpp).
#include <cstddef>
#include <cstdint>
#include <vector>

namespace acuity {

// A file read (acuity/file.hpp, offline), an encoded profile, or a caller's copy of one.
struct Blob {
  std::vector<std::uint64_t> storage;
  std::size_t size = 0;
  const void* data() const { return storage.data(); }
};

}  // namespace acuity
