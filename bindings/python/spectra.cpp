// acuity.spectra: building and writing profiles from numpy arrays.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstring>

#include "acuity/spectra/profile_writer.hpp"
#include "bindings.hpp"

namespace py = pybind11;
using namespace pybind11::literals;

namespace acuity::python {
namespace {

using F32 = py::array_t<float, py::array::c_style | py::array::forcecast>;
using U32 = py::array_t<std::uint32_t, py::array::c_style | py::array::forcecast>;

spectra::ProfileData profile_data(F32 sphere, U32 triangles, F32 geometric_error, F32 view_directions,
                                  F32 orientations, F32 bands, F32 lost, F32 features, std::uint32_t snapshot_pixels) {
  spectra::ProfileData d;
  if (sphere.size() != 4) throw py::value_error("sphere: expected 4 values (centre xyz, radius)");
  std::memcpy(d.sphere, sphere.data(), 4 * sizeof(float));
  d.snapshot_pixels = snapshot_pixels;
  if (triangles.size() != geometric_error.size()) throw py::value_error("triangles and geometric_error differ in length");
  for (py::ssize_t k = 0; k < triangles.size(); ++k) d.levels.push_back({triangles.data()[k], geometric_error.data()[k]});
  if (view_directions.ndim() != 2 || view_directions.shape(1) != 3) throw py::value_error("view_directions: expected shape (V, 3)");
  for (py::ssize_t v = 0; v < view_directions.shape(0); ++v) {
    const float* w = view_directions.data() + 3 * v;
    d.views.push_back(spectra::make_view(w[0], w[1], w[2]));
  }
  d.orientations.assign(orientations.data(), orientations.data() + orientations.size());
  d.bands.assign(bands.data(), bands.data() + bands.size());
  d.lost.assign(lost.data(), lost.data() + lost.size());
  d.features.assign(features.data(), features.data() + features.size());
  return d;
}

}  // namespace

void bind_spectra(py::module_ m) {
  py::register_exception<spectra::InvalidProfile>(m, "InvalidProfile", PyExc_ValueError);
  const char* doc =
      "Build a profile blob. sphere (4,); triangles, geometric_error (K,); view_directions (V, 3) from\n"
      "the object towards the camera (canonical up); orientations (T,) [deg]; bands (B,) [cycles per\n"
      "diameter]; lost (K-1, V, T, B); features (K, V, T) [cpod].";
  m.def("encode_profile", [](F32 sphere, U32 triangles, F32 geometric_error, F32 views, F32 orientations, F32 bands,
                             F32 lost, F32 features, std::uint32_t snapshot_pixels) {
    const Blob b = spectra::encode_profile(profile_data(sphere, triangles, geometric_error, views, orientations, bands,
                                                        lost, features, snapshot_pixels));
    return py::bytes(static_cast<const char*>(b.data()), b.size);
  }, "sphere"_a, "triangles"_a, "geometric_error"_a, "view_directions"_a, "orientations"_a, "bands"_a, "lost"_a,
     "features"_a, "snapshot_pixels"_a = 256, doc);
  m.def("write_profile", [](const std::string& path, F32 sphere, U32 triangles, F32 geometric_error, F32 views,
                            F32 orientations, F32 bands, F32 lost, F32 features, std::uint32_t snapshot_pixels) {
    spectra::write_profile(path, profile_data(sphere, triangles, geometric_error, views, orientations, bands, lost,
                                              features, snapshot_pixels));
  }, "path"_a, "sphere"_a, "triangles"_a, "geometric_error"_a, "view_directions"_a, "orientations"_a, "bands"_a,
     "lost"_a, "features"_a, "snapshot_pixels"_a = 256, "encode_profile() written atomically to path.");
}

}  // namespace acuity::python
