#!/usr/bin/env bash
# Fresh machine to a passing test suite: installs what is missing, then runs every test
# on lavapipe with the Vulkan validation layer on (the tests turn it on themselves), and
# checks that the core stays free of the front ends' dependencies and compiles alone from
# its package's own files (what an embedding engine and crates.io get); runs the C
# API's tests (its generated header, the C example engine built with cc, the C++ engine
# built with CMake and pkg-config against the installed library); then builds the
# Python module's wheel, installs it into a virtual environment (target/py-venv, reused)
# and runs its tests (python/tests) against the CLI, the workflow engines' (Nipype,
# pydra) and the example notebook included; then the GPU tests again on Mesa 25's
# lavapipe (GLYPHCAST_MESA25=0 skips them);
# last, as root, the cohort scripts on a one-node SLURM cluster it starts and stops
# (tests/slurm, tools/slurm-local.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
export GLYPHCAST_LAVAPIPE="${GLYPHCAST_LAVAPIPE:-1}"
. tools/env.sh
cargo test --locked "$@"
echo "== [${SECONDS} s] the core alone, as an engine depends on it"
# Cargo keeps the layers apart: the core's own dependency tree holds no front end's crate.
# flate2 is looked for among the direct dependencies only: the png crate deflates with it.
core_tree=$(cargo tree --locked -p glyphcast -e normal --prefix none)
core_direct=$(cargo tree --locked -p glyphcast -e normal --prefix none --depth 1)
if grep -E '^(clap|winit|plotters|indicatif|nifti|ndarray|clarabel|sha2|pyo3|glyphcast-[a-z]+) v' <<<"$core_tree" \
    || grep -E '^flate2 v' <<<"$core_direct"; then
    echo "error: the core's dependency tree holds a front end's crate (above)" >&2
    exit 1
fi
# The crates as crates.io would receive them: the core and the helper it links shaderc
# with (crates/glyphcast-shaderc-link, a path and version dependency), packaged
# together (cargo resolves the core's dependency on the helper to the helper's package:
# no path-only dependency), unpacked outside the workspace and checked from the
# packages' own files with their own Cargo.lock and the core's own features alone (no
# front end's feature unified in: what an engine compiles). From another folder each is
# another package to cargo, so it shares the workspace's target folder (the dependencies
# `.ci/run` checked for the core alone) without touching the workspace's artifacts
# (`cargo package`'s own verify build would: it has the same artifact hashes). The core
# finds the helper through a [patch] to the unpacked helper: its Cargo.lock then changes
# in exactly the helper's source and checksum, and that checksum is the packaged
# helper's. Its build script runs (the shaders come from the workspace's SPIR-V cache).
echo "== [${SECONDS} s] the core and its shaderc helper as crates.io would receive them"
cargo package --locked --allow-dirty --no-verify --quiet -p glyphcast-shaderc-link -p glyphcast
workspace_target="${CARGO_TARGET_DIR:-$PWD/target}"
core_version=$(cargo pkgid -p glyphcast | sed 's/.*[#@]//')
link_version=$(cargo pkgid -p glyphcast-shaderc-link | sed 's/.*[#@]//')
unpacked=$(mktemp -d)
for crate in "glyphcast-$core_version" "glyphcast-shaderc-link-$link_version"; do
    tar -xzf "$workspace_target/package/$crate.crate" -C "$unpacked"
done
(
    cd "$unpacked/glyphcast-shaderc-link-$link_version"
    cargo check --locked --offline --quiet --target-dir "$workspace_target"
)
(
    cd "$unpacked/glyphcast-$core_version"
    link_sum=$(sha256sum "$workspace_target/package/glyphcast-shaderc-link-$link_version.crate" | cut -d' ' -f1)
    cp Cargo.lock "$unpacked/Cargo.lock.packaged"
    GLYPHCAST_SPIRV_CACHE="$workspace_target/glyphcast-spirv-cache" \
        cargo check --offline --quiet --target-dir "$workspace_target" --config \
        "patch.crates-io.glyphcast-shaderc-link.path=\"../glyphcast-shaderc-link-$link_version\""
    lock_change=$(diff "$unpacked/Cargo.lock.packaged" Cargo.lock | grep '^[<>]' || true)
    expected="< source = \"registry+https://github.com/rust-lang/crates.io-index\"
< checksum = \"$link_sum\""
    if [ "$lock_change" != "$expected" ]; then
        printf 'error: the packaged core'"'"'s Cargo.lock differs from the patched one in more than the helper:\n%s\n' \
            "$lock_change" >&2
        exit 1
    fi
)
rm -rf "$unpacked"
# The helper's own tests (the ELF and archive checks, the message naming the packages).
cargo test --locked --quiet -p glyphcast-shaderc-link
# A build script that stops with the message rather than a linker's list: a pkg-config
# `shaderc` in a folder with Debian 12's split libshaderc.so and none of its parts.
if [ -f "/usr/lib/$(uname -m)-linux-gnu/libshaderc.so" ] && [ -f /etc/debian_version ] \
    && grep -q '^12' /etc/debian_version; then
    fake=$(mktemp -d)
    mkdir "$fake/lib" "$fake/pc"
    ln -s "/usr/lib/$(uname -m)-linux-gnu/libshaderc.so" "$fake/lib/libshaderc.so"
    ln -s "/usr/lib/$(uname -m)-linux-gnu/libshaderc_combined.a" "$fake/lib/libshaderc_combined.a"
    printf 'libdir=%s\nName: shaderc\nDescription: fake\nVersion: 2023.2\nLibs: -L${libdir} -lshaderc\n' \
        "$fake/lib" >"$fake/pc/shaderc.pc"
    if env -u SHADERC_LIB_DIR -u VULKAN_SDK PKG_CONFIG_LIBDIR="$fake/pc" \
        cargo check --locked --quiet -p glyphcast-shaderc-link --target-dir "$fake/target" \
        >"$fake/log" 2>&1; then
        echo "error: the helper's build script accepted a shaderc without its parts" >&2
        exit 1
    fi
    for package in "libshaderc-dev glslang-dev spirv-tools" libshaderc-devel VULKAN_SDK; do
        grep -q "$package" "$fake/log" || { cat "$fake/log" >&2
            echo "error: the helper's message does not name $package" >&2; exit 1; }
    done
    rm -rf "$fake"
fi
echo "== [${SECONDS} s] a new crate outside the repository, built with nothing sourced"
bash tools/outside-crate.sh
echo "== [${SECONDS} s] the C API (capi/): its header up to date, the C example engine (examples/c/)"
cargo test --locked -p glyphcast-c
echo "== [${SECONDS} s] the Python module (python/)"
# The CLI the Python tests compare with: built by `cargo test` above (a no-op then).
cargo test --locked --no-run --test integration
venv=target/py-venv
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/python" -m pip install -q --disable-pip-version-check \
    'maturin>=1.9,<2' numpy pytest nibabel dipy nipype 'pydra>=0.25,<1' \
    nbclient nbformat ipykernel pillow
# The module as users get it: a wheel, installed with pip into the environment, so the
# tests import it from site-packages, not from python/. Built in the dev profile in the
# shared target/ (minutes from cold, seconds when nothing changed); the release
# artifact (abi3, manylinux_2_28, by maturin --zig) is tools/build-wheel.sh's, whose
# own check, tools/test-wheel.sh, runs these tests against it in a fresh environment.
wheels=target/wheels/test
rm -rf "$wheels"
(cd python && VIRTUAL_ENV="$PWD/../$venv" PATH="$PWD/../$venv/bin:$PATH" \
    maturin build --locked --profile dev --quiet --out "../$wheels")
"$venv/bin/python" -m pip uninstall -q -y glyphcast >/dev/null 2>&1 || true
"$venv/bin/python" -m pip install -q --disable-pip-version-check --no-deps "$wheels"/glyphcast-*.whl
python=$PWD/$venv/bin/python
(cd / && "$python" -c 'import glyphcast; f = glyphcast.__file__
assert "site-packages" in f, "glyphcast imported from " + f')
# conftest.py turns the validation layer on (GLYPHCAST_VALIDATION=1) and picks lavapipe.
"$venv/bin/python" -m pytest -q python/tests
# ---- Mesa 25 (GLYPHCAST_MESA25=0 skips it) --------------------------------------------
# The GPU tests of the core (and its embedding example), of the C API (the C and C++
# example engines) and of the Python module again, on Mesa 25's lavapipe: unpacked from
# Debian's bookworm-backports beside the system's driver by tools/mesa25.sh (which adds
# that suite to apt's sources if no source lists it; nothing is installed).
if [ "${GLYPHCAST_MESA25:-1}" = 1 ]; then
    echo "== [${SECONDS} s] again on Mesa 25's lavapipe (tools/mesa25.sh)"
    (
        eval "$(bash tools/mesa25.sh)"
        # Every library's unit tests and the embedding example, with the features of the
        # workspace build above (so nothing is compiled again).
        cargo test --locked --lib --examples
        cargo test --locked -p glyphcast-c
        "$venv/bin/python" -m pytest -q python/tests
    )
fi
echo "== [${SECONDS} s] cohorts on SLURM (tests/slurm, on a local one-node cluster: tools/slurm-local.sh)"
if [ "$(id -u)" = 0 ]; then
    # The cluster stops on every exit, a failed test's included.
    trap 'bash tools/slurm-local.sh stop' EXIT
    bash tools/slurm-local.sh start
    eval "$(bash tools/slurm-local.sh env)"
    GLYPHCAST_BIN="$PWD/target/debug/glyphcast" PYTHON="$PWD/$venv/bin/python" \
        "$venv/bin/python" -m pytest -q tests/slurm
else
    echo "skipped: the local cluster's daemons run as root (run this as root, or start a" \
         "cluster and run pytest tests/slurm with SLURM_CONF set)" >&2
fi
echo "== [${SECONDS} s] done"
