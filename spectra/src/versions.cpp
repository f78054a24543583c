#include "acuity/spectra/versions.hpp"

#include <fftw3.h>
#include <oneapi/tbb/version.h>

namespace acuity::spectra {

std::string library_versions() {
  return std::string("FFTW ") + fftw_version + ", oneTBB " + TBB_runtime_version();
}

}  // namespace acuity::spectra
