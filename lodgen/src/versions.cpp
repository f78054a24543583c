#include "acuity/lodgen/versions.hpp"

#include <CGAL/version_macros.h>
#include <OpenMesh/Core/System/config.h>
#include <opensubdiv/version.h>

namespace acuity::lodgen {

std::string library_versions() {
  return "OpenMesh " + std::to_string(OM_GET_VER) + "." + std::to_string(OM_GET_MAJ) +
         ", CGAL " CGAL_VERSION_STR + std::string(", OpenSubdiv ") +
         std::to_string(OPENSUBDIV_VERSION_MAJOR) + "." + std::to_string(OPENSUBDIV_VERSION_MINOR) + "." +
         std::to_string(OPENSUBDIV_VERSION_PATCH);
}

}  // namespace acuity::lodgen
