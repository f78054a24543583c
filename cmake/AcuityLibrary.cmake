# acuity_add_library(<name> [STATIC] <sources>...): one of the project's libraries as every one is
# declared: target acuity_<name>, alias acuity::<name> (link by it), export name <name>, its
# include/ public (build tree and install), C++20, the project's warnings. Each folder adds its own
# dependencies and installs its headers.
include(AcuityWarnings)
function(acuity_add_library name)
  add_library(acuity_${name} ${ARGN})
  add_library(acuity::${name} ALIAS acuity_${name})
  set_target_properties(acuity_${name} PROPERTIES EXPORT_NAME ${name})
  target_include_directories(acuity_${name} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_compile_features(acuity_${name} PUBLIC cxx_std_20)
  acuity_target_warnings(acuity_${name})
endfunction()
