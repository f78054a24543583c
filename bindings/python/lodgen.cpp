// acuity.lodgen: the chain of levels from Python, as the command builds it.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>

#include "acuity/bake/chains.hpp"
#include "acuity/lodgen/output.hpp"
#include "bindings.hpp"

namespace py = pybind11;
using namespace pybind11::literals;

namespace acuity::python {

void bind_lodgen(py::module_ m) {
  py::register_exception<lodgen::InputError>(m, "InputError", PyExc_ValueError);
  m.def(
      "build",
      [](const std::string& input, const std::string& output, std::size_t levels, double ratio,
         double max_error, const std::string& backend, bool lock_border, const std::string& asset_root) {
        if (!(ratio >= 0.01 && ratio <= 0.99))
          throw py::value_error("ratio: a number in [0.01, 0.99], not " + std::to_string(ratio));
        if (!(max_error >= 0) || !std::isfinite(max_error))
          throw py::value_error("max_error: a finite number >= 0, not " + std::to_string(max_error));
        lodgen::ChainOptions o;
        o.levels = levels;
        o.ratio = ratio;
        o.max_error = max_error;
        o.decimate.lock_border = lock_border;
        if (!lodgen::parse_backend(backend, &o.decimate.backend))
          throw py::value_error("backend: meshopt, openmesh, cgal or cgal-lt");
        py::dict summary;
        py::list meshes;
        {
          bake::SceneChains sc;
          {
            py::gil_scoped_release release;
            if (!output.empty()) lodgen::check_output(output, {input}, {".glb", ".gltf"});  // before any work
            bake::ChainRequest request;
            request.input = input;
            request.asset_root = asset_root;
            request.chain = o;
            sc = bake::build_scene_chains(request);
            if (!output.empty()) {
              lodgen::GltfWriteOptions wo;
              wo.binary = !bake::is_gltf_text_path(output);
              lodgen::write_lod_gltf(output, sc.objects, sc.scene.materials, wo);
            }
          }
          for (std::size_t i = 0; i < sc.chains.size(); ++i) {
            py::list lv;
            for (const auto& l : sc.chains[i].levels)
              lv.append(py::dict("target"_a = l.target_triangles, "triangles"_a = l.mesh.triangle_count(),
                                 "hausdorff_diameters"_a = l.hausdorff,
                                 "normal_deviation_degrees"_a = l.normal_deviation, "seconds"_a = l.seconds));
            meshes.append(py::dict("name"_a = sc.scene.mesh_names[i], "diameter"_a = sc.chains[i].diameter,
                                   "levels"_a = lv, "warnings"_a = sc.chains[i].warnings));
          }
        }
        summary["input"] = input;
        summary["output"] = output;
        summary["backend"] = backend;
        summary["meshes"] = meshes;
        return summary;
      },
      "input"_a, "output"_a = "", "levels"_a = 0, "ratio"_a = 0.5, "max_error"_a = 0.0,
      "backend"_a = "meshopt", "lock_border"_a = false, "asset_root"_a = "",
      "Build a measured chain of levels for every mesh of `input` (OFF/OBJ/PLY/STL/glTF/GLB); write\n"
      "it as glTF with MSFT_lod when `output` is given, each node that draws a mesh at its world matrix:\n"
      "the same code and the same bytes as `acuity lodgen` (acuity::bake::build_scene_chains). Returns the "
      "summary as a dict. Raises\n"
      "acuity.lodgen.InputError (a ValueError) for bad input, a refused output (not .glb/.gltf, not a\n"
      "regular file, the input itself) or a glTF uri outside `asset_root` (default: the glTF's folder).");
}

}  // namespace acuity::python
