#pragma once
// FNV-1a 64 (scheduler/src only): the profile's checksum and a cluster hierarchy's hash.
#include <cstddef>
#include <cstdint>

namespace acuity::internal {

inline constexpr std::uint64_t kFnv1aBasis = 0xcbf29ce484222325ull;

// `hash` continued over `size` bytes at `data`. Linear; no allocation.
inline std::uint64_t fnv1a(std::uint64_t hash, const void* data, std::size_t size) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) hash = (hash ^ bytes[i]) * 0x100000001b3ull;
  return hash;
}

}  // namespace acuity::internal
