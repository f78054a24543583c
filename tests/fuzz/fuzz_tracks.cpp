// libFuzzer: head paths and gaze traces (CSV and JSON) are read into tracks or rejected with a
// std::runtime_error; never a crash, a hang or another exception. The first byte picks the format.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "acuity/sim/tracks.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const bool json = data[0] & 1;
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  try {
    const acuity::sim::Table t = acuity::sim::parse_table(text, "fuzz", json);
    for (const auto& row : t.rows)
      for (double v : row)
        if (!std::isfinite(v)) std::abort();  // the reader promises finite numbers
    try {
      for (const auto& g : acuity::sim::gaze_trace_from(t, 60, 16))
        if (!(std::abs(glm::length(g.direction) - 1.0) < 1e-6)) std::abort();  // unit directions only
    } catch (const std::runtime_error&) {}
    for (const auto& h : acuity::sim::head_path_from(t, 60, 16))
      if (!(std::abs(glm::length(h.orientation) - 1.0) < 1e-6)) std::abort();
  } catch (const std::runtime_error&) {}
  return 0;
}
