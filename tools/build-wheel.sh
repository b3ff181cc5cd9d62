#!/usr/bin/env bash
# Builds the Python module (python/) as one wheel for Linux on x86_64 (or the machine's
# architecture) that installs on CPython 3.9 and later (abi3) and on any distribution
# with glibc 2.28 or later (manylinux_2_28: RHEL/Rocky 8, Debian 10, Ubuntu 18.10 on):
#
#   bash tools/build-wheel.sh OUTDIR
#
# maturin builds it in release mode with zig as the C compiler and linker (`--zig`):
# zig links against glibc 2.28's symbol versions whatever this machine's glibc is. Both
# come from PyPI (maturin, ziglang) into a virtual environment of their own
# (target/wheel-venv, reused). The shaders are compiled into the library (build.rs) and
# so are inside the wheel; the Vulkan loader is not: the library opens libvulkan.so.1
# when the first Renderer is made, so the wheel needs nothing from the system to be
# imported, and a render on a machine without the loader or a driver raises an error
# naming the package to install. The script checks both: the wheel's platform tag and
# auditwheel's reading of its symbols, and that no libvulkan is in it or linked by it.
#
# A cold build takes many minutes on a small machine (the whole of glyphcast in release).
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:?usage: bash tools/build-wheel.sh OUTDIR}"
mkdir -p "$out"
out=$(cd "$out" && pwd)
. tools/env.sh
target="${CARGO_TARGET_DIR:-$PWD/target}"
venv="$target/wheel-venv"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
# The versions the wheel was last built and checked with (maturin 1.16, zig 0.17.1,
# auditwheel 6.8): a newer zig may change what it links.
"$venv/bin/python" -m pip install -q --disable-pip-version-check \
    'maturin>=1.9,<2' 'ziglang>=0.17,<0.18' 'auditwheel>=6,<7'

compat=manylinux_2_28
# zig is the C++ compiler for the target, whose triple is this machine's: the cc crate
# then takes it for the build scripts' C++ too (shaderc's, which compiles the shaders
# at build time and runs here), and zig's C++ library is libc++, which the host linker
# does not have. The library itself compiles no C++; the build scripts link the system's
# libstdc++, as they do in every other build.
export CXXSTDLIB=stdc++
# maturin writes into a folder of its own, so that the wheel checked is this build's.
fresh="$target/wheel-out"
rm -rf "$fresh"
(cd python && PATH="$venv/bin:$PATH" maturin build --locked --release --zig \
    --compatibility "$compat" --out "$fresh")
wheel=$(ls "$fresh"/glyphcast-*.whl)
case "$(basename "$wheel")" in
    *-cp39-abi3-"$compat"_*.whl) ;;
    *) echo "error: $wheel is not an abi3 (cp39) $compat wheel" >&2; exit 1 ;;
esac
"$venv/bin/auditwheel" show "$wheel" | tee "$target/wheel-auditwheel.txt"
if ! grep -q "\"$compat" "$target/wheel-auditwheel.txt"; then
    echo "error: auditwheel does not find $wheel consistent with $compat" >&2
    exit 1
fi
# No loader inside, none linked: the module's NEEDED entries are the C runtime's.
check="$target/wheel-check"
rm -rf "$check"
"$venv/bin/python" -m zipfile -e "$wheel" "$check"
if find "$check" -name 'libvulkan*' | grep -q .; then
    echo "error: $wheel holds a Vulkan loader" >&2
    exit 1
fi
module=$(find "$check" -name '_glyphcast*.so')
objdump -p "$module" | awk '$1 == "NEEDED" { print "needs", $2 }'
if objdump -p "$module" | grep -q 'NEEDED.*libvulkan'; then
    echo "error: $module links libvulkan (it should open it at run time)" >&2
    exit 1
fi
mv "$wheel" "$out/"
echo "built $out/$(basename "$wheel")"
