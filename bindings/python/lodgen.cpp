// acuity.lodgen: the chain of levels from Python, as the command builds it.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "acuity/bake/chains.hpp"
#include "acuity/bake/library.hpp"
#include "acuity/lodgen/formats.hpp"
#include "bindings.hpp"

namespace py = pybind11;
using namespace pybind11::literals;

namespace acuity::python {

void bind_lodgen(py::module_ m) {
  py::register_exception<lodgen::InputError>(m, "InputError", PyExc_ValueError);
  // The formats named from lodgen's registry (acuity/lodgen/formats.hpp), as the command's help does.
  static const std::string build_doc =
      "Build a measured chain of levels for every mesh of `input` (" + lodgen::input_format_names() +
      "); write\n"
      "it as glTF with MSFT_lod when `output` is given, each node that draws a mesh at its world matrix:\n"
      "the same code and the same bytes as `acuity lodgen` (acuity::bake::build_scene_chains). Returns the "
      "summary as a dict (the JSON acuity lodgen writes beside its output). Raises\n"
      "acuity.lodgen.InputError (a ValueError) for bad input, a bad option, or a glTF uri outside\n"
      "`asset_root` (default: the glTF's folder), and acuity.FileError (a ValueError) for a file that\n"
      "cannot be read or a refused output (not .glb/.gltf, not a regular file, the input itself).\n"
      "Options (keywords) as acuity lodgen and acuity bake take them: levels, ratio, max_error,\n"
      "backend, lock_border, crease, measure_seconds, reference_height, asset_root.";
  m.def(
      "build",
      [](const std::string& input, const std::string& output, const py::kwargs& options) {
        // The options acuity bake and acuity lodgen take, checked by the library (bake::parse_options).
        const std::string text = py::str(py::module_::import("json").attr("dumps")(options));
        const bake::BakeOptions o = bake::parse_options(text, bake::BakeOptions{}, "options");
        const bake::ChainRequest request = bake::chain_request(input, o);
        std::string summary;
        {
          py::gil_scoped_release release;
          summary = bake::write_scene_chains(request, output, o.reference_height, o.backend).json;
        }
        return py::module_::import("json").attr("loads")(summary);
      },
      "input"_a, "output"_a = "", build_doc.c_str());
}

}  // namespace acuity::python
