// Writes the golden version-1 profile from tests/profile_v1_input.hpp:
//   cmake --build build --target make_profile_v1 && ./build/tests/make_profile_v1 tests/data/profile_v1.acuity
// Run once, with the writer of commit dde7054 (before the header structs became public, so the
// file also shows that the struct-based writer is byte-identical); the committed file is never
// regenerated. A later format version gets a file of its own.
#include <cstdio>
#include <exception>

#include "profile_v1_input.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUTPUT.acuity\n", argv[0]);
    return 2;
  }
  try {
    acuity::spectra::write_profile(argv[1], acuity::testing::profile_v1_input());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_profile_v1: %s\n", e.what());
    return 1;
  }
  return 0;
}
