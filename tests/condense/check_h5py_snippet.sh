#!/usr/bin/env bash
# The h5py example of docs/hdf5-format.md, run against a superelement condense just wrote: the format
# document and the files agree, read by an independent HDF5 reader (h5py).
# usage: check_h5py_snippet.sh CONDENSE SOURCE_DIR WORK_DIR
set -euo pipefail
condense="$1"; source_dir="$2"; work="$3"
rm -rf "$work" && mkdir -p "$work" && cd "$work"
"$condense" "$source_dir/testdata/crankshaft.toml" -o crankshaft.h5 -q
awk '/```python/{p=1;next} /```/{if(p){exit}} p' "$source_dir/docs/hdf5-format.md" > snippet.py
test -s snippet.py || { echo "no python example found in docs/hdf5-format.md"; exit 1; }
/usr/bin/python3 snippet.py
echo "docs/hdf5-format.md example: ok"
