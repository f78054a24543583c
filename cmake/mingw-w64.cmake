# Cross-compiles for 64-bit Windows with Debian's mingw-w64 (package g++-mingw-w64-x86-64): the
# runtime's portability check. Use with the runtime-only configuration, which needs nothing but
# the compiler's own standard library:
#   cmake -S . -B build-mingw -G Ninja -DCMAKE_TOOLCHAIN_FILE=cmake/mingw-w64.cmake \
#         -DACUITY_RUNTIME_ONLY=ON -DACUITY_TESTS=OFF -DACUITY_BENCH=OFF
#   cmake --build build-mingw      # acuity_scheduler, acuity_c (static) and hello_lod.exe
set(CMAKE_SYSTEM_NAME Windows)
set(CMAKE_SYSTEM_PROCESSOR x86_64)
set(ACUITY_MINGW_PREFIX x86_64-w64-mingw32)

# The -posix flavour (std::thread/std::mutex through winpthreads) is Debian's default alternative;
# the runtime uses no threads, so either flavour builds it. Name the flavour to be independent of
# update-alternatives.
set(CMAKE_C_COMPILER ${ACUITY_MINGW_PREFIX}-gcc-posix)
set(CMAKE_CXX_COMPILER ${ACUITY_MINGW_PREFIX}-g++-posix)
set(CMAKE_RC_COMPILER ${ACUITY_MINGW_PREFIX}-windres)

# Headers and libraries come from the Windows sysroot only, never from the build machine's /usr.
set(CMAKE_FIND_ROOT_PATH /usr/${ACUITY_MINGW_PREFIX})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# Executables carry their C and C++ runtimes, so hello_lod.exe runs on a Windows machine (or under
# wine) without the mingw DLLs next to it.
set(CMAKE_EXE_LINKER_FLAGS_INIT "-static -static-libgcc -static-libstdc++")
