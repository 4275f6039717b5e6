#!/usr/bin/python3
"""Independent check of `condense export --format nastran` (docs/matrix-export.md): no code of the toolchain.

Parses the Nastran bulk data (large-field DMIG, GRID, SPOINT, by the Quick Reference Guide's card
layouts) on its own, maps the DOF back to the superelement's coordinates by the documented numbering,
and compares with the superelement file read by h5py:
  - format: lines <= 80 characters, large-field entries in whole small-field lines (an even
    number of lines), every DMIG symmetric (IFO 6) real double (TIN 2), only the upper triangle given;
  - every entry of K, M (and B) within 5e-10 relative of /reduced/* (a 16-character field holds >= 10
    significant digits), zeros zero;
  - the GRID position of an interface is the point its rotation coordinates turn about: the interface
    point moves by theta x (position - grid) per unit rotation theta (/interface/shape), to 1e-9 m;
  - the eigenfrequencies of the re-read (K, M) by scipy.linalg.eigh against /modes/frequency_hz:
    1e-9 relative for mass-orthonormal coordinates; for a raw basis (interface DOF, rigid-body modes
    contained) within the first-order bound of the rounding, eps x^T (|K| + lambda |M|) x / (2 lambda).

usage: check_dmig_export.py SUPERELEMENT.h5 EXPORT.pch [--first-grid N] [--first-spoint N] [--grid NAME=ID]...
Exit 0 pass, 1 fail, 77 skipped (SciPy missing: make -f Makefile.workflow deps installs python3-scipy).
"""
import argparse
import re
import sys

import h5py
import numpy as np

try:
    import scipy.linalg
except ImportError:
    print("check_dmig_export: SciPy is missing (Debian: python3-scipy); skipped")
    sys.exit(77)

ENTRY_RTOL = 5e-10
FREQUENCY_RTOL = 1e-9
DOF_NAMES = ["x", "y", "z", "rx", "ry", "rz"]


def nastran_real(text):
    """A Nastran real: 1.5D+3, -2.0E-7, 7.+5 (exponent without a letter), .5"""
    s = text.strip().upper().replace("D", "E")
    if "E" not in s:
        s = re.sub(r"(?<=[0-9.])([+-])", r"E\1", s)
    if "." not in s.split("E")[0]:
        raise ValueError(f"not a Nastran real (no decimal point): {text!r}")
    return float(s)


def read_deck(path):
    """Entries as (keyword, [fields 2..]) from fixed-format lines; format violations listed."""
    entries, problems = [], []
    lines_in_entry, large = 0, False

    def close():
        if entries and large and lines_in_entry % 2:
            problems.append(f"{entries[-1][0]} entry with an odd number of large-field lines")

    with open(path) as f:
        for number, line in enumerate(f, 1):
            line = line.rstrip("\n")
            if len(line) > 80:  # comments too (the test's names and paths are short)
                problems.append(f"line {number}: {len(line)} characters (at most 80)")
            if not line or line.startswith("$"):
                continue
            if not line.startswith("*"):
                close()
                keyword = line[:8].strip()
                large = keyword.endswith("*")
                entries.append((keyword.rstrip("*"), []))
                lines_in_entry = 0
            lines_in_entry += 1
            width, count = (16, 4) if large else (8, 8)
            line = line.ljust(8 + width * count)
            entries[-1][1].extend(line[8 + k * width: 8 + (k + 1) * width].strip() for k in range(count))
    close()
    return entries, problems


def parse(path):
    entries, problems = read_deck(path)
    dmig, grids, spoints = {}, {}, []
    for keyword, f in entries:
        if keyword == "DMIG":
            m = dmig.setdefault(f[0], {"ifo": None, "tin": None, "terms": {}})
            if f[1] == "0":
                m["ifo"], m["tin"] = int(f[2]), int(f[3])
                continue
            column = (int(f[1]), int(f[2] or 0))
            for k in range(4, len(f) - 3, 4):
                g, c, a, b = f[k:k + 4]
                if not g and not a:
                    continue
                if b:
                    problems.append(f"{f[0]}: imaginary part given for a real matrix")
                row = (int(g), int(c or 0))
                if (row, column) in m["terms"]:
                    problems.append(f"{f[0]}: term {row} {column} given twice")
                m["terms"][(row, column)] = nastran_real(a)
        elif keyword == "GRID":
            grids[int(f[0])] = np.array([nastran_real(x) for x in f[2:5]])
        elif keyword == "SPOINT":
            if len(f) > 2 and f[1] == "THRU":
                spoints.extend(range(int(f[0]), int(f[2]) + 1))
            else:
                spoints.extend(int(x) for x in f if x)
        else:
            problems.append(f"unexpected entry {keyword}")
    return dmig, grids, spoints, problems


def documented_dofs(coordinates, interfaces, first_grid, first_spoint, grid_ids):
    """Interface p's coordinate NAME.x..NAME.rz -> (grid, 1..6); every other coordinate -> next SPOINT."""
    dofs, spoint = [], first_spoint
    for c in coordinates:
        name, _, dof = c.rpartition(".")
        if name in interfaces and dof in DOF_NAMES:
            grid = grid_ids.get(name, first_grid + interfaces.index(name))
            dofs.append((grid, DOF_NAMES.index(dof) + 1))
        else:
            dofs.append((spoint, 0))
            spoint += 1
    return dofs


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("h5")
    ap.add_argument("pch")
    ap.add_argument("--first-grid", type=int, default=1)
    ap.add_argument("--first-spoint", type=int, default=100001)
    ap.add_argument("--grid", action="append", default=[])
    ap.add_argument("--suffix", default="AAX")
    args = ap.parse_args()
    grid_ids = {g.rpartition("=")[0]: int(g.rpartition("=")[2]) for g in args.grid}

    with h5py.File(args.h5, "r") as f:
        K0, M0, D0 = f["reduced/stiffness"][:], f["reduced/mass"][:], f["reduced/damping"][:]
        coordinates = list(f["reduced/coordinates"].asstr()[:])
        interfaces = list(f["interface/name"].asstr()[:])
        position, shape = f["interface/position"][:], f["interface/shape"][:]
        f_hz = f["modes/frequency_hz"][:]
        rigid = int(f["modes"].attrs["rigid_body_modes_contained"])
        orthonormal = int(f.attrs["orthonormalized"]) == 1

    dmig, grids, spoints, problems = parse(args.pch)
    failures = list(problems)
    dofs = documented_dofs(coordinates, interfaces, args.first_grid, args.first_spoint, grid_ids)
    index = {d: j for j, d in enumerate(dofs)}
    n = len(coordinates)

    def matrix(name):
        m = dmig[name]
        if (m["ifo"], m["tin"]) != (6, 2):
            failures.append(f"{name}: IFO {m['ifo']}, TIN {m['tin']} (expected 6, 2)")
        A = np.zeros((n, n))
        for (row, column), v in m["terms"].items():
            i, j = index[row], index[column]
            if i > j:
                failures.append(f"{name}: term below the diagonal ({row}, {column})")
            A[i, j] = A[j, i] = v
        return A

    suffix = args.suffix.upper()
    compared = [("K" + suffix, K0), ("M" + suffix, M0)]
    if np.any(D0 != 0):
        compared.append(("B" + suffix, D0))
    read = {}
    for name, exact in compared:
        if name not in dmig:
            failures.append(f"{name} missing")
            continue
        A = read[name] = matrix(name)
        nonzero = exact != 0
        err = np.max(np.abs(A[nonzero] - exact[nonzero]) / np.abs(exact[nonzero]))
        if np.any(A[~nonzero] != 0):
            failures.append(f"{name}: an entry that is zero in the .h5 is not zero")
        print(f"{name}: {np.count_nonzero(nonzero)} nonzero entries, largest relative difference {err:.2e}")
        if not err <= ENTRY_RTOL:
            failures.append(f"{name}: entries differ by {err:.2e} > {ENTRY_RTOL:g}")

    # Scalar points: the modal coordinates; grid points: the interfaces whose DOF are coordinates.
    if sorted(spoints) != sorted(d[0] for d in dofs if d[1] == 0):
        failures.append("SPOINT ids differ from the documented numbering")
    for p, name in enumerate(interfaces):
        columns = {k: coordinates.index(f"{name}.{k}") for k in DOF_NAMES if f"{name}.{k}" in coordinates}
        if not columns:
            continue
        grid = grids.get(grid_ids.get(name, args.first_grid + p))
        if grid is None:
            failures.append(f"interface {name}: no GRID entry")
            continue
        r = position[p] - grid
        for axis, k in enumerate(["rx", "ry", "rz"]):
            if k in columns:
                moved = shape[p, 0:3, columns[k]]
                expected = np.cross(np.eye(3)[axis], r)
                if np.max(np.abs(moved - expected)) > 1e-9:
                    failures.append(f"interface {name}: GRID {grid} is not the point its {k} turns about")
        print(f"interface {name}: GRID at {grid}, offset to the point {np.linalg.norm(r):.3g} m")

    if "K" + suffix in read and "M" + suffix in read:
        K, M = read["K" + suffix], read["M" + suffix]
        lam, X = scipy.linalg.eigh(K, M)
        lam, X = lam[rigid:], X[:, rigid:]
        hz = np.sqrt(np.clip(lam, 0, None)) / (2 * np.pi)
        if hz.size != f_hz.size:
            failures.append(f"{hz.size} elastic frequencies against {f_hz.size} in the .h5")
        else:
            rel = np.abs(hz - f_hz) / f_hz
            if orthonormal:
                tolerance = np.full_like(rel, FREQUENCY_RTOL)
                what = f"{FREQUENCY_RTOL:g}"
            else:
                A = np.abs(X)
                quadratic = np.einsum("ij,ij->j", A, np.abs(K) @ A) + lam * np.einsum("ij,ij->j", A, np.abs(M) @ A)
                bound = ENTRY_RTOL * quadratic / lam / 2  # relative in f: half that in lambda
                tolerance = 2 * bound
                what = f"2 x the rounding bound (largest {tolerance.max():.2e})"
            worst = int(np.argmax(rel))
            print(f"frequencies: {hz.size} elastic modes ({rigid} rigid skipped), largest relative difference "
                  f"{rel[worst]:.2e} (mode {worst + 1}, {f_hz[worst]:.6g} Hz); tolerance {what}")
            if not np.all(rel <= tolerance):
                failures.append(f"frequencies differ by up to {rel.max():.2e} beyond the tolerance")

    for failure in failures:
        print("FAIL:", failure)
    print("check_dmig_export:", "FAILED" if failures else "ok", args.pch)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
