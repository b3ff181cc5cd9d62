#!/usr/bin/env bash
# Installs the Debian packages glyphcast needs to build and to run on lavapipe,
# only where they are missing. Safe to run again.
set -euo pipefail
pkgs=(mesa-vulkan-drivers libvulkan-dev vulkan-validationlayers
      libshaderc-dev glslang-dev spirv-tools pkg-config)
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
