# The offline dependencies, all from Debian 12 packages. Each becomes an imported target with a
# plain name; lodgen/, spectra/ and tools/ link those. The runtime (scheduler/) uses none of them.
include_guard(GLOBAL)

find_package(glm REQUIRED)                  # libglm-dev: header-only maths of the simulation and the OSG kit
find_package(OpenMesh REQUIRED)             # libopenmesh-dev: OpenMeshCore, OpenMeshTools
find_package(CGAL REQUIRED)                 # libcgal-dev: header-only CGAL::CGAL
find_package(Eigen3 REQUIRED)               # libeigen3-dev: CGAL's Garland-Heckbert policies
include(CGAL_Eigen3_support)                # -> CGAL::Eigen3_support
find_package(TinyGLTF REQUIRED)             # libtinygltf-dev: shared TinyGLTF::TinyGLTF
find_package(nlohmann_json REQUIRED)        # nlohmann-json3-dev
find_package(TBB REQUIRED)                  # libtbb-dev: oneTBB
find_package(PkgConfig REQUIRED)
pkg_check_modules(FFTW3 REQUIRED IMPORTED_TARGET fftw3f fftw3)   # libfftw3-dev

# OpenSubdiv: Debian's OpenSubdivConfig.cmake names static libraries the package does not ship,
# so find the shared CPU library and the headers directly.
if(NOT TARGET acuity_opensubdiv)
  find_path(OPENSUBDIV_INCLUDE_DIR opensubdiv/version.h REQUIRED)
  find_library(OPENSUBDIV_CPU_LIBRARY NAMES osdCPU REQUIRED)
  add_library(acuity_opensubdiv INTERFACE IMPORTED GLOBAL)
  set_target_properties(acuity_opensubdiv PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${OPENSUBDIV_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${OPENSUBDIV_CPU_LIBRARY}")
endif()

# stb (PNG encoding): Debian's libstb-dev, the shared library tinygltf itself links.
find_path(STB_INCLUDE_DIR stb_image_write.h PATH_SUFFIXES stb REQUIRED)
find_library(STB_LIBRARY stb REQUIRED)

# meshoptimizer (lodgen's default decimation back-end): Debian's libmeshoptimizer-dev ships the
# shared library and header without a CMake config.
find_path(MESHOPTIMIZER_INCLUDE_DIR meshoptimizer.h REQUIRED)
find_library(MESHOPTIMIZER_LIBRARY meshoptimizer REQUIRED)

# METIS (lodgen's cluster hierarchies group neighbouring clusters by graph partitioning): Debian's
# libmetis-dev ships the library and header without a CMake config.
find_path(METIS_INCLUDE_DIR metis.h REQUIRED)
find_library(METIS_LIBRARY metis REQUIRED)
