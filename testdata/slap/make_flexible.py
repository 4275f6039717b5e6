#!/usr/bin/python3
"""Writes slap_flexible.toml, level (d) of the slap family: level (b) (slap_film.toml, written by
make_scenes.py) with the film on cylinder 4's liner of the engine's flexible block instead of a rigid liner.
Run it in this directory after make_scenes.py.

The block is testdata/engine/block.toml condensed by `condense` (Craig-Bampton to 5 kHz) to block.h5 beside
this file (not in the repository: 3.8 GB and about 3 min to make):

  build/condense/condense testdata/engine/block.toml -o testdata/slap/block.h5

It is placed so that its cylinder 4 is the slap scene's cylinder: the block's frame (x along the crank axis, z up
the cylinders, cylinder 4's axis at x = 0.135 m, y = 0; thrust side +y) turned by -120 deg about (1, 1, 1)
(orientation [0.5, -0.5, -0.5, -0.5]: block x -> scene z, y -> x, z -> y) and moved by -0.135 m along the
scene's z, so that cylinder 4's axis is the scene's y axis and its thrust side the scene's +x. The block is held
at its four mount pads (fixed joints to ground; the mounts' compliance is left out: the slap's path to the
block's surface is the subject). The gas force's reaction and the crank's bearing forces go to ground as in
levels (a) - (c): the block carries the skirt's film forces only. The element's `liner` is cylinder 4's 168
liner markers (14 levels x 12 angles, testdata/engine/liner4_markers.py), clustered into their grid within
`liner_tolerance` = 4 mm (they snap to the mesh's surface nodes).
"""
import pathlib
import sys

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "engine"))
import liner4_markers  # noqa: E402

MOUNTS = [("mount1", (-0.110, 0.140, 0.015)), ("mount2", (0.110, 0.140, 0.015)),
          ("mount3", (-0.110, -0.140, 0.015)), ("mount4", (0.110, -0.140, 0.015))]


def scene_point(p):
    """A point of the block's frame in the scene's: (x, y, z) -> (y, z, x - 0.135)."""
    x, y, z = p
    return (y, z, x - 0.135)


def main():
    text = (HERE / "slap_film.toml").read_text()
    head, body = text.split("[scene]", 1)
    head = """# Piston slap, level (d): the skirt's film of level (b) on cylinder 4's liner of the flexible engine block.
#
# Written by make_flexible.py from slap_film.toml (level (b), see below); edit those, not this file. The block:
# testdata/engine/block.toml condensed to block.h5 beside this file (make_flexible.py says how), placed so that
# its cylinder 4 is this scene's cylinder and held at its mount pads; the film's pressure deforms the liner
# (168 markers on the bore) and the deformation enters the film (docs/bearing.md section 17).
#
# Level (b)'s header, for the parameters:
""" + "\n".join("#" + line[1:] if line.startswith("#") else line for line in head.splitlines()[1:]) + "\n"
    body = body.replace('name = "slap_film"', 'name = "slap_flexible"', 1)
    ground_markers = ""
    for name, p in MOUNTS:
        s = scene_point(p)
        ground_markers += f"""  [[body.marker]]
  name = "{name}"            # the block's {name} pad (axes: the block's turned into the scene)
  at = [{s[0]:.3f}, {s[1]:.3f}, {s[2]:.3f}]
  x = [0, 0, 1]
  z = [0, 1, 0]
"""
    anchor = "[[body]]\nname = \"crank\""
    block = """# ---- the engine block: flexible, Craig-Bampton (testdata/engine/block.toml), its lowest 45 coordinates as
# testdata/engine/engine_film4.toml; every interface and observation point is a marker (l4_ZZZ_AAA: the liner)
[[body]]
name = "block"
type = "flexible"
superelement = "block.h5"
modes = 45
position = [0, 0, -0.135]
orientation = [0.5, -0.5, -0.5, -0.5]
  [[body.marker]]
  name = "bore4"             # the liner frame of the film: z the cylinder axis, x the thrust side (block +y)
  point = "liner4"
  z = [0, 0, 1]
  x = [0, 1, 0]

"""
    assert anchor in body
    body = body.replace(anchor, block + anchor, 1)
    marker_anchor = "  [[body.marker]]\n  name = \"bore\""
    assert marker_anchor in body
    body = body.replace(marker_anchor, ground_markers + marker_anchor, 1)
    joints = "".join(f"""[[joint]]
name = "hold_{name}"
type = "fixed"
i = "block.{name}"
j = "ground.{name}"
""" for name, _ in MOUNTS)
    body = body.replace("[[driver]]", joints + "\n[[driver]]", 1)
    names = liner4_markers.names()
    liner = "liner = [" + ", ".join(f'"{n}"' for n in names) + "]"
    old = 'j = "ground.bore"\n'
    assert old in body
    body = body.replace(old, f"""j = "block.bore4"
# cylinder 4's liner: 14 levels x 12 angles of observation points on the bore (testdata/engine/liner4_markers.py)
{liner}
liner_tolerance = 0.004      # m: the points snap to surface nodes of the 12 mm mesh
""", 1)
    old = 'markers = ["piston.pin", "piston.skirt_top", "piston.skirt_bottom"]'
    assert old in body
    body = body.replace(old, 'markers = ["piston.pin", "piston.skirt_top", "piston.skirt_bottom", "block.jacket4_thrust", '
                             '"block.l4_150_000", "block.l4_150_180"]')
    (HERE / "slap_flexible.toml").write_text(head + "[scene]" + body)


if __name__ == "__main__":
    main()
