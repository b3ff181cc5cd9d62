#!/usr/bin/env bash
# Mesa 25's lavapipe beside the system's (Debian 12: Mesa 22.3), without replacing it:
# downloads the packages from Debian's bookworm-backports and unpacks them into a folder
# (target/mesa25/, or the one given), with an ICD file that points at the unpacked
# driver. Nothing is installed; the one change to the system is the backports source
# (/etc/apt/sources.list.d/bookworm-backports.sources), added when no source lists the
# suite. apt never picks a backport on its own (their priority is 100), so installed
# packages and upgrades stay as they were.
#
#   bash tools/mesa25.sh [DIR]      prints the two lines that select the driver:
#   eval "$(bash tools/mesa25.sh)"  then Vulkan programs in this shell use Mesa 25's
#                                   lavapipe (VK_DRIVER_FILES, LD_LIBRARY_PATH)
#
# The driver (libvulkan_lvp.so) needs a newer libdrm than Debian 12's (2.4.121 or later):
# the backport's libdrm2 and libdrm-amdgpu1 are unpacked beside it and found through
# LD_LIBRARY_PATH. Its other libraries, LLVM 15's included, are Debian 12's. Safe to run
# again: the packages are fetched once.
set -euo pipefail
cd "$(dirname "$0")/.."
dest="${1:-$PWD/target/mesa25}"
suite=bookworm-backports
packages=(mesa-vulkan-drivers libdrm2 libdrm-amdgpu1)
arch=$(dpkg --print-architecture)
triplet=$(dpkg-architecture -qDEB_HOST_MULTIARCH 2>/dev/null || gcc -print-multiarch)
icd="$dest/lvp_icd.$(uname -m).json"

if [ ! -f "$icd" ]; then
    sudo_cmd=()
    [ "$(id -u)" -ne 0 ] && sudo_cmd=(sudo)
    if ! apt-cache policy | grep -q " $suite/main $arch "; then
        echo "adding $suite to apt's sources (/etc/apt/sources.list.d/$suite.sources)" >&2
        "${sudo_cmd[@]}" tee "/etc/apt/sources.list.d/$suite.sources" >/dev/null <<EOF
# Added by glyphcast's tools/mesa25.sh, which unpacks Mesa 25's lavapipe from here
# (apt never installs a backport unless asked: nothing installed changes).
Types: deb
URIs: http://deb.debian.org/debian
Suites: $suite
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
EOF
        "${sudo_cmd[@]}" apt-get update -qq
    fi
    mkdir -p "$dest/debs"
    # apt's download user (_apt) may not write here: the files come down as root then,
    # which apt warns about; the warning is left out.
    (cd "$dest/debs" && apt-get download -qq "${packages[@]/%//$suite}" 2>&1 \
        | grep -v 'Download is performed unsandboxed' >&2 || true)
    for p in "${packages[@]}"; do
        ls "$dest/debs/${p}_"*.deb >/dev/null || { echo "error: $p was not downloaded" >&2; exit 1; }
    done
    for deb in "$dest"/debs/*.deb; do
        dpkg-deb -x "$deb" "$dest/root"
    done
    lvp="$dest/root/usr/lib/$triplet/libvulkan_lvp.so"
    [ -f "$lvp" ] || { echo "error: no $lvp in the packages" >&2; exit 1; }
    # The packaged ICD file (lvp_icd.json from Mesa 24 on, lvp_icd.<arch>.json before),
    # with the unpacked driver's path in place of the system's; written last, as the
    # sign that the folder is complete.
    packaged=$(ls "$dest"/root/usr/share/vulkan/icd.d/lvp_icd*.json | head -n 1)
    sed "s|\"library_path\": *\"[^\"]*\"|\"library_path\": \"$lvp\"|" "$packaged" > "$icd.part"
    grep -q "\"library_path\": \"$lvp\"" "$icd.part"
    mv "$icd.part" "$icd"
    version=$(dpkg-deb -f "$dest"/debs/mesa-vulkan-drivers_*.deb Version)
    echo "Mesa $version's lavapipe unpacked into $dest" >&2
fi
echo "export VK_DRIVER_FILES=$icd"
echo "export LD_LIBRARY_PATH=$dest/root/usr/lib/$triplet\${LD_LIBRARY_PATH:+:\$LD_LIBRARY_PATH}"
