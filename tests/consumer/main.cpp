#include <acuity/models.hpp>
#include <acuity/version.hpp>

#include <cmath>
#include <cstdio>

int main() {
  const double fc = acuity::geisler_perry_cutoff(0.0);
  std::printf("acuity %s: foveal cutoff %.4f cpd\n", ACUITY_VERSION_STRING, fc);
  return std::abs(fc - 39.2347) < 1e-3 ? 0 : 1;
}
