#!/usr/bin/env bash
# acuity's one setup script: installs the Debian packages, configures and builds, then runs a job.
#   bash scripts/bootstrap.sh demo   # set up, build, run the main job on its embedded default
#   bash scripts/bootstrap.sh test   # set up, build, run every test (what .ci/run runs)
#   bash scripts/bootstrap.sh deps   # only install the packages
# Idempotent: packages already present are not reinstalled; the build is incremental.
set -euo pipefail
cd "$(dirname "$0")/.."

# Every package the project needs, in one list. Debian 12 names.
PACKAGES=(
  build-essential cmake ninja-build pkg-config clang
  clang-format                                # scripts/check_format.sh: the code matches .clang-format (version 14)
  libglm-dev                                  # runtime (scheduler/): header-only maths
  libopenmesh-dev libcgal-dev libosd-dev      # lodgen/: mesh IO, repair, decimation, subdivision
  libeigen3-dev                               # CGAL's Garland-Heckbert quadrics need Eigen
  libtinygltf-dev libstb-dev nlohmann-json3-dev
  libfftw3-dev libtbb-dev                     # spectra/: analysis, parallelism
  libcli11-dev                                # tools/: the acuity command
  pybind11-dev python3-dev python3-numpy python3-matplotlib python3-pytest   # bindings/
  libgtest-dev libgmock-dev libbenchmark-dev  # tests/, bench/
  libcgal-demo libmeshoptimizer-dev           # real meshes for tests and benchmarks; meshoptimizer as the reference
  libmetis-dev                                # lodgen --clusters: groups of neighbouring clusters by graph partitioning
  emscripten chromium                         # web/: the runtime in WebAssembly, the page tested in headless Chromium
  assimp-testmodels                           # broken glTFs that seed the glTF fuzzer (tests/fuzz/); real assets (lodgen's tests, the demo's Wuson)
  libopenscenegraph-dev xvfb xauth libgl1-mesa-dri   # integrations/osg/: the OSG kit, rendered headless (llvmpipe) under xvfb-run
  g++-mingw-w64-x86-64                        # the runtime and the C ABI cross-compiled for Windows (portability check)
  python3-distributed                         # acuity.bake on a Dask cluster (LocalCluster in the tests)
  python3-pip python3-setuptools python3-wheel python3-venv   # pip install build/python into a venv (the python_package test)
)

install_packages() {
  local missing=()
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    echo "== installing: ${missing[*]}"
    local sudo=""; [ "$(id -u)" -ne 0 ] && sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
  fi
}

# npm packages, each folder exactly as pinned in its lockfile (npm ci; reinstalled only when the
# lockfile changed); node and npm are on the machine already (never in PACKAGES: NodeSource's nodejs
# conflicts with Debian's npm). Nothing is fetched at build or test time.
#   web/               three, playwright-core, pngjs: the page and its tests (no browser download:
#                      the tests drive Debian's chromium)
#   assets/third_party/ @webxr-input-profiles/assets: 82 controller models (MIT) for lodgen's
#                      real-asset tests and the demo's field (two of them)
#   tests/node/        gltf-validator: the Khronos validator run on lodgen's output
install_npm_packages() {
  local dir
  for dir in web assets/third_party tests/node; do
    if ! cmp -s "$dir/package-lock.json" "$dir/node_modules/.acuity-installed-lock" 2>/dev/null; then
      echo "== npm ci ($dir/)"
      (cd "$dir" && PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1 npm ci --no-audit --no-fund --loglevel=error && \
        cp package-lock.json node_modules/.acuity-installed-lock)
    fi
  done
}

JOBS=${JOBS:-$(nproc)}
# Debian's python3, never a pyenv one found first on PATH: the bindings must load in it.
PY=/usr/bin/python3

configure_and_build() { # $1 build dir, rest: extra cmake args; CC/CXX pick the compiler
  local dir=$1; shift
  cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPython3_EXECUTABLE=$PY \
    ${CXX:+-DCMAKE_CXX_COMPILER=$CXX} ${CC:+-DCMAKE_C_COMPILER=$CC} "$@" >/dev/null
  cmake --build "$dir" -j "$JOBS"
}

case "${1:-test}" in
  deps) install_packages; install_npm_packages ;;
  demo)
    install_packages
    install_npm_packages
    configure_and_build build
    ./build/tools/acuity demo
    ;;
  test)
    install_packages
    install_npm_packages
    # Formatting: every C and C++ file matches .clang-format (clang-format 14; `clang-format -i FILE`).
    bash scripts/check_format.sh --all
    configure_and_build build
    ctest --test-dir build --output-on-failure -j "$JOBS"
    # The runtime alone (standard library + GLM): what an engine links must build by itself.
    configure_and_build build-runtime -DACUITY_RUNTIME_ONLY=ON -DACUITY_BENCH=OFF
    ctest --test-dir build-runtime --output-on-failure -j "$JOBS"
    # The runtime and the C ABI cross-compiled for Windows (mingw-w64, warnings as errors): static
    # libraries and hello_lod.exe must compile and link; nothing runs (no Windows here).
    CC= CXX= configure_and_build build-mingw -DCMAKE_TOOLCHAIN_FILE=cmake/mingw-w64.cmake \
      -DACUITY_RUNTIME_ONLY=ON -DACUITY_TESTS=OFF -DACUITY_BENCH=OFF
    # The same tests under AddressSanitizer + UndefinedBehaviorSanitizer.
    configure_and_build build-asan -DACUITY_SANITIZE=ON -DACUITY_BENCH=OFF -DACUITY_PYTHON=OFF -DACUITY_WEB=OFF
    ACUITY_QUICK_TESTS=1 ctest --test-dir build-asan --output-on-failure -j "$JOBS" -LE nosan
    # libFuzzer (Debian's clang): a short, seeded run of the profile reader and the importers.
    if command -v clang++ >/dev/null; then
      CC=clang CXX=clang++ configure_and_build build-fuzz -DACUITY_FUZZ=ON
      ctest --test-dir build-fuzz --output-on-failure -j "$JOBS"
    fi
    ;;
  *) echo "usage: $0 demo|test|deps" >&2; exit 2 ;;
esac
