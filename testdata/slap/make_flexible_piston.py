#!/usr/bin/python3
"""Writes level (e) of the slap family, the flexible piston, and its rigid twin (run it in this directory after
make_scenes.py):

  piston_skirt.toml               the piston component (testdata/piston.geo, as testdata/piston.toml) with
                                  50 observation points on the skirt (5 levels x 10 angles, the
                                  film's grid); condense it to piston_skirt.h5 beside this file:
                                    build/condense/condense piston_skirt.toml -o piston_skirt.h5
                                  (about 15 s CPU, 0.7 GB)
  piston_skirt_rv.toml            the same with 6 fixed-interface modes (to 10 kHz) and the residual vectors of
                                  the 50 skirt points (6 mm patches): the skirt's static compliance exact, for
                                  the mode-count check (bench/slap_study.py --piston-residual piston_skirt_rv.h5)
  slap_flexible_piston.toml  (e)  level (b) (slap_film.toml) with the piston as that Craig-Bampton superelement:
                                  the skirt's 50 points are the film's `skirt` markers (their radial deformation
                                  enters the film, the film's pressure goes back to them), the gas force acts
                                  at the pin as in levels (a) - (d), the pin, rings and the rest of the 0.42 kg are a rigid 0.101 kg
                                  body fixed at the pin bore
  slap_piston_rigid.toml          the same piston rigid, with the superelement's mass, centre of mass and
                                  inertia (PISTON below, from piston_skirt.h5's /invariants): level (e) less the
                                  piston's deformation, so that (e) against it shows what the flexibility does

The piston's frame (piston.geo: z up the piston, the pin along y) is turned into the scene's (the cylinder +y,
the pin along z, the thrust side +x) by -90 deg about x: piston x -> scene x, z -> y, y -> -z
(orientation [0.70710678, -0.70710678, 0, 0]). Film angles run from the thrust side x_j = +x towards
w = x_j x z_j = +z of the scene, that is -y of the piston.
"""
import math
import pathlib

HERE = pathlib.Path(__file__).resolve().parent
R = 0.043
LEVELS = [0.012, 0.002, -0.008, -0.018, -0.028]  # m along the piston axis from the pin: the film's skirt
ANGLES = list(range(0, 360, 36))                 # deg, from the thrust side; 72 and 108 deg clear the pin bore's
#                                                  holes in the skirt (at 90 and 270 deg, z within +-11 mm)
PIN_Y = 0.186                                    # the pin's height at the start (TDC), scene y
# The superelement's invariants (piston_skirt.h5, /invariants; checked by tests/solve/test_slap_flexible_piston.cpp):
# mass, centre of mass on the axis above the pin, inertia about it in the piston's axes (x, y the pin, z the axis)
PISTON = {"mass": 0.3187013, "com_z": 0.0093969, "inertia": (3.024342e-4, 2.697329e-4, 3.757883e-4)}
PIN_MASS = round(0.42 - PISTON["mass"], 4)      # pin, rings, pin clips: the rest of the family's 0.42 kg


def name(level, angle):
    return f"sk_{level}_{angle:03d}"


def component():
    text = (HERE.parent / "piston.toml").read_text()
    head, rest = text.split("[component]", 1)
    head = ("# The slap family's flexible piston (level (e), written by make_flexible_piston.py; edit that, not this\n"
            "# file): testdata/piston.toml with the film's skirt grid as observation points. testdata/piston.toml's header:\n") + head
    rest = rest.replace('mesh = "piston.geo"', 'mesh = "../piston.geo"', 1)
    points = "".join(f"""[[observe]]
name = "{name(k, a)}"
at = [{R * math.cos(math.radians(a)):.6f}, {-R * math.sin(math.radians(a)):.6f}, {z}]
""" for k, z in enumerate(LEVELS) for a in ANGLES)
    anchor = "[reduction]"
    rest = rest.replace(anchor, "# The skirt's grid for the film (sk_LEVEL_ANGLE): levels z = " +
                        ", ".join(f"{z:g}" for z in LEVELS) + " m, angles from +x towards -y (deg)\n" + points +
                        "\n" + anchor, 1)
    (HERE / "piston_skirt.toml").write_text(head + "[component]" + rest)
    # The same with the fixed-interface modes to 10 kHz only and residual vectors of the skirt's points
    # (6 mm pressure patches): the static skirt compliance exact (docs/component-format.md section 5.4)
    old = next(line for line in rest.splitlines() if line.startswith("fmax = 30000.0"))
    rv = rest.replace(old, "fmax = 10000.0                # Hz: 6 fixed-interface modes ...\n"
                      "residual_vectors = [\"sk_*\"]   # ... and the skirt points' residual vectors\n"
                      "residual_patch = 0.006         # m: each a 6 mm pressure patch", 1)
    rv_head = head.replace("# The slap family's flexible piston (level (e),",
                           "# The slap family's flexible piston with residual vectors (level (e)'s convergence check,", 1)
    (HERE / "piston_skirt_rv.toml").write_text(rv_head + "[component]" + rv)


def scene(flexible):
    text = (HERE / "slap_film.toml").read_text()
    head, body = text.split("[scene]", 1)
    level = ("(e): the skirt's film of level (b) on the flexible piston" if flexible else
             "(e)'s rigid twin: the piston of level (e) rigid, with its superelement's mass properties")
    head = f"""# Piston slap, level {level}.
#
# Written by make_flexible_piston.py from slap_film.toml (level (b), see below); edit those, not this file.
# The piston: testdata/piston.geo (0.319 kg) """ + (
        "as the Craig-Bampton superelement piston_skirt.h5 (make_flexible_piston.py says\n"
        "# how to make it), the film's skirt its 50 observation points (docs/bearing.md section 18), the gas force at\n"
        "# the pin as in levels (a) - (d);" if flexible else
        "rigid, its mass, centre of mass and inertia those of piston_skirt.h5;") + f""" the pin and rings a rigid {PIN_MASS} kg body fixed at the pin.
#
# Level (b)'s header, for the parameters:
""" + "\n".join("#" + line[1:] if line.startswith("#") else line for line in head.splitlines()[1:]) + "\n"
    body = body.replace('name = "slap_film"', f'name = "{"slap_flexible_piston" if flexible else "slap_piston_rigid"}"', 1)
    start = body.index('[[body]]\nname = "piston"')
    end = body.index("[[joint]]", start)
    if flexible:
        markers = "".join(f"""  [[body.marker]]
  name = "{label}"
  point = "{name(level, 0)}"
""" for label, level in [("skirt_top", 0), ("skirt_bottom", len(LEVELS) - 1)])
        piston = f"""[[body]]
name = "piston"
type = "flexible"
superelement = "piston_skirt.h5"
position = [0, {PIN_Y}, 0]
orientation = [0.70710678, -0.70710678, 0, 0]
  [[body.marker]]
  name = "axis"              # the film's piston frame at the pin: z up the piston, x the thrust side
  point = "pin"
  z = [0, 0, 1]
  x = [1, 0, 0]
  [[body.marker]]
  name = "wrist"             # the pin's frame for the joints: z along the pin (the piston's -y), x the thrust side
  point = "pin"
  z = [0, -1, 0]
  x = [1, 0, 0]
{markers}"""
    else:
        ix, iy, iz = PISTON["inertia"]
        c = PISTON["com_z"]
        piston = f"""[[body]]
name = "piston"
type = "rigid"
mass = {PISTON["mass"]}
inertia = [{ix:.6e}, {iz:.6e}, {iy:.6e}]   # the piston's x, z (its axis), y (the pin) about the centre of mass
position = [0, {PIN_Y + c:.7f}, 0]       # the centre of mass, {c * 1e3:.4f} mm above the pin
  [[body.marker]]
  name = "pin"
  at = [0, {-c:.7f}, 0]
  [[body.marker]]
  name = "wrist"             # the pin's frame for the joints (as the flexible piston's)
  at = [0, {-c:.7f}, 0]
  [[body.marker]]
  name = "skirt_top"
  at = [0, {0.012 - c:.7f}, 0]
  [[body.marker]]
  name = "skirt_bottom"
  at = [0, {-0.028 - c:.7f}, 0]
  [[body.marker]]
  name = "axis"              # the piston axis at the pin; z towards the crown, x the thrust side
  at = [0, {-c:.7f}, 0]
  z = [0, 1, 0]
  x = [1, 0, 0]
"""
    pin = f"""[[body]]
name = "gudgeon_pin"         # pin, rings and clips: the family's 0.42 kg less the piston's {PISTON["mass"]:.4f} kg
type = "rigid"
mass = {PIN_MASS}
inertia = [2e-5, 2e-5, 5e-6]
position = [0, {PIN_Y}, 0]
  [[body.marker]]
  name = "centre"

"""
    body = body[:start] + piston + "\n" + pin + body[end:]
    fixed = """[[joint]]
name = "pin_in_piston"
type = "fixed"
i = "gudgeon_pin.centre"
j = "piston.wrist"
"""
    old = 'i = "piston.pin"\nj = "conrod.small_end"'
    assert old in body
    body = body.replace(old, 'i = "piston.wrist"\nj = "conrod.small_end"', 1)
    body = body.replace("[[driver]]", fixed + "\n[[driver]]", 1)
    if flexible:
        skirt = "skirt = [" + ", ".join(f'"piston.{name(k, a)}"' for k in range(len(LEVELS)) for a in ANGLES) + "]"
        old = 'j = "ground.bore"\n'
        assert old in body
        body = body.replace(old, f"""{old}# the skirt's 5 levels x 10 angles: observation points of piston_skirt.h5 (surface nodes within 2 mm)
{skirt}
skirt_tolerance = 0.003      # m: the points snap to surface nodes of the 5 mm mesh
""", 1)
    name_ = "slap_flexible_piston.toml" if flexible else "slap_piston_rigid.toml"
    (HERE / name_).write_text(head + "[scene]" + body)


if __name__ == "__main__":
    component()
    scene(True)
    scene(False)
