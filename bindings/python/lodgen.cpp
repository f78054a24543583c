// acuity.lodgen: the chain of levels from Python, as the command builds it.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>

#include "acuity/lodgen/chain.hpp"
#include "acuity/lodgen/gltf.hpp"
#include "acuity/lodgen/output.hpp"
#include "bindings.hpp"

namespace py = pybind11;
using namespace pybind11::literals;

namespace acuity::python {

void bind_lodgen(py::module_ m) {
  py::register_exception<lodgen::InputError>(m, "InputError", PyExc_ValueError);
  m.def("build", [](const std::string& input, const std::string& output, std::size_t levels, double ratio,
                    double max_error, const std::string& backend, bool lock_border, const std::string& asset_root) {
    if (!(ratio >= 0.01 && ratio <= 0.99)) throw py::value_error("ratio: a number in [0.01, 0.99], not " + std::to_string(ratio));
    if (!(max_error >= 0) || !std::isfinite(max_error)) throw py::value_error("max_error: a finite number >= 0, not " + std::to_string(max_error));
    lodgen::ChainOptions o;
    o.levels = levels;
    o.ratio = ratio;
    o.max_error = max_error;
    o.decimate.lock_border = lock_border;
    if (!lodgen::parse_backend(backend, &o.decimate.backend)) throw py::value_error("backend: meshopt, openmesh, cgal or cgal-lt");
    py::dict summary;
    py::list meshes;
    {
      lodgen::Scene scene;
      std::vector<lodgen::Chain> chains;
      {
        py::gil_scoped_release release;
        if (!output.empty()) lodgen::check_output(output, {input}, {".glb", ".gltf"});  // before any work
        lodgen::LoadOptions lo;
        lo.asset_root = asset_root;
        scene = lodgen::load_scene(input, lo);
        for (std::size_t i = 0; i < scene.meshes.size(); ++i)
          chains.push_back(lodgen::build_chain(scene.meshes[i], input + ": mesh '" + scene.mesh_names[i] + "'", o));
        std::vector<lodgen::LodObject> objects;
        for (std::size_t i = 0; i < chains.size(); ++i) {
          lodgen::LodObject obj;
          obj.name = scene.mesh_names[i];
          for (const auto& l : chains[i].levels) {
            obj.levels.push_back(l.mesh);
            obj.geometric_error.push_back(l.hausdorff);
            obj.normal_deviation.push_back(l.normal_deviation);
          }
          obj.material = obj.levels[0].material;
          objects.push_back(std::move(obj));
        }
        if (!output.empty()) {
          lodgen::GltfWriteOptions wo;
          wo.binary = output.size() < 5 || (output.compare(output.size() - 5, 5, ".gltf") != 0 && output.compare(output.size() - 5, 5, ".GLTF") != 0);
          lodgen::write_lod_gltf(output, objects, scene.materials, wo);
        }
      }
      for (std::size_t i = 0; i < chains.size(); ++i) {
        py::list lv;
        for (const auto& l : chains[i].levels)
          lv.append(py::dict("target"_a = l.target_triangles, "triangles"_a = l.mesh.triangle_count(),
                             "hausdorff_diameters"_a = l.hausdorff, "normal_deviation_degrees"_a = l.normal_deviation,
                             "seconds"_a = l.seconds));
        meshes.append(py::dict("name"_a = scene.mesh_names[i], "diameter"_a = chains[i].diameter, "levels"_a = lv,
                               "warnings"_a = chains[i].warnings));
      }
    }
    summary["input"] = input;
    summary["output"] = output;
    summary["backend"] = backend;
    summary["meshes"] = meshes;
    return summary;
  }, "input"_a, "output"_a = "", "levels"_a = 0, "ratio"_a = 0.5, "max_error"_a = 0.0, "backend"_a = "meshopt",
     "lock_border"_a = false, "asset_root"_a = "",
  "Build a measured chain of levels for every mesh of `input` (OFF/OBJ/PLY/STL/glTF/GLB); write\n"
  "it as glTF with MSFT_lod when `output` is given. Returns the summary as a dict. Raises\n"
  "acuity.lodgen.InputError (a ValueError) for bad input, a refused output (not .glb/.gltf, not a\n"
  "regular file, the input itself) or a glTF uri outside `asset_root` (default: the glTF's folder).");
}

}  // namespace acuity::python
