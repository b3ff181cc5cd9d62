#!/usr/bin/env bash
# Builds glyphcast's C API (capi/: libglyphcast_c) and the C example engine
# (examples/c/main.c) with the system C compiler against include/glyphcast.h, and runs
# it: `bash tools/c-example.sh OUT.png [--plain-memory]` writes the example's last frame
# (--plain-memory: glyphcast's memory from the example's allocation callbacks). The example
# exits non-zero on any failure or validation message. The library is built in the test
# profile, so that `cargo test -p glyphcast-c` (which runs this script) and the script
# share one build of glyphcast.
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:?usage: bash tools/c-example.sh OUT.png [--plain-memory]}"
shift
. tools/env.sh
export GLYPHCAST_LAVAPIPE="${GLYPHCAST_LAVAPIPE:-1}"
lib="${CARGO_TARGET_DIR:-$PWD/target}/debug"
cargo build --locked --profile test -p glyphcast-c
build="${CARGO_TARGET_DIR:-$PWD/target}/c-example"
mkdir -p "$build"
# The library's SONAME is versioned (capi/build.rs): the example finds it, under that
# name, in its own folder, which links to the build.
soname=$(objdump -p "$lib/libglyphcast_c.so" | awk '$1 == "SONAME" { print $2 }')
ln -sf "$lib/libglyphcast_c.so" "$build/${soname:-libglyphcast_c.so}"
# The example compiles its own plane shaders (examples/shaders/) with shaderc's C API,
# linked as the Rust build links it (crates/glyphcast-shaderc-link): the static shaderc
# of SHADERC_LIB_DIR as it is; on Debian 12, whose libshaderc.so leaves glslang's
# symbols undefined, the static shaderc with the static glslang and SPIRV-Tools
# libraries of the same folder; elsewhere the system's own shaderc.
sys=$(pkg-config --variable=libdir shaderc 2>/dev/null || true)
sys=${sys:-/usr/lib/$(uname -m)-linux-gnu}
parts=(glslang SPIRV MachineIndependent GenericCodeGen OSDependent OGLCompiler
       SPIRV-Tools-opt SPIRV-Tools)
# (Read whole before grep: with pipefail, `nm | grep -q` fails when grep stops early.)
undefined=$(nm -D --undefined-only "$sys/libshaderc.so" 2>/dev/null || true)
if [ -n "${SHADERC_LIB_DIR:-}" ]; then
  shaderc=(-L "$SHADERC_LIB_DIR" -l:libshaderc_combined.a -lstdc++ -lpthread)
elif [ -f "$sys/libshaderc_combined.a" ] && [ -f "$sys/libglslang.a" ] \
    && grep -q glslang <<<"$undefined"; then
  shaderc=(-L "$sys" -Wl,--start-group -l:libshaderc_combined.a)
  for part in "${parts[@]}"; do
    [ -f "$sys/lib$part.a" ] && shaderc+=("-l:lib$part.a")
  done
  shaderc+=(-Wl,--end-group -lstdc++ -lpthread)
else
  shaderc=(-lshaderc)
fi
cc -std=c11 -Wall -Wextra -Werror -O1 -I include \
    -DPLANE_SHADER_DIR="\"$PWD/examples/shaders\"" examples/c/main.c \
    -L "$lib" -lglyphcast_c -lvulkan "${shaderc[@]}" -lm -Wl,-rpath,"$build" \
    -o "$build/c-example"
"$build/c-example" "$out" "$@"
