#!/usr/bin/env bash
# Installs the Debian packages glyphcast needs to build and to run on lavapipe,
# only where they are missing. Safe to run again.
set -euo pipefail
pkgs=(mesa-vulkan-drivers libvulkan-dev vulkan-validationlayers
      libshaderc-dev glslang-dev spirv-tools pkg-config
      # `glyphcast view`: the X11 libraries winit loads at run time, and Xvfb, the
      # virtual X server its tests open their windows on.
      libx11-6 libx11-xcb1 libxcursor1 libxi6 libxrandr2 libxkbcommon-x11-0 xvfb
      # `glyphcast bench --out`: the font of the PNG plots.
      fonts-dejavu-core
      # The C example engine (examples/c/, tools/c-example.sh): the system C compiler.
      gcc libc6-dev
      # The C++ example engine (examples/cpp/, tools/cpp-example.sh): built with CMake
      # against the installed C library (tools/install-c.sh).
      g++ cmake
      # The Python module (python/): a virtual environment to build and test it in
      # (maturin, numpy, pytest and nibabel come from PyPI into it).
      python3 python3-venv python3-pip
      # The notebook view's browser test (python/tests/test_notebook_browser.py):
      # headless Chromium, driven by Selenium through chromedriver.
      chromium chromium-driver)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}" >&2
  sudo_cmd=()
  [ "$(id -u)" -ne 0 ] && sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
