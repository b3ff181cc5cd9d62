#!/usr/bin/env bash
# Builds glyphcast's C library (capi/, package glyphcast-c) and installs it under PREFIX
# the way C and C++ builds look for a library:
#
#   PREFIX/include/glyphcast.h                      the header (cbindgen's, checked in)
#   PREFIX/lib/libglyphcast_c.so.<ABI>              the shared library, SONAME the same
#   PREFIX/lib/libglyphcast_c.so -> .so.<ABI>       what -lglyphcast_c links against
#   PREFIX/lib/libglyphcast_c.a                     the static library
#   PREFIX/lib/pkgconfig/glyphcast.pc               pkg-config --cflags --libs glyphcast
#   PREFIX/lib/cmake/glyphcast/glyphcastConfig.cmake (+ ConfigVersion)
#                                                   find_package(glyphcast CONFIG): the
#                                                   targets glyphcast::glyphcast (shared)
#                                                   and glyphcast::glyphcast_static
#
#   bash tools/install-c.sh [--debug] PREFIX
#
# Release build by default. --debug installs the development build instead
# (`cargo build --profile test -p glyphcast-c`, the build tools/c-example.sh and the
# tests already make, so the test of the installed library costs no second build of
# glyphcast); it is slower at run time and meant for tests, not for users.
#
# cargo-c (`cargo cinstall`) is the usual tool for this. It is not used here because it
# is one more large tool to compile from source (`cargo install cargo-c`: many minutes),
# and what it would add for this library is three small text files; they are written
# below, relocatable (both find the prefix from their own location).
#
# Neither library links libvulkan: glyphcast loads every Vulkan function through the
# vkGetInstanceProcAddr the host passes, so the host program links (or opens) the
# Vulkan loader itself.
# ABI is the version's major, or 0.<minor> while the major is 0 (capi/build.rs sets the
# SONAME). The shared library carries no RUNPATH and needs only the C runtime: a
# program finds it through its own rpath (CMake sets one for builds in the build tree;
# pass -Wl,-rpath,PREFIX/lib with pkg-config) or LD_LIBRARY_PATH, or from a prefix the
# dynamic linker searches (/usr/local/lib after ldconfig).
set -euo pipefail
cd "$(dirname "$0")/.."
usage="usage: bash tools/install-c.sh [--debug] PREFIX"
profile=release
if [ "${1:-}" = --debug ]; then
    profile=debug
    shift
fi
prefix="${1:?$usage}"
[ $# -eq 1 ] || { echo "$usage" >&2; exit 2; }
. tools/env.sh
if [ "$profile" = release ]; then
    cargo build --locked --release -p glyphcast-c
else
    cargo build --locked --profile test -p glyphcast-c
fi
built="${CARGO_TARGET_DIR:-$PWD/target}/$profile"

version=$(sed -n 's/^version = "\(.*\)"$/\1/p' capi/Cargo.toml | head -n 1)
soname=$(objdump -p "$built/libglyphcast_c.so" | awk '$1 == "SONAME" { print $2 }')
if [ -z "$soname" ]; then
    echo "error: $built/libglyphcast_c.so has no SONAME (capi/build.rs sets it)" >&2
    exit 1
fi
# What the static library needs from the system, as
# `cargo rustc -p glyphcast-c --release --lib --crate-type staticlib -- --print native-static-libs`
# prints it (Linux, glibc: "-ldl -lgcc_s -lutil -lrt -lpthread -lm -ldl -lc"; the first
# -ldl is libloading's, with which the core can open the loader, unused by the C API);
# libvulkan is not among them.
static_libs="-lgcc_s -lutil -lrt -lpthread -lm -ldl -lc"

mkdir -p "$prefix/include" "$prefix/lib/pkgconfig" "$prefix/lib/cmake/glyphcast"
prefix=$(cd "$prefix" && pwd)
install -m 644 include/glyphcast.h "$prefix/include/glyphcast.h"
install -m 755 "$built/libglyphcast_c.so" "$prefix/lib/$soname"
ln -sfn "$soname" "$prefix/lib/libglyphcast_c.so"
install -m 644 "$built/libglyphcast_c.a" "$prefix/lib/libglyphcast_c.a"
if [ "$profile" = release ]; then
    strip --strip-debug "$prefix/lib/$soname"
fi

cat > "$prefix/lib/pkgconfig/glyphcast.pc" <<EOF
# glyphcast's C library (include/glyphcast.h). The header includes <vulkan/vulkan.h>
# from the system's Vulkan headers; glyphcast does not link the Vulkan loader (the
# program passes its vkGetInstanceProcAddr). Static linking: pkg-config --static.
prefix=\${pcfiledir}/../..
libdir=\${prefix}/lib
includedir=\${prefix}/include

Name: glyphcast
Description: Vulkan ray caster for tensor and spherical-harmonic glyphs, embedded in a host's frame
Version: $version
Cflags: -I\${includedir}
Libs: -L\${libdir} -lglyphcast_c
Libs.private: $static_libs
EOF

cmake_libs=$(sed 's/-l//g; s/ /;/g' <<<"$static_libs")
cat > "$prefix/lib/cmake/glyphcast/glyphcastConfig.cmake" <<EOF
# glyphcast's C library: find_package(glyphcast CONFIG REQUIRED), then link
# glyphcast::glyphcast (the shared library) or glyphcast::glyphcast_static. The header
# includes <vulkan/vulkan.h>: link Vulkan::Vulkan (or Vulkan::Headers) too. glyphcast
# does not link the Vulkan loader; the program passes its vkGetInstanceProcAddr.
get_filename_component(_glyphcast_prefix "\${CMAKE_CURRENT_LIST_DIR}/../../.." ABSOLUTE)
if(NOT TARGET glyphcast::glyphcast)
  add_library(glyphcast::glyphcast SHARED IMPORTED)
  set_target_properties(glyphcast::glyphcast PROPERTIES
    IMPORTED_LOCATION "\${_glyphcast_prefix}/lib/$soname"
    IMPORTED_SONAME "$soname"
    INTERFACE_INCLUDE_DIRECTORIES "\${_glyphcast_prefix}/include")
  add_library(glyphcast::glyphcast_static STATIC IMPORTED)
  set_target_properties(glyphcast::glyphcast_static PROPERTIES
    IMPORTED_LOCATION "\${_glyphcast_prefix}/lib/libglyphcast_c.a"
    IMPORTED_LINK_INTERFACE_LANGUAGES "C"
    INTERFACE_INCLUDE_DIRECTORIES "\${_glyphcast_prefix}/include"
    INTERFACE_LINK_LIBRARIES "$cmake_libs")
endif()
unset(_glyphcast_prefix)
EOF

major=${version%%.*}
minor=${version#*.}
minor=${minor%%.*}
cat > "$prefix/lib/cmake/glyphcast/glyphcastConfigVersion.cmake" <<EOF
# find_package(glyphcast X.Y) accepts this version ($version) when the ABI matches: the
# same major version, and the same minor while the major is 0; and not older than asked.
set(PACKAGE_VERSION "$version")
set(PACKAGE_VERSION_COMPATIBLE FALSE)
if(NOT PACKAGE_FIND_VERSION VERSION_GREATER PACKAGE_VERSION
   AND "\${PACKAGE_FIND_VERSION_MAJOR}" STREQUAL "$major"
   AND ("$major" STREQUAL "0" AND "\${PACKAGE_FIND_VERSION_MINOR}" STREQUAL "$minor"
        OR NOT "$major" STREQUAL "0"))
  set(PACKAGE_VERSION_COMPATIBLE TRUE)
endif()
if(PACKAGE_FIND_VERSION STREQUAL PACKAGE_VERSION)
  set(PACKAGE_VERSION_EXACT TRUE)
endif()
EOF
echo "installed glyphcast $version ($profile) into $prefix"
