#!/usr/bin/python3
"""Writes the three fidelity levels of the slap family from common.toml.in (run it in this directory):

  slap_dry.toml           (a) six dry point contacts (`contact`, Hunt-Crossley) at the skirt's top edge, barrel
                              crown and bottom edge, thrust and anti-thrust side, each with the clearance of
                              the skirt profile there
  slap_film.toml          (b) one `piston-liner` element on a rigid liner: the skirt film (JFO), partially
                              flooded by an 8 um oil layer, Greenwood-Tripp asperity contact
  slap_film_starved.toml  (c) the same with a starved supply: a 3 um oil layer
"""
import pathlib

HERE = pathlib.Path(__file__).resolve().parent
R, C = 0.043, 30e-6
# the barrel (radius reduction, m) against s (m, from the pin towards the crown): 12 um at the bottom edge
# (s = -0.028), crown at s = -0.006: 12e-6 ((s + 0.006) / 0.022)^2
BARREL_S = [-0.028, -0.024, -0.020, -0.016, -0.012, -0.008, -0.006, -0.004, 0.0, 0.004, 0.008, 0.012]


def barrel(s):
    return 12e-6 * ((s + 0.006) / 0.022) ** 2


def barrel_table():
    rows = ", ".join(f"[{s:g}, {barrel(s):.3g}]" for s in BARREL_S)
    return f"barrel = [{rows}]"


DRY_POINTS = [("top", 0.012), ("crown", -0.006), ("bottom", -0.028)]


def dry():
    ground = """  [[body.marker]]
  name = "liner_thrust"      # the liner's surface at x = +R, normal into the bore (-x)
  at = [0.043, 0.0, 0.0]
  z = [-1, 0, 0]
  x = [0, 1, 0]
  [[body.marker]]
  name = "liner_anti"        # at x = -R, normal +x
  at = [-0.043, 0.0, 0.0]
  z = [1, 0, 0]
  x = [0, 1, 0]
"""
    piston = ""
    for side, x in (("thrust", R), ("anti", -R)):
        for pos, s in DRY_POINTS:
            piston += f"""  [[body.marker]]
  name = "{side}_{pos}"
  at = [{x}, {s}, 0]
"""
    guidance = """# Skirt against liner, dry (level a): a linear penalty of 2e8 N/m per point (an estimate of the skirt panel's
# local radial stiffness, as testdata/scenes/piston_slap.toml), Hunt-Crossley restitution 0.5 at 0.1 m/s; the
# clearance of each point is the radial clearance plus the barrel's radius reduction there.
"""
    for side in ("thrust", "anti"):
        for pos, s in DRY_POINTS:
            guidance += f"""[[force]]
name = "dry_{side}_{pos}"
type = "contact"
i = "piston.{side}_{pos}"
j = "ground.liner_{side}"
stiffness = 2e8
exponent = 1.0
restitution = 0.5
reference_speed = 0.1
clearance = {C + barrel(s):.4g}
"""
    integrator = """# the contact onsets are events; a 20 us step limit resolves the contact (its period sqrt(m / k) is 0.3 ms)
[integrator]
rtol = 1e-6
atol = 1e-9
max_step = 2e-5
"""
    return ground, piston, guidance, integrator


def film(oil_layer, fill, viscosity=0.007, axial=16, around=12, comment=""):
    ground = """  [[body.marker]]
  name = "bore"              # on the bore axis; z the bore axis (towards the crown), x the thrust side
  z = [0, 1, 0]
  x = [1, 0, 0]
"""
    piston = """  [[body.marker]]
  name = "axis"              # the piston axis at the pin; z towards the crown, x the thrust side
  z = [0, 1, 0]
  x = [1, 0, 0]
"""
    guidance = f"""# The skirt's film and asperities (docs/bearing.md sections 15 and 16). {comment}
# Oil: 0.007 Pa s (a 5W-30 at about 130 deg C on the liner: HTHS 3 mPa s at 150 deg C, about 2.5 times that
# at 120 deg C). The skirt is partially flooded: `oil_layer` is the oil the liner and skirt carry (a closing gap
# wider than it pushes air, not oil); the fill ratio of the film dragged in at either edge is that layer over
# the inlet edge's film (about 40 um: the clearance and the barrel), fill = oil_layer / 40 um.
# Roughness and modulus as piston_slap_film.toml (honed cast-iron liner, machined aluminium skirt).
[[force]]
name = "skirt"
type = "piston-liner"
i = "piston.axis"
j = "ground.bore"
bore_radius = {R}
radial_clearance = {C:g}
skirt_length = 0.040
skirt_top = 0.012
arcs_deg = [[-60, 60], [120, 240]]
{barrel_table()}
viscosity = {viscosity:g}
cavitation = "jfo"
oil_layer = {oil_layer:g}
fill_bottom = {fill:g}
fill_top = {fill:g}
cells_axial = {axial}
cells_around = {around}
sigma = 1e-6                 # composite roughness (m)
sigma_beta_eta = 0.04        # Greenwood-Tripp: K = 2.40e-4
sigma_over_beta = 1e-3
modulus = 1.1e11             # composite modulus E' (Pa)
mu_asperity = 0.1
"""
    integrator = """# as piston_slap_film.toml: the velocity tolerance keeps IDA from chasing the nanometre ringing of the
# lateral and tilt velocities on the stiff squeeze film (docs/bearing.md section 15.6)
[integrator]
rtol = 1e-7
atol = 1e-9
velocity_atol = 1e-6
"""
    return ground, piston, guidance, integrator


def write(name, title, parts):
    ground, piston, guidance, integrator = parts
    text = (HERE / "common.toml.in").read_text()
    for key, value in (("@TITLE@", title), ("@NAME@", name), ("@GROUND_MARKERS@", ground),
                       ("@PISTON_MARKERS@", piston), ("@GUIDANCE@", guidance), ("@INTEGRATOR@", integrator)):
        text = text.replace(key, value)
    (HERE / f"{name}.toml").write_text(text)


if __name__ == "__main__":
    write("slap_dry", "Piston slap, level (a): dry point contacts of the skirt on the liner.", dry())
    write("slap_film", "Piston slap, level (b): the skirt's oil film (piston-liner) on a rigid liner, 8 um oil layer.",
          film(8e-6, 0.2, comment="Level (b): an 8 um oil layer."))
    write("slap_film_starved", "Piston slap, level (c): the film of level (b) with a starved supply, 3 um oil layer.",
          film(3e-6, 0.075, comment="Level (c): a starved 3 um oil layer (fill 0.075)."))
