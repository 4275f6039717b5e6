#!/usr/bin/env bash
# condense export --format nastran, checked by an independent reader (check_dmig_export.py: h5py, NumPy,
# SciPy; no code of the toolchain) on the crankshaft of testdata/:
#   1. as written: orthonormalized Craig-Bampton, 100 modal coordinates (SPOINTs), damping;
#   2. raw Craig-Bampton (orthonormalize = false), 9 interfaces + one on a counterweight's rigid-link end
#      (its GRID is the link's master station), with GRID and SPOINT ids moved by the options.
# usage: check_dmig_export.sh CONDENSE SOURCE_DIR WORK_DIR   (exit 77: SciPy missing, ctest skips)
set -euo pipefail
condense="$1"; source_dir="$2"; work="$3"
check="/usr/bin/python3 $source_dir/tests/condense/check_dmig_export.py"
rm -rf "$work" && mkdir -p "$work" && cd "$work"

"$condense" "$source_dir/testdata/crankshaft.toml" -o crank.h5 -q
"$condense" export crank.h5 -o crank.pch -q
$check crank.h5 crank.pch

sed 's/^orthonormalize = true/orthonormalize = false/' "$source_dir/testdata/crankshaft.toml" > crank_raw.toml
grep -q '^orthonormalize = false' crank_raw.toml
cat >> crank_raw.toml <<'TOML'

[[interface]]  # on the rigid link of the first counterweight: its coordinates are the master station's
name = "cw1"
at = [0.022, -0.040, 0.0]
TOML
"$condense" crank_raw.toml -o crank_raw.h5 -q
"$condense" export crank_raw.h5 -o crank_raw.pch -q --first-grid 11 --first-spoint 9001 --grid pin4=501
$check crank_raw.h5 crank_raw.pch --first-grid 11 --first-spoint 9001 --grid pin4=501
echo "condense export: both decks agree with their superelement files"
