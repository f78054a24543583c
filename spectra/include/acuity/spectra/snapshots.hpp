#pragma once
// acuity/spectra/snapshots.hpp — profiles from a user's own snapshots (docs/design.md section 7): the
// analysis is of what the display shows, so an engine's own shading can be profiled.
//
// Manifest (JSON):
//   {"pixels_per_diameter": 256,                       // the bounding sphere's diameter in pixels
//    "sphere": [cx, cy, cz, r],                        // object space (optional; default unit sphere)
//    "levels": [{"triangles": 100000, "geometric_error": 0.0}, ...],   // finest first
//    "views": [{"direction": [x, y, z], "up": [x, y, z],             // object to camera; image up
//               "images": ["v0_l0.png", "v0_l1.png", ...]}, ...]}    // one per level, relative paths
// Images: square PNG, pixels_per_diameter across (a power of two, 8 .. 8192), 8-bit sRGB or grey;
// converted to linear luminance. Image names stay inside the manifest's folder; files must be
// regular files; at most 32 levels (kMaxLevels).
#include <string>

#include "acuity/spectra/analyze.hpp"
#include "acuity/spectra/profile_writer.hpp"

namespace acuity::spectra {

// Linear luminance of a PNG file (a regular file, at most 8192 pixels across, checked from its
// header before decoding). Throws std::runtime_error naming the file.
Image load_png_luminance(const std::string& path);

// Reads the manifest and its images and measures them. Throws std::runtime_error naming the file
// and the entry at fault.
ProfileData profile_from_snapshots(const std::string& manifest, const AnalysisSettings& settings);

}  // namespace acuity::spectra
