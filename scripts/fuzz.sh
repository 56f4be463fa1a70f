#!/usr/bin/env bash
# Long fuzz campaign: runs every libFuzzer target for SECONDS (default 300) each, one after the other,
# with a random seed (CTest runs them briefly with a fixed seed), after replaying its regressions
# (tests/fuzz/seeds/<NAME>/, every input that ever crashed it). Corpora grow across campaigns in
# build/fuzz-campaign/<NAME>/corpus; an input that crashes, hangs or leaks is written to
# build/fuzz-campaign/<NAME>/artifacts/ and the script exits non-zero. Copy such a file into
# tests/fuzz/seeds/<NAME>/ (named after what it found) when fixing it, so CTest keeps checking it.
#
#   scripts/fuzz.sh            # 300 s per fuzzer
#   scripts/fuzz.sh 60 gltf_fuzz level_fuzz   # 60 s, only these
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_EACH=${1:-300}
shift || true
BUILD_DIR=${CUMULO_BUILD_DIR:-build}
[ -d "$BUILD_DIR/fuzz" ] || scripts/build.sh
# Volume and TGA seeds are written by the real writers (the CTest fixture fuzz_seeds).
ctest --test-dir "$BUILD_DIR" -R '^fuzz_seeds$' >/dev/null

names=("$@")
if [ ${#names[@]} -eq 0 ]; then
  for f in "$BUILD_DIR"/fuzz/*/seed_dirs.txt; do names+=("$(basename "$(dirname "$f")")"); done
fi

failed=0
for name in "${names[@]}"; do
  exe="$BUILD_DIR/fuzz/$name/$name"
  if [ ! -x "$exe" ]; then
    echo "$name: not built ($exe missing)" >&2
    failed=1
    continue
  fi
  work="$BUILD_DIR/fuzz-campaign/$name"
  mkdir -p "$work/corpus" "$work/artifacts"
  seeds=()
  while IFS= read -r d; do [ -n "$d" ] && [ -d "$d" ] && seeds+=("$d"); done <"$BUILD_DIR/fuzz/$name/seed_dirs.txt"
  regressions="tests/fuzz/seeds/$name"
  if [ -d "$regressions" ] && ! "$exe" -timeout=10 -rss_limit_mb=2048 "$regressions"/* >"$work/regressions.log" 2>&1; then
    failed=1
    echo "$name: FAILED on a regression seed; log $work/regressions.log"
    continue
  fi
  seed=$(od -An -N4 -tu4 /dev/urandom | tr -d ' ')
  log="$work/last_run.log"
  start=$(date +%s)
  set +e
  # -seed=N with N random; corpus first (libFuzzer writes new inputs there), then the read-only seeds.
  "$exe" -seed="$seed" -max_total_time="$SECONDS_EACH" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$work/artifacts/" "$work/corpus" "${seeds[@]}" >"$log" 2>&1
  rc=$?
  set -e
  took=$(($(date +%s) - start))
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  if [ $rc -eq 0 ]; then
    echo "$name: clean, $took s, $runs runs, seed $seed"
  else
    failed=1
    echo "$name: FAILED (exit $rc) after $took s, seed $seed; log $log"
    grep -E '^(==[0-9]+==ERROR|SUMMARY|.*runtime error|artifact_prefix|Test unit written)' "$log" | head -5 | sed 's/^/  /'
  fi
done
exit $failed
