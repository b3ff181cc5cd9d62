#!/usr/bin/env bash
# Installs glyphcast's C library into a prefix (tools/install-c.sh), builds the C++
# example engine (examples/cpp/) against that installation three ways and runs each:
#
#   OUT.png            CMake, find_package(glyphcast), the shared library
#   OUT-static.png     CMake, glyphcast::glyphcast_static (libglyphcast_c.a)
#   OUT-pkgconfig.png  c++ with `pkg-config --cflags --libs glyphcast vulkan`
#
#   bash tools/cpp-example.sh [--debug] OUT.png
#
# The prefix and the builds are in target/cpp-example/. --debug installs the development
# build of the library (what `cargo test -p glyphcast-c` has built already; see
# tools/install-c.sh), as that test does; without it the release build. The example
# exits non-zero on any failure or validation message (the layer is always on).
set -euo pipefail
cd "$(dirname "$0")/.."
usage="usage: bash tools/cpp-example.sh [--debug] OUT.png"
debug=()
if [ "${1:-}" = --debug ]; then
    debug=(--debug)
    shift
fi
out="${1:?$usage}"
out="$(cd "$(dirname "$out")" && pwd)/$(basename "$out")"
export GLYPHCAST_LAVAPIPE="${GLYPHCAST_LAVAPIPE:-1}"
. tools/env.sh
work="${CARGO_TARGET_DIR:-$PWD/target}/cpp-example"
prefix="$work/prefix"
rm -rf "$prefix"
bash tools/install-c.sh "${debug[@]}" "$prefix"

echo "== CMake: find_package(glyphcast CONFIG), the shared library"
cmake -S examples/cpp -B "$work/cmake-shared" -DCMAKE_PREFIX_PATH="$prefix" \
    -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/cmake-shared" >/dev/null
"$work/cmake-shared/glyphcast-cpp-example" "$out"

echo "== CMake: glyphcast::glyphcast_static"
cmake -S examples/cpp -B "$work/cmake-static" -DCMAKE_PREFIX_PATH="$prefix" \
    -DCMAKE_BUILD_TYPE=Release -DGLYPHCAST_STATIC=ON >/dev/null
cmake --build "$work/cmake-static" >/dev/null
if ldd "$work/cmake-static/glyphcast-cpp-example" | grep -q libglyphcast_c; then
    echo "error: the static build links libglyphcast_c.so" >&2
    exit 1
fi
"$work/cmake-static/glyphcast-cpp-example" "${out%.png}-static.png"

echo "== pkg-config"
export PKG_CONFIG_PATH="$prefix/lib/pkgconfig${PKG_CONFIG_PATH:+:$PKG_CONFIG_PATH}"
# shellcheck disable=SC2046 # pkg-config's flags are words
c++ -std=c++17 -O2 -Wall -Wextra -Werror -Wno-missing-field-initializers examples/cpp/main.cpp \
    $(pkg-config --cflags --libs glyphcast vulkan) -Wl,-rpath,"$prefix/lib" \
    -o "$work/pkgconfig-example"
"$work/pkgconfig-example" "${out%.png}-pkgconfig.png"
