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
# Nothing here is needed to build: the build links shaderc by itself, Debian 12's split
# one included (crates/glyphcast-shaderc-link).
