#!/usr/bin/env bash
# fuzz/run.sh [SECONDS]: builds the libFuzzer targets (clang-14, ASan + UBSan; fuzz/CMakeLists.txt)
# and runs each for SECONDS (default 60; JOBS targets side by side, default one per core) from its
# seed corpus in fuzz/corpus/<name>/, with a 2 GiB memory limit and a 10 s limit per input.
# Exits non-zero, with the crashing input saved under build-fuzz/artifacts/, when any target
# finds a crash, a leak, undefined behaviour, an allocation above the limit or a broken promise
# (see each target's header). New inputs the fuzzer finds go to build-fuzz/corpus-<name>/ (not
# committed); the seeds are never modified.
#
#   fuzz/run.sh 60                 # CI: every target, 60 s each
#   FUZZ_TARGETS=ply_mesh fuzz/run.sh 600
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
SECONDS_EACH="${1:-60}"
BUILD="${FUZZ_BUILD_DIR:-$ROOT/build-fuzz}"
TARGETS="${FUZZ_TARGETS:-scene_json obj_mesh ply_mesh serialized_mesh accumulation mitsuba_xml}"

if ! command -v clang++-14 >/dev/null; then
  echo "fuzz/run.sh: clang++-14 is missing (scripts/install-deps.sh installs clang-14 and libclang-rt-14-dev)" >&2
  exit 1
fi
LAUNCHER=()
if command -v ccache >/dev/null; then LAUNCHER=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S "$ROOT/fuzz" -B "$BUILD" -G Ninja -DCMAKE_CXX_COMPILER=clang++-14 "${LAUNCHER[@]}" >/dev/null
ninja -C "$BUILD" -j "${JOBS:-$(nproc)}" >/dev/null

mkdir -p "$BUILD/artifacts"
# run_target NAME: fuzzes one target for SECONDS_EACH; its report goes to $BUILD/NAME.report.
run_target() {
  local name="$1" seeds="$ROOT/fuzz/corpus/$1" extra=() report="$BUILD/$1.report"
  if [ "$name" = mitsuba_xml ]; then
    # Its seeds are the project's XML scenes (docs/mitsuba.md, "Fuzzing").
    seeds="$BUILD/seeds-mitsuba_xml"
    mkdir -p "$seeds"
    cp "$ROOT"/tests/data/mitsuba/*.xml "$ROOT"/tests/data/reference/cbox/mitsuba.xml "$ROOT"/scenes/*.xml \
      "$ROOT"/fuzz/corpus/mitsuba_xml/*.xml "$seeds/"
    extra=(-dict="$ROOT/fuzz/mitsuba_xml.dict")
  fi
  local work="$BUILD/corpus-$name"
  mkdir -p "$work"
  echo "== fuzz $name for ${SECONDS_EACH} s (seeds: $(ls "$seeds" | wc -l) files)" >"$report"
  if "$BUILD/${name}_fuzzer" "${extra[@]}" -max_total_time="$SECONDS_EACH" -timeout=10 \
       -rss_limit_mb=2048 -malloc_limit_mb=2048 -max_len=65536 -print_final_stats=1 \
       -artifact_prefix="$BUILD/artifacts/${name}-" "$work" "$seeds" >"$BUILD/$name.log" 2>&1; then
    { grep -E "^stat::number_of_executed_units|^stat::peak_rss_mb" "$BUILD/$name.log" | tr '\n' ' '
      echo; } >>"$report"
  else
    { echo "FAIL: ${name}_fuzzer found a problem; last lines of $BUILD/$name.log:"
      tail -n 40 "$BUILD/$name.log"; } >>"$report"
    return 1
  fi
}

# The targets run side by side, JOBS at a time (default: one per core), each single-threaded
# for SECONDS_EACH of wall time, so a run takes about ceil(targets / JOBS) x SECONDS_EACH.
status=0
pids=() names=()
for name in $TARGETS; do
  while [ "$(jobs -rp | wc -l)" -ge "${JOBS:-$(nproc)}" ]; do wait -n || true; done
  run_target "$name" &
  pids+=($!) names+=("$name")
done
for i in "${!pids[@]}"; do
  wait "${pids[$i]}" || status=1
  cat "$BUILD/${names[$i]}.report"
  if grep -q '^FAIL:' "$BUILD/${names[$i]}.report"; then status=1; fi
done
exit "$status"
