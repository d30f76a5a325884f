#!/usr/bin/env bash
# Run the fuzz targets built in BUILD (default build-fuzz) for SECONDS each (default 60), from a
# seed corpus made now from models/ and tests/models/ (no copy is kept in the repository), and
# print each target's executions and findings. Exit 1 if any target found something: the input
# is left as BUILD/fuzz/findings/<target>/crash-*; save it under tests/hostile/fuzz/<target>/ so
# that the replay test keeps it fixed.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build-fuzz}
SECONDS_PER_TARGET=${FUZZ_SECONDS:-60}
out="$BUILD/fuzz"
status=0

# seeds: every model as it is for fuzz_mjcf; for fuzz_engine, a few byte strings per model (the
# first byte picks the model, the second the integrator and steps, then values from the menu)
rm -rf "$out/seeds"
mkdir -p "$out/seeds/fuzz_mjcf" "$out/seeds/fuzz_engine" "$out/corpus/fuzz_mjcf" \
  "$out/corpus/fuzz_engine" "$out/findings/fuzz_mjcf" "$out/findings/fuzz_engine"
cp models/*.xml tests/models/*.xml "$out/seeds/fuzz_mjcf/"
# the contact scenes: pairs, exclusions, margins, every geom type that collides
for f in tests/diff/contact_scenes/*.xml; do cp "$f" "$out/seeds/fuzz_mjcf/contact-scene-$(basename "$f")"; done
[ -d tests/hostile/fuzz/fuzz_mjcf ] && cp tests/hostile/fuzz/fuzz_mjcf/* "$out/seeds/fuzz_mjcf/" 2>/dev/null || true
[ -d tests/hostile/fuzz/fuzz_engine ] && cp tests/hostile/fuzz/fuzz_engine/* "$out/seeds/fuzz_engine/" 2>/dev/null || true
n=$(ls models/*.xml tests/models/*.xml | wc -l)
for ((m = 0; m < n; m++)); do
  for flags in 0 1 3 7 66; do
    # model m; ordinary values (menu 12..15 with a small number), then NaN, inf, huge, denormal
    printf "\\x$(printf %02x $m)\\x$(printf %02x $flags)\\x0c\\x08\\x0d\\xf0\\x00\\x01\\x03\\x05\\x07\\x0a\\x0c\\x10" \
      > "$out/seeds/fuzz_engine/model$m-flags$flags"
  done
done

run() {
  local target=$1
  shift
  local log="$out/$target.log"
  echo "fuzz: $target for ${SECONDS_PER_TARGET} s (corpus $out/corpus/$target, seeds $(ls "$out/seeds/$target" | wc -l))"
  set +e
  "$BUILD/fuzz/$target" "$out/corpus/$target" "$out/seeds/$target" \
    -max_total_time="$SECONDS_PER_TARGET" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1024 \
    -max_len=65536 -print_final_stats=1 -artifact_prefix="$out/findings/$target/" "$@" > "$log" 2>&1
  local rc=$?
  set -e
  local runs
  runs=$(grep -E "^stat::number_of_executed_units" "$log" | awk '{print $2}')
  local found
  found=$(ls "$out/findings/$target" | wc -l)
  echo "fuzz: $target: ${runs:-?} executions in ${SECONDS_PER_TARGET} s, corpus $(ls "$out/corpus/$target" | wc -l) inputs, exit $rc, findings $found"
  if [ "$rc" -ne 0 ] || [ "$found" -ne 0 ]; then
    grep -E "FINDING|ERROR: |SUMMARY|runtime error" "$log" | head -20 || true
    echo "fuzz: $target: see $log and $out/findings/$target/"
    status=1
  fi
}

run fuzz_mjcf -dict="$BUILD/fuzz/mjcf.dict"
run fuzz_engine
exit $status
