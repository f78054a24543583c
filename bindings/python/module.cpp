// The native part of the Python package `acuity`. Each area registers its own submodule.
#include <pybind11/pybind11.h>

#include "acuity/file.hpp"
#include "acuity/version.hpp"
#include "bindings.hpp"

PYBIND11_MODULE(_acuity, m) {
  m.doc() = "acuity native module; import the package `acuity` instead.";
  m.attr("__version__") = ACUITY_VERSION_STRING;
  // acuity::io's one error (acuity/file.hpp): a file that cannot be read or written as asked.
  pybind11::register_exception<acuity::io::Error>(m, "FileError", PyExc_ValueError);
  acuity::python::bind_models(m.def_submodule("models", "Vision models (see acuity.models)"));
  acuity::python::bind_scheduler(m);
  acuity::python::bind_spectra(
      m.def_submodule("spectra", "Profiles, snapshots and analysis (see acuity.spectra)"));
  acuity::python::bind_foveation(
      m.def_submodule("foveation", "Shading-rate and mip-bias maps (see acuity.foveation)"));
  acuity::python::bind_lodgen(m.def_submodule("lodgen", "Chains of levels of detail (see acuity.lodgen)"));
  acuity::python::bind_clusters(
      m.def_submodule("clusters", "Detail that follows the gaze inside one object (see acuity.clusters)"));
  acuity::python::bind_sim(m.def_submodule("sim", "Simulated runs through the LOD rules (see acuity.sim)"));
  acuity::python::bind_bake(m.def_submodule("_bake", "Baking an asset library (see acuity.bake)"));
}
