# Sourced by the tools/ scripts: Vulkan driver selection for glyphcast.
# GLYPHCAST_LAVAPIPE=1 forces Mesa's software rasteriser (lavapipe), which the tests use
# so that they run the same on every machine; otherwise the loader sees every driver.
lvp_icd=/usr/share/vulkan/icd.d/lvp_icd.$(uname -m).json
if [ "${GLYPHCAST_LAVAPIPE:-0}" = 1 ] && [ -z "${VK_DRIVER_FILES:-}" ] && [ -f "$lvp_icd" ]; then
  export VK_DRIVER_FILES="$lvp_icd"
fi
# Find cargo where rustup puts it when the shell did not source its profile.
if ! command -v cargo >/dev/null 2>&1 && [ -x "$HOME/.cargo/bin/cargo" ]; then
  export PATH="$HOME/.cargo/bin:$PATH"
fi
# The shaderc the build links (see tools/shaderc-lib.sh): Debian 12's own is incomplete.
if [ -z "${SHADERC_LIB_DIR:-}" ] && [ -z "${VULKAN_SDK:-}" ]; then
  shaderc_dir=$(bash "$(dirname "${BASH_SOURCE[0]}")/shaderc-lib.sh" \
    "${CARGO_TARGET_DIR:-$PWD/target}/shaderc")
  [ -n "$shaderc_dir" ] && export SHADERC_LIB_DIR="$shaderc_dir"
  unset shaderc_dir
fi
