#pragma once
// The measurements' worker threads: `jobs`, or one per hardware thread when 0 (the settings' `jobs`
// fields), held for the life of the returned object (TBB's global control; no copy is made).
#include <oneapi/tbb/global_control.h>

#include <algorithm>
#include <thread>

namespace acuity::spectra {

inline oneapi::tbb::global_control thread_limit(unsigned jobs) {
  return oneapi::tbb::global_control(oneapi::tbb::global_control::max_allowed_parallelism,
                                     jobs ? jobs : std::max(1u, std::thread::hardware_concurrency()));
}

}  // namespace acuity::spectra
