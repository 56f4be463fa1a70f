#!/usr/bin/env bash
# Builds a relocatable Release bundle of `cumulo` that runs `cumulo bench` and `cumulo run --headless` on
# any x86-64 Linux machine with a Vulkan driver and none of our Debian packages (no network needed):
#
#   DIR/cumulo              launcher: sets LD_LIBRARY_PATH, CUMULO_ROOT (and CUMULO_CACHE_DIR if unset)
#   DIR/bin/cumulo          the stripped executable (no tests; VDB import left out)
#   DIR/lib/                every shared library it needs except glibc's and the Vulkan driver
#                           (the Vulkan loader, GLFW and X11 client libraries, libstdc++, zstd, ...)
#   DIR/shaders/            GLSL sources (compiled at run time by the built-in glslang)
#   DIR/content/            the sample level (terrain, cloudscape recipe; baked on first use into the cache),
#                           the weather states, the atmosphere preset and the schemas
#   DIR/README.txt          how to run it, and how to point the loader at a driver
#   DIR/device-bench.sh     the bench at 960x540 and 1920x1080 in one command (JSON + tables)
#
# Usage: scripts/bundle.sh [DIR]   (default out/bundle; the build goes to build-bundle/)
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
DIR=${1:-out/bundle}
BUILD=${CUMULO_BUNDLE_BUILD_DIR:-build-bundle}
scripts/deps.sh
launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$(dirname "$PWD")} CCACHE_NOHASHDIR=${CCACHE_NOHASHDIR:-1}
fi
cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCUMULO_BUILD_TESTS=OFF -DCUMULO_BUILD_FUZZ=OFF \
  -DCUMULO_WITH_OPENVDB=OFF "${launcher[@]}" >/dev/null
cmake --build "$BUILD" -j "$(nproc)" --target cumulo cumulo_shaders

rm -rf "$DIR"
mkdir -p "$DIR/bin" "$DIR/lib" "$DIR/content/levels"
cp "$BUILD/cumulo" "$DIR/bin/cumulo"
strip --strip-all "$DIR/bin/cumulo"

# Shared libraries: everything ldd resolves except the C library family (the target has its own, and
# mixing them breaks) and the Vulkan driver (the target's; the loader finds it through its ICD file).
ldd "$BUILD/cumulo" | awk '/=> \// {print $3}' | while read -r lib; do
  case "$(basename "$lib")" in
    libc.so*|libm.so*|libpthread.so*|libdl.so*|librt.so*|ld-linux*|libresolv.so*|libutil.so*) continue ;;
  esac
  cp -L "$lib" "$DIR/lib/"
done

cp -r shaders "$DIR/shaders"
cp -r content/levels/sample "$DIR/content/levels/sample"
cp -r content/schemas "$DIR/content/schemas"
cp -r content/weather "$DIR/content/weather"
cp -r content/atmosphere "$DIR/content/atmosphere"
cp content/README.md "$DIR/content/README.md"
cp scripts/device-bench.sh "$DIR/device-bench.sh"

cat > "$DIR/cumulo" <<'LAUNCH'
#!/bin/sh
# cumulo bundle launcher: the bundled libraries first, the bundle as the source root, a cache beside it.
here=$(cd "$(dirname "$0")" && pwd)
export LD_LIBRARY_PATH="$here/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export CUMULO_ROOT="$here"
export CUMULO_CACHE_DIR="${CUMULO_CACHE_DIR:-$here/cache}"
exec "$here/bin/cumulo" "$@"
LAUNCH
chmod +x "$DIR/cumulo"

cat > "$DIR/README.txt" <<'TXT'
cumulo bundle: a relocatable Release build (no tests, no VDB import) with its shared libraries.

Run (from anywhere; the bundle can be moved):
  ./cumulo bench --size 960x540 --out bench.json          # the cloud cost table (markdown + JSON)
  ./cumulo run content/levels/sample/level.json --headless --size 960x540 --frames 30 \
      --camera immersed --mode 60 --screenshot immersed.png --stats stats.json

The first run bakes the sample cloudscape and the voxel noise into ./cache (CUMULO_CACHE_DIR moves it);
later runs reuse them.

Vulkan: the bundle carries the Vulkan loader (lib/libvulkan.so.1) but no driver. The loader finds the
machine's driver through its ICD manifest (/usr/share/vulkan/icd.d, /etc/vulkan/icd.d). When the driver
is installed elsewhere, name its manifest:
  VK_DRIVER_FILES=/path/to/nvidia_icd.json ./cumulo bench ...     (loader >= 1.3.234)
  VK_ICD_FILENAMES=/path/to/nvidia_icd.json ./cumulo bench ...    (older loaders; both may be set)
CUMULO_DEVICE=<index or name part> picks the device when there are several.

The GPU bench in one command (960x540 and 1920x1080, every camera, JSON + tables into OUT):
  ./device-bench.sh OUT          (it offers the usual ICD folders and NVIDIA's container folder to the loader)
TXT

size=$(du -sm "$DIR" | cut -f1)
echo "cumulo: bundle in $DIR (${size} MB): $(ls "$DIR/lib" | wc -l) libraries"
if [ "$size" -gt 40 ]; then
  echo "cumulo: the bundle is over 40 MB" >&2
  exit 1
fi
