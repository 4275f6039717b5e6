#!/usr/bin/env bash
# The h5py examples of docs/hdf5-format.md, run against a superelement condense just wrote: the format
# document and the files agree, read by an independent HDF5 reader (h5py).
# usage: check_h5py_snippet.sh CONDENSE SOURCE_DIR WORK_DIR
set -euo pipefail
condense="$1"; source_dir="$2"; work="$3"
rm -rf "$work" && mkdir -p "$work" && cd "$work"
# --band: the file also holds /reduction_error, which one of the examples reads.
"$condense" "$source_dir/testdata/crankshaft.toml" -o crankshaft.h5 -q --band 3000
awk '/```python/{p=1;n++;next} /```/{p=0} p{print > ("snippet" n ".py")}' "$source_dir/docs/hdf5-format.md"
ls snippet*.py > /dev/null 2>&1 || { echo "no python example found in docs/hdf5-format.md"; exit 1; }
for snippet in snippet*.py; do
  /usr/bin/python3 "$snippet"
  echo "docs/hdf5-format.md example $snippet: ok"
done
