#pragma once
#include <pybind11/pybind11.h>

namespace acuity::python {
void bind_models(pybind11::module_ m);
}  // namespace acuity::python
