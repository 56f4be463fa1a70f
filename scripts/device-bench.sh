#!/usr/bin/env bash
# The GPU bench in one command: `cumulo bench` at 960x540 and 1920x1080 on whatever Vulkan device the
# machine has, from a bundle made by scripts/bundle.sh (no packages, no network, no repository needed).
#
#   DIR/device-bench.sh [OUT_DIR]     from a bundle (bundle.sh copies this script into it)
#   scripts/device-bench.sh [OUT_DIR] from the repository: uses $CUMULO_BUNDLE, else out/bundle
#
# Writes OUT_DIR (default: ./device-bench) /
#   <device>.json   {"device", "sizes": {"960x540": <bench JSON>, "1920x1080": <bench JSON>}}: every run's
#                   medians and every round's figures, as `cumulo bench --out` writes them
#   <device>.md     the bench tables of both sizes
#   <device>_<size>.log  each bench's progress lines
# where <device> is the Vulkan device's name in lower case, non-alphanumerics as '-'. Copy the JSON to
# docs/bench/<device>.json to record it.
#
# Environment: CUMULO_DEVICE_BENCH_SIZES (default "960x540 1920x1080"), CUMULO_DEVICE_BENCH_VIEWS (default
# every camera of the sample level), CUMULO_DEVICE_BENCH_FRAMES / _WARMUP / _ROUNDS (default 8 / 4 / 3: each
# round's figure a median of 8 frames), CUMULO_DEVICE (pick a device by index or name part), and the
# Vulkan loader's VK_DRIVER_FILES. When no driver is named, the ICD manifests in the usual folders and in
# NVIDIA's container folder (/usr/local/nvidia/share/vulkan/icd.d) are offered to the loader, lavapipe last.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
if [ -x "$here/bin/cumulo" ] && [ -x "$here/cumulo" ]; then
  bundle=$here
else
  bundle=${CUMULO_BUNDLE:-$here/../out/bundle}
fi
if [ ! -x "$bundle/cumulo" ]; then
  echo "device-bench: no bundle at $bundle (make one with scripts/bundle.sh, or set CUMULO_BUNDLE)" >&2
  exit 2
fi
bundle=$(cd "$bundle" && pwd)
out=${1:-$PWD/device-bench}
mkdir -p "$out"
out=$(cd "$out" && pwd)

sizes=${CUMULO_DEVICE_BENCH_SIZES:-"960x540 1920x1080"}
views=${CUMULO_DEVICE_BENCH_VIEWS:-ground,mixed,immersed,stormbird,lair,shafts,overview}
frames=${CUMULO_DEVICE_BENCH_FRAMES:-8}
warmup=${CUMULO_DEVICE_BENCH_WARMUP:-4}
rounds=${CUMULO_DEVICE_BENCH_ROUNDS:-3}

# The driver: a container's NVIDIA driver sits outside the loader's search path; offer every manifest
# found, hardware first, so the loader enumerates them all and cumulo picks the discrete GPU.
if [ -z "${VK_DRIVER_FILES:-}${VK_ICD_FILENAMES:-}" ]; then
  hw=() sw=()
  for d in /usr/local/nvidia/share/vulkan/icd.d /etc/vulkan/icd.d /usr/local/share/vulkan/icd.d /usr/share/vulkan/icd.d; do
    for f in "$d"/*.json; do
      [ -f "$f" ] || continue
      case "$(basename "$f")" in
        lvp_icd*) sw+=("$f") ;;
        *) hw+=("$f") ;;
      esac
    done
  done
  all=("${hw[@]}" "${sw[@]}")
  if [ ${#all[@]} -gt 0 ]; then
    VK_DRIVER_FILES=$(IFS=:; echo "${all[*]}")
    export VK_DRIVER_FILES VK_ICD_FILENAMES=$VK_DRIVER_FILES
    echo "device-bench: Vulkan drivers offered: $VK_DRIVER_FILES"
  else
    echo "device-bench: no ICD manifest found; the loader's own search decides" >&2
  fi
fi

# The name of JSON field "name" in the first "device" object of a bench JSON (no jq or python needed).
device_name() { sed -n '/"device"/,/}/s/.*"name": *"\([^"]*\)".*/\1/p' "$1" | head -1; }

results=()
for size in $sizes; do
  json="$out/bench_$size.json"
  echo "device-bench: $size, views $views, $frames frames x $rounds rounds after $warmup warm-up frames"
  start=$(date +%s)
  if ! "$bundle/cumulo" bench --size "$size" --views "$views" --frames "$frames" --warmup "$warmup" --rounds "$rounds" \
      --out "$json" >"$out/bench_$size.md" 2>"$out/bench_$size.log"; then
    echo "device-bench: the bench at $size failed; its last lines:" >&2
    tail -n 20 "$out/bench_$size.log" >&2
    exit 1
  fi
  echo "device-bench: $size done in $(( $(date +%s) - start )) s"
  results+=("$size")
done

name=$(device_name "$out/bench_${results[0]}.json")
slug=$(printf '%s' "${name:-unknown}" | tr 'A-Z' 'a-z' | sed 's/[^a-z0-9]\{1,\}/-/g; s/^-//; s/-$//')
{
  printf '{\n  "device_bench": {"sizes": "%s", "views": "%s", "frames": %s, "warmup": %s, "rounds": %s},\n' \
    "$sizes" "$views" "$frames" "$warmup" "$rounds"
  printf '  "sizes": {\n'
  for i in "${!results[@]}"; do
    printf '    "%s": ' "${results[$i]}"
    cat "$out/bench_${results[$i]}.json"
    [ "$i" -lt $(( ${#results[@]} - 1 )) ] && printf ',\n'
  done
  printf '  }\n}\n'
} >"$out/$slug.json"
{
  echo "# cumulo device bench: $name"
  echo
  for size in "${results[@]}"; do
    echo "## $size"
    echo
    cat "$out/bench_$size.md"
    echo
  done
} >"$out/$slug.md"
for size in "${results[@]}"; do
  mv "$out/bench_$size.log" "$out/${slug}_$size.log"
  rm -f "$out/bench_$size.json" "$out/bench_$size.md"
done
echo "device-bench: wrote $out/$slug.json and $out/$slug.md ($name)"
