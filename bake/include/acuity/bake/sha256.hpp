#pragma once
// acuity/bake/sha256.hpp — SHA-256 (FIPS 180-4) for the bake cache's content addresses. A small
// portable implementation (no OpenSSL dependency for one hash); tested against the FIPS 180-2
// examples and Python's hashlib.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace acuity::bake {

class Sha256 {
 public:
  Sha256();
  void update(const void* data, std::size_t size);
  void update(const std::string& s) { update(s.data(), s.size()); }
  // The digest as 64 lower-case hex digits; the object must not be updated afterwards.
  std::string hex();

 private:
  void block(const std::uint8_t* p);
  std::array<std::uint32_t, 8> h_;
  std::array<std::uint8_t, 64> buffer_{};
  std::size_t buffered_ = 0;
  std::uint64_t bytes_ = 0;
};

// The SHA-256 of `size` bytes, as 64 hex digits.
std::string sha256_hex(const void* data, std::size_t size);

}  // namespace acuity::bake
