#!/usr/bin/env bash
# Run bench_condense_beam (exporting its matrices) and the SciPy peer on the same problem; print both.
#
# usage: bench/run_condense_bench.sh [BUILD_DIR] [bench_condense_beam options...]
#   BUILD_DIR: the CMake build directory (default: $BUILD_DIR, else build-bench, else build, next to
#   bench/). Environment: EXPORT_DIR (default: a temporary directory, removed afterwards), PYTHON
#   (default: the first python3 that imports scipy).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
if [[ $# -gt 0 && "$1" != -* ]]; then
  build_dir="$1"
  shift
elif [[ -n "${BUILD_DIR:-}" ]]; then
  build_dir="$BUILD_DIR"
elif [[ -x "$here/../build-bench/bench/bench_condense_beam" ]]; then
  build_dir="$here/../build-bench"
else
  build_dir="$here/../build"
fi
bench="$build_dir/bench/bench_condense_beam"
if [[ ! -x "$bench" ]]; then
  echo "run_condense_bench.sh: $bench not found; build it first:" >&2
  echo "  cmake -S $here/.. -B $build_dir -DCMAKE_BUILD_TYPE=Release && cmake --build $build_dir --target bench_condense_beam" >&2
  exit 2
fi

python="${PYTHON:-}"
if [[ -z "$python" ]]; then
  for candidate in python3 /usr/bin/python3; do
    if command -v "$candidate" >/dev/null && "$candidate" -c "import scipy" 2>/dev/null; then
      python="$candidate"
      break
    fi
  done
fi
if [[ -z "$python" ]]; then
  echo "run_condense_bench.sh: no python3 with scipy found (set PYTHON=...)" >&2
  exit 2
fi

if [[ -n "${EXPORT_DIR:-}" ]]; then
  export_dir="$EXPORT_DIR"
else
  export_dir="$(mktemp -d "${TMPDIR:-/tmp}/condense_bench.XXXXXX")"
  trap 'rm -rf "$export_dir"' EXIT
fi

echo "== ours: $bench $* --export $export_dir"
"$bench" "$@" --export "$export_dir"
echo
echo "== peer: $python $here/peer_scipy_eigsh.py $export_dir"
"$python" "$here/peer_scipy_eigsh.py" "$export_dir"
