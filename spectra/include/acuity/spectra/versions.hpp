#pragma once
#include <string>

namespace acuity::spectra {
// "FFTW fftw-3.3.10, oneTBB 2021.8": the run-time versions of the libraries spectra links.
std::string library_versions();
}  // namespace acuity::spectra
