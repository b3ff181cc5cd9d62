#!/usr/bin/env bash
# Prints a directory holding a complete static shaderc (libshaderc_combined.a with
# glslang and SPIRV-Tools inside) for the shaderc crate to link, made from Debian's
# packages; prints nothing where those are missing (then the shaderc crate finds the
# system's own library, or builds shaderc from source).
#
# Why: Debian 12's libshaderc.so.1 (2023.2) leaves glslang's symbols undefined and its
# libshaderc_combined.a does not contain them, so neither links alone. glslang-dev and
# spirv-tools ship the missing static libraries; joined into one archive, the shaderc
# crate links it as it links any complete shaderc (SHADERC_LIB_DIR, which tools/env.sh
# exports). Fast (ar, about a second); redone only when a system library is newer.
set -euo pipefail
sys=/usr/lib/$(uname -m)-linux-gnu
parts=(shaderc_combined glslang SPIRV MachineIndependent GenericCodeGen OSDependent
       OGLCompiler SPIRV-Tools-opt SPIRV-Tools)
for part in "${parts[@]}"; do
  [ -f "$sys/lib$part.a" ] || exit 0
done
out=${1:?usage: tools/shaderc-lib.sh DIR}
archive=$out/libshaderc_combined.a
fresh=1
[ -f "$archive" ] || fresh=0
for part in "${parts[@]}"; do
  [ "$fresh" = 1 ] && [ "$sys/lib$part.a" -nt "$archive" ] && fresh=0
done
if [ "$fresh" = 0 ]; then
  mkdir -p "$out"
  script="create $archive.tmp"
  for part in "${parts[@]}"; do script+=$'\n'"addlib $sys/lib$part.a"; done
  script+=$'\nsave\nend'
  rm -f "$archive.tmp"
  ar -M <<<"$script"
  mv "$archive.tmp" "$archive"
fi
echo "$out"
