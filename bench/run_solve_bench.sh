#!/bin/bash
# Work-precision of solve's integrators (error against an IDA rtol 1e-12 reference vs CPU time) on
# (a) a slider-crank with a flexible conrod and (b) a rigid slider-crank with stiff piston-liner contacts.
# Writes CSV and PNG charts to OUT (default out/bench/solve).
set -euo pipefail
BUILD=${BUILD:-build}
OUT=${1:-out/bench/solve}
mkdir -p "$OUT"
cp testdata/scenes/slider_crank_flexible.toml "$OUT/"
"$BUILD/condense/condense" testdata/conrod.toml -o "$OUT/conrod.h5" -q
[ -s "$OUT/flexible_conrod.csv" ] && [ -z "${REDO:-}" ] || \
  "$BUILD/bench/bench_solve_work_precision" "$OUT/slider_crank_flexible.toml" markers/piston.pin/position 1 "$OUT/flexible_conrod.csv"
# Stiff contacts: the reference at rtol 1e-9 with contact events (11 s of CPU), tolerances down to 1e-8, each
# sweep also without events (about 25 s in all).
"$BUILD/bench/bench_solve_work_precision" testdata/scenes/piston_slap.toml markers/piston.pin/position 0 "$OUT/piston_slap.csv" 1e-9 1e-8 events-off
/usr/bin/python3 bench/plot_work_precision.py "$OUT/flexible_conrod.csv" "$OUT/piston_slap.csv" -o "$OUT/work_precision.png"
/usr/bin/python3 bench/plot_work_precision.py "$OUT/piston_slap.csv" -o "$OUT/piston_slap.png"
echo "charts: $OUT/work_precision.png, $OUT/piston_slap.png"
