#!/bin/bash
# solve before and after issue 12 (analytic Jacobians, preallocated workspaces, the element registry), side by
# side in one run, on the two scenes the issue names:
#   1. the compressor demo's solve (out/compressor/compressor.toml: 4 flexible bodies, 30 revolutions), both
#      versions on the demo's scene at the same tolerances (the old one without the integrator key
#      jacobian_cj_change, which it does not know); first-order spring-top accelerations compared
#      (postproc stats --harmonics 1, as the demo does): amplitude and phase of each of the 12 channels;
#   2. the crankshaft on 5 finite Reynolds bearings (testdata/scenes/bearing_crankshaft.toml, 2 cycles) and
#      its short-bearing variant: CPU per revolution and the journal orbits' distance (in units of the
#      clearance, 30 um) over the second cycle.
#
#   bash bench/run_solve_speedup.sh [BUILD_DIR] [BASE_REF]     (defaults: build, eebfba9)
#   BASE_BUILD=/path/to/a/build/of/eebfba9 bash bench/run_solve_speedup.sh    (reuse a build of the base)
#
# BASE_REF is the commit before issue 12's work (eebfba9, 2026-11-23). The script checks it out in a git
# worktree under $OUT/base/src and builds its solve in $OUT/base/build (Release, ccache when installed; the
# first time about 10 minutes on 2 cores), builds this tree's solve, condense and postproc in BUILD_DIR, makes
# the demo's inputs (make -f Makefile.workflow), then times every run as a process (user + sys CPU of the
# child), the compressor runs REPEAT times (default 2), the least kept. Results: $OUT/speedup.txt and the
# results files in $OUT (default OUT=out/bench/speedup).
set -euo pipefail
BUILD=$(realpath -m "${1:-build}")
BASE_REF=${2:-eebfba9}
OUT=$(realpath -m "${OUT:-out/bench/speedup}")
REPEAT=${REPEAT:-2}
JOBS=${JOBS:-2}
cd "$(dirname "$0")/.."
ROOT=$(pwd)
PY=/usr/bin/python3
mkdir -p "$OUT"

echo "== building this tree's tools in $BUILD"
cmake --build "$BUILD" --target solve condense postproc -j "$JOBS" > "$OUT/build.log" 2>&1 ||
  { echo "build failed: see $OUT/build.log"; exit 1; }

if [ -n "${BASE_BUILD:-}" ]; then
  echo "== solve before: the build of $BASE_REF in $BASE_BUILD (BASE_BUILD given)"
else
  BASE_BUILD=$OUT/base/build
  echo "== building solve at $BASE_REF in $OUT/base"
  [ -d "$OUT/base/src" ] || git worktree add --detach "$OUT/base/src" "$BASE_REF" > /dev/null
  LAUNCHER=$(command -v ccache > /dev/null && echo "-DCMAKE_CXX_COMPILER_LAUNCHER=ccache" || true)
  if [ ! -f "$BASE_BUILD/CMakeCache.txt" ]; then
    cmake -S "$OUT/base/src" -B "$BASE_BUILD" -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF $LAUNCHER \
      > "$OUT/base-build.log" 2>&1 || { echo "configure failed: see $OUT/base-build.log"; exit 1; }
  fi
  cmake --build "$BASE_BUILD" --target solve -j "$JOBS" >> "$OUT/base-build.log" 2>&1 ||
    { echo "build failed: see $OUT/base-build.log"; exit 1; }
fi
OLD=$BASE_BUILD/solve/solve
NEW=$BUILD/solve/solve

echo "== the demo's inputs"
DEMO=out/compressor
CSV=$(for f in testdata/compressor/*.csv; do echo "$DEMO/$(basename "$f")"; done)
make -f Makefile.workflow OUT=out BUILD_DIR="$BUILD" $DEMO/compressor.toml $DEMO/spring.h5 $DEMO/pipe.h5 $DEMO/shell.h5 \
  $CSV > "$OUT/inputs.log" 2>&1 || { echo "making the demo's inputs failed: see $OUT/inputs.log"; exit 1; }
mkdir -p "$OUT/compressor"
cp $DEMO/compressor.toml $DEMO/*.h5 $DEMO/*.csv "$OUT/compressor/" 2> /dev/null || true
# The demo's scene as the old solve can read it: without the integrator keys added since (same tolerances).
grep -v '^jacobian_cj_change' "$OUT/compressor/compressor.toml" > "$OUT/compressor/compressor_base.toml"
rm -f "$OUT/compressor/"*.results.h5 "$OUT/compressor/compressor.harmonics.h5"

# timed LABEL COMMAND...: runs it, its output to $OUT/LABEL.log, and appends "LABEL cpu_s" (user + sys of the
# child, bash's time) to $OUT/times.txt
TIMES=$OUT/times.txt
: > "$TIMES"
timed() {
  local label=$1
  shift
  { TIMEFORMAT='%U %S'; time "$@" > "$OUT/$label.log" 2>&1; } 2> "$OUT/$label.time" ||
    { echo "$label failed: see $OUT/$label.log"; exit 1; }
  awk -v l="$label" '{printf "%s %.3f\n", l, $1 + $2}' "$OUT/$label.time" >> "$TIMES"
}

echo "== compressor: $REPEAT runs each (about 20 s each before, 5 s after)"
for r in $(seq "$REPEAT"); do
  (cd "$OUT/compressor" && timed "compressor_old_$r" "$OLD" compressor_base.toml -o old.results.h5 --progress none -q)
  (cd "$OUT/compressor" && timed "compressor_new_$r" "$NEW" compressor.toml -o new.results.h5 --progress none -q)
done

echo "== crankshaft on 5 bearings: finite and short, 2 cycles (about 90 s finite before)"
mkdir -p "$OUT/bearing"
cp testdata/scenes/bearing_crankshaft.toml "$OUT/bearing/finite.toml"
sed 's/model = "finite"/model = "short"/' testdata/scenes/bearing_crankshaft.toml > "$OUT/bearing/short.toml"
for model in short finite; do
  for v in old new; do
    exe=$OLD
    [ $v = new ] && exe=$NEW
    (cd "$OUT/bearing" && timed "bearing_${model}_$v" "$exe" $model.toml -o ${model}_$v.results.h5 --progress none -q)
  done
done

echo "== harmonics of the spring tops (postproc stats, as the demo)"
for v in old new; do
  ARGS=()
  for k in 1 2 3 4; do
    for c in x y z; do ARGS+=("top${k}_$c=$OUT/compressor/$v.results.h5:/markers/unit.top$k/acceleration[$c]"); done
  done
  "$BUILD/postproc/postproc" stats "${ARGS[@]}" --harmonics 1 --cycle 360 --skip-cycles 10 \
    -o "$OUT/compressor/$v.harmonics.h5" -q
done

$PY bench/compare_solve_speedup.py "$OUT" | tee "$OUT/speedup.txt"
