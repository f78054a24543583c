#pragma once
#include <string>

namespace acuity::lodgen {
// "OpenMesh 9.0, CGAL 5.5.1, OpenSubdiv 3.5.0": the versions lodgen was built against.
std::string library_versions();
}  // namespace acuity::lodgen
