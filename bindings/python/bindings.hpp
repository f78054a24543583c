#pragma once
#include <pybind11/pybind11.h>

namespace acuity::python {
void bind_models(pybind11::module_ m);
void bind_scheduler(pybind11::module_ m);  // into the package's top level
void bind_spectra(pybind11::module_ m);
void bind_lodgen(pybind11::module_ m);
void bind_foveation(pybind11::module_ m);
void bind_bake(pybind11::module_ m);  // acuity._acuity._bake, used by acuity.bake (bake.py)
void bind_sim(pybind11::module_ m);
// "threshold model name: default, ..." (acuity::threshold_model_names()), for the config properties.
const char* threshold_model_doc();
}  // namespace acuity::python
