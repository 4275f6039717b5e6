#!/bin/bash
# Work-precision of every integrator (IDA over tolerances, generalized-alpha over steps, the body-wise split
# over macro steps) on the scenes, one chart per scene (issue 16 item 3):
#   (a) the slider-crank with the flexible Craig-Bampton conrod (testdata/conrod.toml), piston position;
#   (b) the hermetic compressor (testdata/compressor), the unit's spring-top vertical position;
#   (c) the valvetrain (testdata/valvetrain/valvetrain.toml, rigid rocker, one cam revolution), the valve's lift;
#   (d) piston slap with the lubricated skirt (testdata/slap/slap_film.toml, one 720 deg cycle), the pin's lateral
#       position;
#   (e) the car axis of the IVP test set (testdata/scenes/car_axis.toml), the left wheel's position;
#   (f) Simeon's flexible slider crank of the IVP test set (testdata/scenes/slider_crank_simeon.toml), the
#       slider's position.
# Error: max |s - s_ref| over the samples / the signal's range, the reference IDA at a tight tolerance.
# Writes CSV and PNG per scene to OUT (default out/bench/work_precision); REDO=1 reruns existing CSVs.
# Usage: bench/run_work_precision_all.sh [OUT]     (BUILD=build by default; about 15-30 min on 2 cores)
set -euo pipefail
BUILD=${BUILD:-build}
OUT=${1:-out/bench/work_precision}
BENCH="$BUILD/bench/bench_solve_work_precision"
mkdir -p "$OUT"
run() {  # name scene signal column [reference_rtol [finest_rtol]]
  local name=$1; shift
  if [ -s "$OUT/$name.csv" ] && [ -z "${REDO:-}" ]; then echo "kept $OUT/$name.csv"; else
    echo "== $name"; "$BENCH" "$@" "$OUT/$name.csv.tmp" "${REF[@]}" && mv "$OUT/$name.csv.tmp" "$OUT/$name.csv"; fi
  /usr/bin/python3 bench/plot_work_precision.py "$OUT/$name.csv" -o "$OUT/$name.png"
}
# (a) the flexible slider-crank: the conrod condensed beside a copy of the scene.
cp testdata/scenes/slider_crank_flexible.toml "$OUT/"
[ -s "$OUT/conrod.h5" ] || "$BUILD/condense/condense" testdata/conrod.toml -o "$OUT/conrod.h5" -q
REF=(1e-11 1e-10); run slider_crank_flexible "$OUT/slider_crank_flexible.toml" markers/piston.pin/position 1
# (b) the compressor: its three superelements, condensed beside a copy of the scene and its tables.
mkdir -p "$OUT/compressor"
cp testdata/compressor_shell.geo "$OUT/"   # the shell component meshes ../compressor_shell.geo
cp testdata/compressor/*.toml testdata/compressor/*.csv "$OUT/compressor/"
for c in spring pipe shell; do
  [ -s "$OUT/compressor/$c.h5" ] || "$BUILD/condense/condense" "$OUT/compressor/$c.toml" -o "$OUT/compressor/$c.h5" -q
done
REF=(1e-9 1e-8); run compressor "$OUT/compressor/compressor.toml" markers/unit.top1/position 2
# (c) the valvetrain (rigid rocker; the split at H = 1 ms did not finish in 2.7 CPU min), shortened to one cam revolution (end_angle_deg 360 instead of 760: 92 ms
#     at 650 cam rpm, the whole valve event and its seating), a copy beside its gas table; the reference IDA
#     at rtol 1e-9 (its own error: the IDA 1e-8 row against it); the chart's title says both. Column 1: the
#     valve moves along y (column 2, z, is constant: every error was NaN).
mkdir -p "$OUT/valvetrain"
cp testdata/valvetrain/exhaust_valve_gas.csv "$OUT/valvetrain/"
sed 's/^end_angle_deg = 760 .*/end_angle_deg = 360        # one cam revolution (work-precision bench)/' \
  testdata/valvetrain/valvetrain.toml > "$OUT/valvetrain/valvetrain.toml"
grep -q '^end_angle_deg = 360 ' "$OUT/valvetrain/valvetrain.toml"
REF=(1e-9 1e-8); run valvetrain_1_cam_rev_ref_1e-9 "$OUT/valvetrain/valvetrain.toml" bodies/valve/position 1
# (d) the lubricated piston slap: one 720 deg cycle at 2000 rpm (the scene as shipped), reference IDA 1e-9.
REF=(1e-9 1e-8); run slap_film_720deg_ref_1e-9 testdata/slap/slap_film.toml markers/piston.pin/position 0
# (e) the car axis.
REF=(1e-11 1e-10); run car_axis testdata/scenes/car_axis.toml bodies/left/position 1
# (f) Simeon's slider crank: its rod written beside a copy of the scene (rtol 1e-12 fails: IDA_CONV_FAIL).
cp testdata/scenes/slider_crank_simeon.toml "$OUT/"
[ -s "$OUT/simeon_rod.h5" ] || /usr/bin/python3 testdata/scenes/make_simeon_rod.py -o "$OUT/simeon_rod.h5"
REF=(1e-11 1e-10); run slider_crank_simeon "$OUT/slider_crank_simeon.toml" bodies/slider/position 0
echo "charts: $OUT/*.png"
