#!/usr/bin/env bash
# Part of tools/test.sh: the crates a registry would receive, checked as it receives
# them; then the shaderc helper's own tests and the message its build script stops with.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v cargo >/dev/null 2>&1 && [ -x "$HOME/.cargo/bin/cargo" ]; then
    PATH="$HOME/.cargo/bin:$PATH"
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
    GLYPHCAST_SPIRV_CACHE="${GLYPHCAST_SPIRV_CACHE:-$workspace_target/glyphcast-spirv-cache}" \
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
