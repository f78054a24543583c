#pragma once
#include <pybind11/pybind11.h>

#include <memory>
#include <string>

#include "acuity/blob.hpp"
#include "acuity/models.hpp"
#include "acuity/profile.hpp"

namespace acuity::python {
// A profile that owns its bytes (a Profile only points into them): acuity.Profile.
struct OwnedProfile {
  Blob blob;
  Profile view{};
};
// Reads and validates a .acuity file (ValueError naming it when bad; acuity.FileError when unreadable).
std::shared_ptr<OwnedProfile> profile_from_file(const std::string& path);
void bind_models(pybind11::module_ m);
void bind_scheduler(pybind11::module_ m);  // into the package's top level
void bind_spectra(pybind11::module_ m);
void bind_lodgen(pybind11::module_ m);
void bind_foveation(pybind11::module_ m);
void bind_bake(pybind11::module_ m);  // acuity._acuity._bake, used by acuity.bake (bake.py)
void bind_sim(pybind11::module_ m);
void bind_clusters(pybind11::module_ m);  // acuity.clusters: cluster cuts of one object
// "threshold model name: default, ..." (acuity::threshold_model_names()), for the config properties.
const char* threshold_model_doc();
// The model a name names (parse_threshold_model); ValueError listing the names otherwise.
ThresholdModel model_from(const std::string& name);
}  // namespace acuity::python
