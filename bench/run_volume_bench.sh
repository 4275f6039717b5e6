#!/usr/bin/env bash
# condense against CalculiX (ccx 2.20, one thread) on the same TET10 mesh, first 30 modes: wall time and peak
# memory of both, their ratio, and the largest frequency difference; over several mesh sizes. Two geometries
# (GEOMETRY): "engine" (default), the generic engine block of testdata/engine_block.geo, cast iron, clamped at
# its 4 mount pads (the last default size, 11.5 mm, is the ~250k-DOF case of issue 3); "plain", issue 17's
# second geometry, a plain steel block 400 x 200 x 100 mm fixed on one end face (bench/plain_block.geo; the
# last default size, 9 mm, gives 237k DOF). Prints a table; see bench/README.md.
#
# usage: [GEOMETRY=engine|plain] bench/run_volume_bench.sh [BUILD_DIR] [SIZE_M ...]
#   BUILD_DIR: CMake build directory with condense and bench_volume_mesh (default: $BUILD_DIR, else
#   build-vol, else build). Sizes default to 0.020 0.015 0.0115 (engine), 0.016 0.012 0.009 (plain).
#   Environment: WORK_DIR (default: a temporary directory, removed afterwards), NO_CCX=1 to run condense
#   only, ORDERING (condense --ordering, default auto), EIGENSOLVER (condense --eigensolver, default block-lanczos;
#   lobpcg: the iterative solve without a factor of K, docs/component-format.md).
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
geometry="${GEOMETRY:-engine}"
case "$geometry" in
  engine)
    geo="$root/testdata/engine_block.geo"
    [[ ${#sizes[@]} -gt 0 ]] || sizes=(0.020 0.015 0.0115)
    material=(cast_iron 110e9 0.26 7200.0) ccx_e="110000000000." fixed=(MOUNT1 MOUNT2 MOUNT3 MOUNT4) ;;
  plain)
    geo="$here/plain_block.geo"
    [[ ${#sizes[@]} -gt 0 ]] || sizes=(0.016 0.012 0.009)
    material=(steel 210e9 0.3 7850.0) ccx_e="210000000000." fixed=(FIXED) ;;
  *) echo "run_volume_bench.sh: GEOMETRY must be engine or plain, got '$geometry'" >&2; exit 2 ;;
esac
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

echo "geometry: $geometry ($geo); condense --eigensolver ${EIGENSOLVER:-block-lanczos}; host: $(nproc) cores, load average now: $(cut -d' ' -f1-3 /proc/loadavg)"
# Times are CPU seconds (user + sys): on a machine shared with other work the wall time measures the
# load as much as the program; both tools run one thread here. Wall times are in the logs.
printf "%-8s %8s %8s | %9s %9s | %9s %9s | %7s %7s | %9s\n" "size_m" "nodes" "DOF" "condense_s" "cond_MiB" \
  "ccx_s" "ccx_MiB" "t_ratio" "m_ratio" "max_df"
for h in "${sizes[@]}"; do
  dir="$work/h$h"
  mkdir -p "$dir"
  counts=$("$mesher" "$geo" "$h" "$dir/block.inp")
  nodes=$(echo "$counts" | awk '{print $1}')
  dofs=$(echo "$counts" | awk '{print $5}')
  {
    cat <<TOML
[component]
name = "${geometry}_block_clamped"
kind = "volume"
[material.${material[0]}]
E = ${material[1]}
nu = ${material[2]}
rho = ${material[3]}
[volume]
mesh = "block.inp"
material = "${material[0]}"
mass_quadrature = "stiffness"   # as CalculiX integrates the C3D10 mass: same matrices
[reduction]
method = "modal"
modes = 30
TOML
    for set in "${fixed[@]}"; do printf '[[fix]]\nsurface = "%s"\ndofs = "x y z"\n' "$set"; done
  } > "$dir/block.toml"
  OMP_NUM_THREADS=1 /usr/bin/time -f "%e %U %S %M" -o "$dir/condense.time" "$condense" "$dir/block.toml" -o "$dir/block.h5" -v \
    --ordering "${ORDERING:-auto}" --eigensolver "${EIGENSOLVER:-block-lanczos}" > "$dir/condense.log" 2>&1
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
    {
      cat <<INP
*INCLUDE, INPUT=block.inp
*MATERIAL, NAME=${material[0]^^}
*ELASTIC
$ccx_e, ${material[2]}
*DENSITY
${material[3]}
*SOLID SECTION, ELSET=BLOCK, MATERIAL=${material[0]^^}
*BOUNDARY
INP
      for set in "${fixed[@]}"; do echo "$set, 1, 3"; done
      printf '*STEP\n*FREQUENCY\n30\n*END STEP\n'
    } > "$dir/job.inp"
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
