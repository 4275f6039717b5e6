#!/usr/bin/python3
"""Writes the liner markers of cylinder 4 at the end of block.toml (run it in this directory): observation
points on the bore's surface (radius 43 mm, cylinder axis x = 0.135 m, y = 0) at 14 axial levels
z = 0.080 .. 0.210 m (every 10 mm; the skirt's travel is 0.072 .. 0.198 m in testdata/slap/slap_flexible.toml:
below 0.080 m the nearest surface nodes of some angles are at 0.080 m, so the skirt's bottom 8 mm at BDC see the
lowest level's displacement) x 12 angles (every 30 deg from the thrust side +y towards +x, the piston-liner
element's theta), named l4_ZZZ_AAA (height ZZZ in mm, angle AAA in deg). The piston-liner element of testdata/slap/slap_flexible.toml
takes them as its `liner` (docs/bearing.md section 17). Each observation point snaps to the nearest node of
the mesh's outer surface (a bore node, within about half the 12 mm element size); the element clusters them
into its grid of levels x angles with `liner_tolerance`.

Replaces the block between the two marker lines below if it is there already, else appends it.
"""
import math
import pathlib

HERE = pathlib.Path(__file__).resolve().parent
BEGIN = "# ---- BEGIN liner4 markers (written by liner4_markers.py; edit there, not here)"
END = "# ---- END liner4 markers"
CX, R = 0.135, 0.043
LEVELS = [0.080 + 0.010 * k for k in range(14)]
ANGLES_DEG = [30 * b for b in range(12)]


def block():
    lines = [BEGIN,
             "# Cylinder 4's liner as 14 levels x 12 angles of observation points on the bore (radius 43 mm):",
             "# the elasto-hydrodynamic piston-liner's `liner` markers (testdata/slap/slap_flexible.toml).",
             "# theta from the thrust side +y towards +x: a point is at (0.135 + R sin theta, R cos theta, z)."]
    for deg in ANGLES_DEG:
        th = math.radians(deg)
        for z in LEVELS:
            lines += ["[[observe]]", f'name = "{name(z, deg)}"',
                      f"at = [{CX + R * math.sin(th):.6f}, {R * math.cos(th):.6f}, {z:.3f}]"]
    lines.append(END)
    return "\n".join(lines) + "\n"


def name(z, deg):
    return f"l4_{round(z * 1000):03d}_{deg:03d}"


def names():
    return ["block." + name(z, deg) for deg in ANGLES_DEG for z in LEVELS]


if __name__ == "__main__":
    path = HERE / "block.toml"
    text = path.read_text()
    if BEGIN in text:
        head, rest = text.split(BEGIN, 1)
        text = head + block() + rest.split(END + "\n", 1)[1]
    else:
        text = text.rstrip("\n") + "\n\n" + block()
    path.write_text(text)
