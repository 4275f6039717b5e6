#!/usr/bin/env bash
# condense against CalculiX (ccx 2.20, one thread) on the same TET10 mesh of the generic engine block
# (testdata/engine_block.geo), clamped at its 4 mount pads, first 30 modes: wall time and peak memory
# of both, their ratio, and the largest frequency difference; over several mesh sizes (the last one,
# 11.5 mm, is the ~250k-DOF case of issue 3). Prints a table; see bench/README.md.
#
# usage: bench/run_volume_bench.sh [BUILD_DIR] [SIZE_M ...]
#   BUILD_DIR: CMake build directory with condense and bench_volume_mesh (default: $BUILD_DIR, else
#   build-vol, else build). Sizes default to 0.020 0.015 0.0115. Environment: WORK_DIR (default: a
#   temporary directory, removed afterwards), NO_CCX=1 to run condense only, ORDERING (condense
#   --ordering, default auto).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$here/.."
if [[ $# -gt 0 && "$1" != [0-9]* ]]; then
  build_dir="$1"
  shift
elif [[ -n "${BUILD_DIR:-}" ]]; then
  build_dir="$BUILD_DIR"
elif [[ -x "$root/build-vol/condense/condense" ]]; then
  build_dir="$root/build-vol"
else
  build_dir="$root/build"
fi
sizes=("$@")
[[ ${#sizes[@]} -gt 0 ]] || sizes=(0.020 0.015 0.0115)
condense="$build_dir/condense/condense"
mesher="$build_dir/bench/bench_volume_mesh"
for exe in "$condense" "$mesher"; do
  if [[ ! -x "$exe" ]]; then
    echo "run_volume_bench.sh: $exe not found; build it first:" >&2
    echo "  cmake --build $build_dir --target condense bench_volume_mesh" >&2
    exit 2
  fi
done
run_ccx=1
if [[ -n "${NO_CCX:-}" ]] || ! command -v ccx >/dev/null; then run_ccx=0; fi

work="${WORK_DIR:-}"
if [[ -z "$work" ]]; then
  work="$(mktemp -d)"
  trap 'rm -rf "$work"' EXIT
fi
mkdir -p "$work"

# Frequencies (Hz) from ccx's .dat: the 4th column of the rows under "E I G E N V A L U E   O U T P U T".
ccx_frequencies() {
  awk '/E I G E N V A L U E   O U T P U T/ {on = 1; next} on && NF == 5 && $1 ~ /^[0-9]+$/ {print $4}
       /P A R T I C I P A T I O N/ {on = 0}' "$1"
}

echo "host: $(nproc) cores, load average now: $(cut -d' ' -f1-3 /proc/loadavg)"
# Times are CPU seconds (user + sys): on a machine shared with other work the wall time measures the
# load as much as the program; both tools run one thread here. Wall times are in the logs.
printf "%-8s %8s %8s | %9s %9s | %9s %9s | %7s %7s | %9s\n" "size_m" "nodes" "DOF" "condense_s" "cond_MiB" \
  "ccx_s" "ccx_MiB" "t_ratio" "m_ratio" "max_df"
for h in "${sizes[@]}"; do
  dir="$work/h$h"
  mkdir -p "$dir"
  counts=$("$mesher" "$root/testdata/engine_block.geo" "$h" "$dir/block.inp")
  nodes=$(echo "$counts" | awk '{print $1}')
  dofs=$(echo "$counts" | awk '{print $5}')
  cat > "$dir/block.toml" <<TOML
[component]
name = "engine_block_clamped"
kind = "volume"
[material.cast_iron]
E = 110e9
nu = 0.26
rho = 7200.0
[volume]
mesh = "block.inp"
material = "cast_iron"
mass_quadrature = "stiffness"   # as CalculiX integrates the C3D10 mass: same matrices
[[fix]]
surface = "MOUNT1"
dofs = "x y z"
[[fix]]
surface = "MOUNT2"
dofs = "x y z"
[[fix]]
surface = "MOUNT3"
dofs = "x y z"
[[fix]]
surface = "MOUNT4"
dofs = "x y z"
[reduction]
method = "modal"
modes = 30
TOML
  OMP_NUM_THREADS=1 /usr/bin/time -f "%e %U %S %M" -o "$dir/condense.time" "$condense" "$dir/block.toml" -o "$dir/block.h5" -v \
    --ordering "${ORDERING:-auto}" > "$dir/condense.log" 2>&1
  read -r c_wall c_user c_sys c_kb < "$dir/condense.time"
  c_s=$(awk -v u="$c_user" -v s="$c_sys" 'BEGIN {printf "%.1f", u + s}')
  /usr/bin/python3 -c "import h5py; print('\n'.join(str(f) for f in h5py.File('$dir/block.h5')['/modes/frequency_hz'][:]))" \
    > "$dir/condense.freq"
  # The BLAS kernels condense ran (it selects OpenBLAS's own for a CPU that OpenBLAS 0.3.21 does not know,
  # common/blas_kernels.hpp): ccx (ARPACK, LAPACK) gets the same.
  kernels=$(/usr/bin/python3 -c "import h5py; print(h5py.File('$dir/block.h5')['/model'].attrs.get('blas_kernels', ''))")
  coretype=""
  [[ "$kernels" == OpenBLAS* ]] && coretype="${kernels#OpenBLAS }"
  x_s="-"; x_kb=""; ratio="-"; mratio="-"; df="-"
  if [[ $run_ccx == 1 ]]; then
    cat > "$dir/job.inp" <<INP
*INCLUDE, INPUT=block.inp
*MATERIAL, NAME=CAST_IRON
*ELASTIC
110000000000., 0.26
*DENSITY
7200.
*SOLID SECTION, ELSET=BLOCK, MATERIAL=CAST_IRON
*BOUNDARY
MOUNT1, 1, 3
MOUNT2, 1, 3
MOUNT3, 1, 3
MOUNT4, 1, 3
*STEP
*FREQUENCY
30
*END STEP
INP
    (cd "$dir" && OMP_NUM_THREADS=1 OPENBLAS_CORETYPE="${OPENBLAS_CORETYPE:-$coretype}" \
      /usr/bin/time -f "%e %U %S %M" -o ccx.time ccx -i job > ccx.log 2>&1)
    read -r x_wall x_user x_sys x_kb < "$dir/ccx.time"
    x_s=$(awk -v u="$x_user" -v s="$x_sys" 'BEGIN {printf "%.1f", u + s}')
    ccx_frequencies "$dir/job.dat" > "$dir/ccx.freq"
    ratio=$(awk -v a="$c_s" -v b="$x_s" 'BEGIN {printf "%.3f", a / b}')
    mratio=$(awk -v a="$c_kb" -v b="$x_kb" 'BEGIN {printf "%.3f", a / b}')
    df=$(paste "$dir/condense.freq" "$dir/ccx.freq" | awk 'BEGIN {m = 0} NF == 2 {d = ($1 - $2) / $2; if (d < 0) d = -d; if (d > m) m = d} END {printf "%.1e", m}')
    x_kb=$(awk -v k="$x_kb" 'BEGIN {printf "%.0f", k / 1024}')
  fi
  printf "%-8s %8s %8s | %9s %9.0f | %9s %9s | %7s %7s | %9s\n" "$h" "$nodes" "$dofs" "$c_s" "$(awk -v k="$c_kb" 'BEGIN {print k / 1024}')" \
    "$x_s" "$x_kb" "$ratio" "$mratio" "$df"
  grep -E "stages|factor:" "$dir/condense.log" | sed 's/^/    condense /'
  echo "    wall time [s]: condense $c_wall${x_wall:+, ccx $x_wall}; BLAS: $kernels"
done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
