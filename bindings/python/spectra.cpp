// acuity.spectra: building and writing profiles from numpy arrays.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <cmath>
#include <cstring>

#include "acuity/spectra/analyze.hpp"
#include "acuity/spectra/profile_builder.hpp"
#include "acuity/spectra/profile_writer.hpp"
#include "acuity/spectra/render.hpp"
#include "bindings.hpp"

namespace py = pybind11;
using namespace pybind11::literals;

namespace acuity::python {
using namespace acuity::spectra;
namespace {

using F32 = py::array_t<float, py::array::c_style | py::array::forcecast>;
using U32 = py::array_t<std::uint32_t, py::array::c_style | py::array::forcecast>;

ProfileData profile_data(F32 sphere, U32 triangles, F32 geometric_error, F32 view_directions,
                         F32 orientations, F32 bands, F32 lost, F32 features, std::uint32_t snapshot_pixels,
                         const py::object& detail_area = py::none(),
                         const py::object& detail_offset = py::none(),
                         const py::object& detail_turn = py::none()) {
  spectra::ProfileData d;
  if (sphere.size() != 4) throw py::value_error("sphere: expected 4 values (centre xyz, radius)");
  std::memcpy(d.sphere, sphere.data(), 4 * sizeof(float));
  d.snapshot_pixels = snapshot_pixels;
  if (triangles.size() != geometric_error.size())
    throw py::value_error("triangles and geometric_error differ in length");
  for (py::ssize_t k = 0; k < triangles.size(); ++k)
    d.levels.push_back({triangles.data()[k], geometric_error.data()[k]});
  if (view_directions.ndim() != 2 || view_directions.shape(1) != 3)
    throw py::value_error("view_directions: expected shape (V, 3)");
  for (py::ssize_t v = 0; v < view_directions.shape(0); ++v) {
    const float* w = view_directions.data() + 3 * v;
    d.views.push_back(spectra::make_view(w[0], w[1], w[2]));
  }
  d.orientations.assign(orientations.data(), orientations.data() + orientations.size());
  d.bands.assign(bands.data(), bands.data() + bands.size());
  d.lost.assign(lost.data(), lost.data() + lost.size());
  d.features.assign(features.data(), features.data() + features.size());
  if (detail_area.is_none() != detail_offset.is_none())
    throw py::value_error("detail_area and detail_offset go together");
  if (!detail_area.is_none()) {
    const F32 a = detail_area.cast<F32>(), o = detail_offset.cast<F32>();
    F32 u(lost.size());
    if (detail_turn.is_none())
      std::fill(u.mutable_data(), u.mutable_data() + u.size(), 0.0f);
    else
      u = detail_turn.cast<F32>();
    if (a.size() != lost.size() || o.size() != lost.size() || u.size() != lost.size())
      throw py::value_error("detail_area, detail_offset, detail_turn: one value per lost value expected");
    for (py::ssize_t i = 0; i < a.size(); ++i)
      d.detail.push_back(encode_detail(a.data()[i], o.data()[i], u.data()[i]));
  }
  return d;
}

MeshView mesh_view(const F32& positions, const U32& indices, const py::object& normals_obj,
                   std::vector<float>& normals) {
  if (positions.ndim() != 2 || positions.shape(1) != 3)
    throw py::value_error("positions: expected shape (N, 3)");
  if (indices.size() % 3) throw py::value_error("indices: a multiple of 3 expected");
  for (py::ssize_t i = 0; i < indices.size(); ++i)
    if (indices.data()[i] >= std::uint32_t(positions.shape(0)))
      throw py::value_error("indices: out of range");
  MeshView v;
  v.positions = positions.data();
  v.vertex_count = std::size_t(positions.shape(0));
  v.indices = indices.data();
  v.index_count = std::size_t(indices.size());
  if (!normals_obj.is_none()) {
    const F32 n = normals_obj.cast<F32>();
    if (n.size() != positions.size()) throw py::value_error("normals: same shape as positions expected");
    normals.assign(n.data(), n.data() + n.size());
    v.normals = normals.data();
  }
  return v;
}

Image to_image(const F32& a) {
  if (a.ndim() != 2 || a.shape(0) != a.shape(1)) throw py::value_error("image: a square 2-D array expected");
  Image im;
  im.width = im.height = std::uint32_t(a.shape(0));
  im.pixels.assign(a.data(), a.data() + a.size());
  return im;
}

AnalysisSettings analysis(std::uint32_t orientations, std::uint32_t bands, float bands_per_octave,
                          float lowest_band = AnalysisSettings{}.lowest_band) {
  AnalysisSettings s;
  s.lowest_band = lowest_band;
  s.orientations = orientations;
  s.bands = bands;
  s.bands_per_octave = bands_per_octave;
  return s;
}

}  // namespace

void bind_spectra(py::module_ m) {
  m.def(
      "render",
      [](F32 positions, U32 indices, std::array<float, 3> direction, py::object normals, std::uint32_t pixels,
         std::uint32_t supersample, float background) {
        std::vector<float> nbuf;
        const MeshView mesh = mesh_view(positions, indices, normals, nbuf);
        RenderSettings rs;
        rs.pixels = pixels;
        rs.supersample = supersample;
        rs.background = background;
        bounding_sphere(mesh, rs.sphere);
        const Image im =
            render_snapshot(mesh, Material{}, make_view(direction[0], direction[1], direction[2]), rs);
        py::array_t<float> out({py::ssize_t(im.height), py::ssize_t(im.width)});
        std::memcpy(out.mutable_data(), im.pixels.data(), im.pixels.size() * sizeof(float));
        return out;
      },
      "positions"_a, "indices"_a, "direction"_a = std::array<float, 3>{0, 0, 1}, "normals"_a = py::none(),
      "pixels"_a = 256, "supersample"_a = 4, "background"_a = 0.5f,
      "Snapshot (linear luminance, row 0 at the top) of a mesh framed by its bounding sphere, seen from\n"
      "`direction` (object to camera), headlight Lambert + ambient, grey albedo 0.8.");

  m.def(
      "lost_contrast",
      [](F32 level, F32 reference, std::uint32_t orientations, std::uint32_t bands, float bands_per_octave,
         bool with_detail, float lowest_band) -> py::tuple {
        const Image a = to_image(level), b = to_image(reference);
        if (!(lowest_band > 0) || !std::isfinite(lowest_band))
          throw py::value_error("lowest_band: a positive number of cycles per image expected");
        const LostContrast analyzer(a.width, analysis(orientations, bands, bands_per_octave, lowest_band));
        std::vector<float> area, offset, turn;
        const std::vector<float> v =
            analyzer.measure(a, b, with_detail ? &area : nullptr, with_detail ? &offset : nullptr,
                             with_detail ? &turn : nullptr);
        auto array = [&](const std::vector<float>& x) {
          py::array_t<float> out({py::ssize_t(orientations), py::ssize_t(analyzer.band_count())});
          std::memcpy(out.mutable_data(), x.data(), x.size() * sizeof(float));
          return out;
        };
        if (with_detail)
          return py::make_tuple(array(v), analyzer.bands(), array(area), array(offset), array(turn));
        return py::make_tuple(array(v), analyzer.bands());
      },
      "level"_a, "reference"_a, "orientations"_a = 8, "bands"_a = 0, "bands_per_octave"_a = 1.0f,
      "with_detail"_a = false, "lowest_band"_a = AnalysisSettings{}.lowest_band,
      "Peli band-limited contrast lost by `level` against `reference` (square, power-of-two images):\n"
      "(array [orientations, bands] of maxima over the image, band centres [cycles per image]); "
      "with_detail:\n"
      "also each band's extent of the loss (sum of c^2 / max c^2 as a fraction of the image) and its\n"
      "frequency offset from the band's centre [octaves] and its angle from the orientation's centre\n"
      "[orientation spacings], each [orientations, bands]. lowest_band: the\n"
      "lowest band's centre [cycles per image] (2).");

  m.def(
      "lost_contrast_maps",
      [](F32 level, F32 reference, std::uint32_t orientations, float lowest_band) -> py::tuple {
        const Image a = to_image(level), b = to_image(reference);
        if (!(lowest_band > 0) || !std::isfinite(lowest_band))
          throw py::value_error("lowest_band: a positive number of cycles per image expected");
        const LostContrast analyzer(a.width, analysis(orientations, 0, 1.0f, lowest_band));
        const std::vector<std::vector<float>> maps = analyzer.contrast_maps(a, *analyzer.prepare(b));
        py::list out;
        const std::uint32_t B = analyzer.band_count();
        for (std::uint32_t band = 0; band < B; ++band) {
          const py::ssize_t m = analyzer.map_size(band);
          py::array_t<float> x({py::ssize_t(orientations), m, m});
          for (std::uint32_t t = 0; t < orientations; ++t)
            std::memcpy(x.mutable_data() + std::size_t(t) * m * m, maps[std::size_t(t) * B + band].data(),
                        std::size_t(m) * m * sizeof(float));
          out.append(x);
        }
        return py::make_tuple(out, analyzer.bands());
      },
      "level"_a, "reference"_a, "orientations"_a = 8, "lowest_band"_a = AnalysisSettings{}.lowest_band,
      "Where lost_contrast's loss lies (octave bands up to pixels / 4): (a list over bands of arrays\n"
      "[orientations, m, m] of the lost contrast over the image, sample (r, c) at the centre of pixel\n"
      "(r s, c s) with s = pixels / m; band centres [cycles per image]). Each array's maximum is\n"
      "lost_contrast's value. For judges whose threshold varies over the image.");

  m.def(
      "reddy_features",
      [](F32 image, std::uint32_t orientations) {
        return reddy_features(to_image(image), analysis(orientations, 0, 1.0f));
      },
      "image"_a, "orientations"_a = 8,
      "Reddy's smallest-feature fundamental frequency per orientation [cycles per image]; 0 where none.");

  m.def(
      "build_profile",
      [](py::list levels, std::uint32_t views, std::uint32_t pixels, std::uint32_t orientations,
         std::uint32_t bands, float tolerance, bool bound_cells, unsigned jobs) {
        std::vector<F32> keep_p;
        std::vector<U32> keep_i;
        std::vector<LevelInput> inputs;
        for (py::handle h : levels) {
          const py::tuple t = h.cast<py::tuple>();
          keep_p.push_back(t[0].cast<F32>());
          keep_i.push_back(t[1].cast<U32>());
        }
        std::vector<std::vector<float>> no_normals(keep_p.size());
        for (std::size_t k = 0; k < keep_p.size(); ++k) {
          LevelInput l;
          l.mesh = mesh_view(keep_p[k], keep_i[k], py::none(), no_normals[k]);
          inputs.push_back(l);
        }
        ProfileSettings s;
        s.views = views;
        s.render.pixels = pixels;
        s.analysis = analysis(orientations, bands, 1.0f);
        s.view_tolerance = tolerance;
        s.bound_cells = bound_cells;
        s.jobs = jobs;
        ProfileReport report;
        ProfileData data;
        {
          py::gil_scoped_release release;
          data = build_profile(inputs, Material{}, s, {}, &report);
        }
        const Blob b = encode_profile(data);
        return py::make_tuple(
            py::bytes(static_cast<const char*>(b.data()), b.size),
            py::dict("views_measured"_a = report.views_measured, "views_kept"_a = report.views_kept,
                     "prediction_error"_a = report.prediction_error, "views_sampled"_a = report.views_sampled,
                     "bound_pessimism"_a = report.bound_pessimism, "seconds"_a = report.seconds));
      },
      "levels"_a, "views"_a = 0, "pixels"_a = 256, "orientations"_a = 8, "bands"_a = 0,
      "view_tolerance"_a = 0.25f, "bound_cells"_a = true, "jobs"_a = 0,
      "Profile a chain: levels = [(positions (N, 3), indices), ...], finest first. Returns (bytes, report).\n"
      "bound_cells: each view stores the largest loss over its cell of 162 sample directions "
      "(docs/spectra.md).");

  py::register_exception<spectra::InvalidProfile>(m, "InvalidProfile", PyExc_ValueError);
  const char* doc =
      "Build a profile blob. sphere (4,); triangles, geometric_error (K,); view_directions (V, 3) from\n"
      "the object towards the camera (canonical up); orientations (T,) [deg]; bands (B,) [cycles per\n"
      "diameter]; lost (K-1, V, T, B); features (K, V, T) [cpod].";
  m.def(
      "encode_profile",
      [](F32 sphere, U32 triangles, F32 geometric_error, F32 views, F32 orientations, F32 bands, F32 lost,
         F32 features, std::uint32_t snapshot_pixels, py::object detail_area, py::object detail_offset,
         py::object detail_turn) {
        const Blob b = spectra::encode_profile(
            profile_data(sphere, triangles, geometric_error, views, orientations, bands, lost, features,
                         snapshot_pixels, detail_area, detail_offset, detail_turn));
        return py::bytes(static_cast<const char*>(b.data()), b.size);
      },
      "sphere"_a, "triangles"_a, "geometric_error"_a, "view_directions"_a, "orientations"_a, "bands"_a,
      "lost"_a, "features"_a, "snapshot_pixels"_a = 256, "detail_area"_a = py::none(),
      "detail_offset"_a = py::none(), "detail_turn"_a = py::none(),
      (std::string(doc) + "\ndetail_area, detail_offset, detail_turn (optional, shaped as lost; detail_turn "
                          "may be left out: 0):\n"
                          "the Detail section, each loss's extent [fraction of the diameter squared], "
                          "frequency offset from its\n"
                          "band's centre [octaves] and angle from its orientation [spacings] "
                          "(lost_contrast(..., with_detail=True)).")
          .c_str());
  m.def(
      "write_profile",
      [](const std::string& path, F32 sphere, U32 triangles, F32 geometric_error, F32 views, F32 orientations,
         F32 bands, F32 lost, F32 features, std::uint32_t snapshot_pixels) {
        spectra::write_profile(path, profile_data(sphere, triangles, geometric_error, views, orientations,
                                                  bands, lost, features, snapshot_pixels));
      },
      "path"_a, "sphere"_a, "triangles"_a, "geometric_error"_a, "view_directions"_a, "orientations"_a,
      "bands"_a, "lost"_a, "features"_a, "snapshot_pixels"_a = 256,
      "encode_profile() written atomically to path.");
}

}  // namespace acuity::python
