#!/usr/bin/python3
"""Write the engine scene family (docs/engine.md) from one set of parameters, so that the variants differ
only where they say they do. Run from anywhere: /usr/bin/python3 make_scenes.py (writes next to itself).
The scenes are committed; rerun this after changing a parameter here and commit both.

  engine.toml                 baseline: flexible block (block.toml, Craig-Bampton) on 4 non-linear mounts
                              + a Maxwell (hydro) element at mount 1; flexible crankshaft (../crankshaft.toml)
                              on 5 short (Ocvirk) journal bearings and a thrust bearing; 4 rigid conrods and
                              pistons; revolute big ends, cylindrical small ends (floating pins), pistons held
                              on their bore axes (in-line joints) and against turning about their pins
                              (in-plane joints of the crowns) - no redundant equation; gas forces 1-3-4-2 on
                              the pistons and, reversed, on the cylinder heads; speed driver 2000 rpm at the
                              flywheel
  engine_bushing_mains.toml   the same with linear spring-damper main bearings (bushings, the paper's eq. 8)
  engine_steady.toml          engine.toml run to its periodic steady state ([steady_state]: the 4 mounts'
                              vertical forces and main bearing 3's force, tolerance 1e-2, the last cycle kept)
  engine_film4.toml           engine_steady.toml with piston 4 on the piston-liner film (skirt, oil and
                              roughness of testdata/slap level b) on a rigid liner at the block's liner4 point;
                              pistons 1-3 keep their joints
  engine_finite_mains.toml    engine_film4.toml with 5 finite (Reynolds, JFO) main bearings: the issue's
                              benchmark configuration (block to 5 kHz, beam crank, finite mains, lubricated
                              piston 4)
  engine_rigid.toml           the rigid twin: block and crankshaft as rigid bodies (their superelements' mass,
                              centre of mass and inertia), bushing main bearings - seconds per cycle; the
                              energy-balance and mount-force test (tests/engine)
  engine_runup.toml           engine.toml as a run-up for order cuts over speed: the speed driver holds
                              1000 rpm for 0.2 s (the mounts' start-up), then ramps linearly to 3000 rpm in
                              1.2 s (about 20 cycles); `make_scenes.py runup --seconds S -o FILE` writes a
                              run-up of another length (the workflow's quick variant)
  engine_rigid_throws.toml    the statically determinate crank train: 4 rigid throws, each on its own 2
                              half main bearings (bushings to ground), each turned by its own speed driver;
                              the main-bearing load test against the hand calculation (tests/engine)

Axes of every scene: the block's (engine_block.geo): x along the crank axis from the front (pulley,
cylinder 1 at x = -0.135 m) to the rear (flywheel), z up along the cylinders, y = z x x; origin on the
crank axis at the middle main bearing. SI units (m, kg, s, N, rad) except keys named _deg or rpm.
The crankshaft turns positively about +x; crank angle 0 = firing TDC of cylinder 1 (throws 1 and 4 up).
"""
import math
from pathlib import Path

HERE = Path(__file__).resolve().parent

# ---------------------------------------------------------------- parameters (sources in docs/engine.md)
RPM = 2000.0
OMEGA = RPM * 2 * math.pi / 60
R, L_ROD = 0.043, 0.145                     # crank radius (crankshaft.toml), conrod centres (conrod.toml)
BORE = 0.086
AREA = math.pi / 4 * BORE**2
GAS_SCALE = 1e5 * AREA                      # N per bar of cylinder_pressure.csv
CYL_X = [-0.135, -0.045, 0.045, 0.135]      # cylinder axes (engine_block.geo, pitch 90 mm)
MAIN_X = [-0.180, -0.090, 0.0, 0.090, 0.180]
THROW_UP = [True, False, False, True]       # flat-plane crank: throws 1, 4 at TDC at crank angle 0
FIRING_OFFSET = [0, 540, 180, 360]          # firing order 1-3-4-2: cylinder k fires at this crank angle
CRANK_ORIGIN_X = -0.180                     # crankshaft.toml has main1 at its origin; the block's main1
# conrod (conrod.toml: 0.674 kg, centre of mass 45.6 mm from the big end)
ROD_M, ROD_A = 0.674, 0.0456
ROD_I_SWING = ROD_M * ROD_A * (L_ROD - ROD_A)   # dynamically equivalent to 2 point masses (docs/engine.md)
ROD_I = [ROD_I_SWING, 0.0030, 0.00015]      # about x (swing), y, z (rod axis), kg m^2
# piston assembly: piston.toml 0.319 kg + pin (steel tube 22/13 mm x 60 mm) 0.116 kg + rings 0.030 kg
PISTON_M = 0.465
PISTON_I = [3.5e-4, 3.5e-4, 4.3e-4]         # a 86 mm x 60 mm aluminium cylinder, roughly
COMPRESSION_H = 0.030                       # pin axis to crown, m
# block (block.h5 invariants: condense testdata/engine/block.toml)
BLOCK_M, BLOCK_C = 56.4161, [0.0, 0.0, 0.0659853]   # x, y: 1.1e-5, -1.5e-7 m, taken as 0
BLOCK_I = [0.681642, 1.35585, 1.26163]
# crankshaft with pulley and flywheel (crankshaft.h5 invariants), centre of mass on the axis
CRANK_M, CRANK_CX = 25.8843, 0.243183       # in the crankshaft's frame (x from main1)
CRANK_I = [0.1301, 0.7298, 0.7397]          # about the centre of mass, crank axes (testdata/README.md)
# mounts: rubber mounts of a ~90 kg engine (bounce ~15 Hz), loss factor ~0.15
MOUNT_X, MOUNT_Y, MOUNT_Z = [-0.110, 0.110, -0.110, 0.110], [0.140, 0.140, -0.140, -0.140], 0.015
MOUNT_KZ, MOUNT_KB, MOUNT_XB, MOUNT_DZ = 2.0e5, 2.0e5, 0.002, 300.0
MOUNT_KXY, MOUNT_DXY, MOUNT_KROT = 1.0e5, 150.0, 100.0
MAXWELL_K, MAXWELL_C = 1.0e5, 1000.0        # hydro mount's fluid path: corner k/(2 pi c) = 15.9 Hz
# main bearings
JB = dict(diameter=0.055, width=0.024, radial_clearance=30e-6, viscosity=0.008)
MAIN_K, MAIN_D = 1.0e9, 2.0e4               # eq. 8 bearings: N/m, N s/m (radial)
# eq. 8 big and small ends (guidance "spring-ends"): an oil film at moderate eccentricity, 4e8 N/m radially
# (the conrod and piston bounce on it at ~3 and ~4.7 kHz), damping ratio ~0.1 for the conrod; axial 1e8 N/m
# (the cheeks' thrust faces, big end only); tilt k_r w^2 / 12 over a 20 mm wide bush (and d alike)
END_SPRING = dict(k=4.0e8, d=4.0e3, k_axial=1.0e8, d_axial=1.0e3, k_tilt=4.0e8 * 0.02**2 / 12,
                  d_tilt=4.0e3 * 0.02**2 / 12)
THRUST_K, THRUST_D = 1.0e8, 2.0e3           # axial, at main 3
# finite (Reynolds) mains: the oil supply of testdata/scenes/bearing_crankshaft.toml; the hole in the upper
# (unloaded by the gas) shell: the shell marker's x is +z (up), so +z is angle 0 about the crank axis
FINITE_SUPPLY, FINITE_GRID, FINITE_HOLE_DEG = 3e5, (60, 20), 0.0


def f(v):
    return f"{v:.9g}"


def vec(v):
    return "[" + ", ".join(f(x) for x in v) + "]"


def header(title, lines):
    out = [f"# {title}", "#"]
    out += ["# " + l if l else "#" for l in lines]
    out += ["#",
            "# Made by make_scenes.py (edit there, not here). SI units (m, kg, s, N, rad; keys _deg and rpm",
            "# as named). Axes: the block's - x along the crank axis (front/pulley at -x, cylinder 1 at",
            "# x = -0.135 m), z up along the cylinders, origin on the crank axis at main bearing 3. Gravity off",
            "# (the mounts are modelled about the static sag, which does not change the vibration about it).",
            "# Crank angle 0 = firing TDC of cylinder 1; firing order 1-3-4-2. Parameters and their sources:",
            "# docs/engine.md."]
    return "\n".join(out) + "\n"


# ---- the lubricated piston (piston-liner, docs/bearing.md sections 15-16): the skirt, oil and roughness of the
# slap study's level (b), testdata/slap/make_scenes.py film(8e-6, 0.2): skirt 40 mm, top edge 12 mm above the
# pin, radial clearance 30 um, parabolic barrel 12 um at the bottom edge with its crown 6 mm below the pin,
# thrust and anti-thrust panels +-60 deg, 16 x 12 cells per panel, 0.007 Pa s, JFO, 8 um oil layer, fill 0.2,
# Greenwood-Tripp sigma 1 um, sigma beta eta 0.04, sigma / beta 1e-3, E' 1.1e11 Pa, mu 0.1.
# Thrust side: the crank turns about +x, so the crank pin moves to -y after TDC and the expansion stroke presses
# the piston on +y: the film's x (thrust) is +y, its z the cylinder axis +z.
SKIRT_C, SKIRT_L, SKIRT_TOP = 30e-6, 0.040, 0.012
SKIRT_BARREL_S = [-0.028, -0.024, -0.020, -0.016, -0.012, -0.008, -0.006, -0.004, 0.0, 0.004, 0.008, 0.012]
OIL_LAYER, OIL_FILL, OIL_VISC = 8e-6, 0.2, 0.007


def skirt_barrel(s):
    return 12e-6 * ((s + 0.006) / 0.022) ** 2


def conrod_tdc_velocity(k):
    """The conrod's velocity at TDC (crank angle 0, throws 1 and 4 up): the small end at rest, the big end at
    the crank pin's -omega r along y, so it turns at -omega r / l about x and its centre of mass moves at
    -omega r (l - a) / l along y. A free piston (film guidance) needs it: the start-up projection otherwise
    gives the piston a lateral velocity (docs/bearing.md section 15.6)."""
    assert THROW_UP[k]
    return (f"velocity = [0, {f(-OMEGA * R * (L_ROD - ROD_A) / L_ROD)}, 0]    # TDC: small end at rest\n"
            f"angular_velocity = [{f(-OMEGA * R / L_ROD)}, 0, 0]\n")


def piston_film_markers():
    return """
  [[body.marker]]
  name = "axis"                    # the piston axis at the pin: z to the crown, x the thrust side (+y)
  z = [0, 0, 1]
  x = [0, 1, 0]"""


def skirt_film(n, block):
    rows = ", ".join(f"[{s:g}, {skirt_barrel(s):.3g}]" for s in SKIRT_BARREL_S)
    return f"""# The lubricated piston {n} (docs/bearing.md sections 15-16): the skirt's film and asperities between the
# piston and a rigid liner whose frame is the block's bore{n} (the liner{n} point: the block's deformation there
# moves the liner frame). Skirt, oil and roughness of testdata/slap level (b) (slap_film.toml).
[[force]]
name = "skirt{n}"
type = "piston-liner"
i = "piston{n}.axis"
j = "{block}.bore{n}"
bore_radius = {f(BORE / 2)}
radial_clearance = {SKIRT_C:g}
skirt_length = {SKIRT_L:g}
skirt_top = {SKIRT_TOP:g}
arcs_deg = [[-60, 60], [120, 240]]
barrel = [{rows}]
viscosity = {OIL_VISC:g}
cavitation = "jfo"
oil_layer = {OIL_LAYER:g}
fill_bottom = {OIL_FILL:g}
fill_top = {OIL_FILL:g}
cells_axial = 16
cells_around = 12
sigma = 1e-6                 # composite roughness (m)
sigma_beta_eta = 0.04        # Greenwood-Tripp: K = 2.40e-4
sigma_over_beta = 1e-3
modulus = 1.1e11             # composite modulus E' (Pa)
mu_asperity = 0.1
"""


# ---- periodic steady state (scene-format.md section 9): the 4 mounts' vertical forces and main bearing 3's
STEADY_CHANNELS = ["forces/mount1_z/force", "forces/mount2_z/force", "forces/mount3_z/force",
                   "forces/mount4_z/force", "forces/main3/force"]
STEADY_TOL, STEADY_MAX = 1e-2, 60


def steady_block(tol=STEADY_TOL, max_cycles=STEADY_MAX, keep=1):
    ch = ", ".join(f'"{c}"' for c in STEADY_CHANNELS)
    return f"""
[steady_state]                     # cycles until the watched channels repeat (scene-format.md section 9)
channels = [{ch}]
tolerance = {tol:g}
max_cycles = {max_cycles}
keep_cycles = {keep}
cycle_deg = 720
"""


def pin_z(k):
    return R if THROW_UP[k] else -R


# the cylinder head as a rigid body (guidance option "head"): an aluminium DOHC head with camshafts and valves,
# 14 kg (an engineering estimate for a 2.0 l four-cylinder: 13-18 kg), a 0.42 x 0.20 x 0.12 m box whose centre of
# mass lies 60 mm above the deck, bolted at the four head points (block.toml's head1..4 on the deck, 0.23 m) by
# bushings; the gas pushes it up at those points (so the load reaches the block through the bolts)
HEAD_M, HEAD_BOX, HEAD_DZ = 14.0, (0.42, 0.20, 0.12), 0.06
HEAD_K, HEAD_D = [1e9, 1e9, 1e9, 1e6, 1e6, 1e6], [2e4, 2e4, 2e4, 10, 10, 10]


def head_body():
    a, b, h = HEAD_BOX
    inertia = [HEAD_M * (b * b + h * h) / 12, HEAD_M * (a * a + h * h) / 12, HEAD_M * (a * a + b * b) / 12]
    text = f"""
# ---- the cylinder head: rigid, {HEAD_M:g} kg, bolted to the deck at head1..4 (bushings)
[[body]]
name = "head"
type = "rigid"
mass = {f(HEAD_M)}
inertia = {vec(inertia)}
position = [0, 0, {f(0.230 + HEAD_DZ)}]
"""
    for k in range(4):
        text += f"""  [[body.marker]]
  name = "pad{k + 1}"
  at = [{f(CYL_X[k])}, 0, {f(-HEAD_DZ)}]
"""
    for k in range(4):
        text += f"""
[[force]]
name = "head_bolts{k + 1}"
type = "bushing"
i = "head.pad{k + 1}"
j = "block.head{k + 1}"
stiffness = {vec(HEAD_K)}
damping = {vec(HEAD_D)}
"""
    return text


def big_end_block(n, crank_pin, marker="big_end"):
    """The big end as the paper's eq. 8 spring-damper (guidance "spring-ends")."""
    r = END_SPRING
    return f"""[[force]]
name = "big_end{n}"                # eq. 8: the big-end bearing as radial, axial and tilt spring-dampers
type = "bearing-spring"
i = "conrod{n}.{marker}"
j = "{crank_pin}"
radial_stiffness = {f(r['k'])}
radial_damping = {f(r['d'])}
axial_stiffness = {f(r['k_axial'])}
axial_damping = {f(r['d_axial'])}
tilt_stiffness = {f(r['k_tilt'])}
tilt_damping = {f(r['d_tilt'])}
"""


def small_end_block(n, marker="small_end"):
    """The small end as the paper's eq. 8 spring-damper: no axial spring (the floating pin)."""
    r = END_SPRING
    return f"""[[force]]
name = "small_end{n}"              # eq. 8: the pin in the small-end bush; floats along the pin
type = "bearing-spring"
i = "piston{n}.pin"
j = "conrod{n}.{marker}"
radial_stiffness = {f(r['k'])}
radial_damping = {f(r['d'])}
tilt_stiffness = {f(r['k_tilt'])}
tilt_damping = {f(r['d_tilt'])}
"""


def crank_train(lines, block, crank_pin, head_at, liner_of, film=(), tilt_plane_of=None, guidance="in-line"):
    """Conrods, pistons, their joints, and the gas loads. crank_pin(k) names the crank pin marker (z along x),
    head_at(k) the block's marker for the head reaction (or None), liner_of(k) the block's guide marker (z the
    cylinder axis), tilt_plane_of(k) the block's marker of the plane through the cylinder and crank axes (z the
    thrust direction y; default liner_of(k) + "_plane").
    The guidance holds each direction once (docs/engine.md, "Piston guidance"): big end revolute (5 equations),
    small end cylindrical along the pin (4: the rod floats along the pin, the crank guides it axially), the
    pin centre on the bore axis (in-line, 2) and the skirt's stop against turning about the pin (in-plane of
    the crown, 1): 12 equations for the 12 coordinates of conrod and piston, none redundant.
    film: the cylinders (0-based) whose piston the piston-liner film guides instead (their bore marker is the
    block's `bore<n>`, see skirt_film); the film holds the lateral motion in the plane and the tilt about the
    pin, the revolute small end the rest (the piston then floats with the rod along the crank axis).
    guidance = "prismatic": the former guidance (prismatic joint to the liner, revolute small end: 15 equations,
    3 redundant, an over-constrained crank train), kept for the comparison in bench/engine_fidelity.py.
    guidance = "spring-ends": the in-line guidance with big and small ends as the paper's eq. 8 spring-dampers
    (`bearing-spring`: radial, axial and tilt springs, the spin free) instead of joints; the small end has no
    axial spring (the floating pin), and film cylinders keep their revolute small end.
    guidance = "head" (in flexible_scene): the cylinder head as a rigid body on bushings (head_body).
    guidance = "beam-conrods": the conrods as beam superelements (testdata/conrod.toml condensed to conrod.h5,
    Craig-Bampton to 15 kHz) instead of rigid bodies. Options combine with "+" ("spring-ends+beam-conrods")."""
    if tilt_plane_of is None:
        tilt_plane_of = lambda k: liner_of(k) + "_plane"  # noqa: E731
    options = set(guidance.split("+"))
    spring_ends = "spring-ends" in options
    beam_conrods = "beam-conrods" in options
    guidance = "prismatic" if "prismatic" in options else "in-line"
    for k in range(4):
        n = k + 1
        zb = pin_z(k)
        zs = zb + math.sqrt(L_ROD**2 - 0.0)  # the conrod stands vertical at TDC and BDC
        if k in film:
            guide = skirt_film(n, block)
            small_end = "revolute"         # the film holds only the in-plane motion: the pin holds the rest
        elif guidance == "prismatic":
            guide = f"""[[joint]]
name = "guide{n}"                  # the former guidance: a prismatic joint (over-constrained, 3 redundant)
type = "prismatic"
i = "piston{n}.slide"
j = "{liner_of(k)}"
"""
            small_end = "revolute"
        else:
            guide = f"""[[joint]]
name = "guide{n}"                  # the bore holds the pin centre on its axis (both lateral directions)
type = "in-line"
i = "piston{n}.slide"
j = "{liner_of(k)}"

[[joint]]
name = "tilt{n}"                   # the skirt stops the piston turning about its pin (secondary motion)
type = "in-plane"
i = "piston{n}.crown"
j = "{tilt_plane_of(k)}"
"""
            small_end = "cylindrical"      # floating pin: the rod slides along it (crank-guided conrod)
        be, se = ("big_eye", "small_eye") if beam_conrods else ("big_end", "small_end")
        big_end = big_end_block(n, crank_pin(k), be) if spring_ends else f"""[[joint]]
name = "big_end{n}"
type = "revolute"
i = "conrod{n}.{be}"
j = "{crank_pin(k)}"
"""
        small_end_text = small_end_block(n, se) if spring_ends and k not in film else f"""[[joint]]
name = "small_end{n}"
type = "{small_end}"
i = "piston{n}.pin"
j = "conrod{n}.{se}"
"""
        if beam_conrods:
            conrod = f"""[[body]]
name = "conrod{n}"
type = "flexible"                  # beam superelement of ../conrod.toml (0.674 kg, CoM 45.6 mm from the big end)
superelement = "conrod.h5"
position = [{f(CYL_X[k])}, 0, {f(zb)}]    # the component's origin: the big-end centre
orientation = [0.7071067811865476, 0, -0.7071067811865476, 0]   # component x (big -> small end) -> global z
  [[body.marker]]
  name = "big_eye"                 # at the interface point big_end, z along the crank axis (global x)
  point = "big_end"
  z = [0, 0, -1]
  x = [1, 0, 0]
  [[body.marker]]
  name = "small_eye"
  point = "small_end"
  z = [0, 0, -1]
  x = [1, 0, 0]
"""
        else:
            conrod = f"""[[body]]
name = "conrod{n}"
type = "rigid"
mass = {f(ROD_M)}                        # conrod.toml
inertia = {vec(ROD_I)}   # x: m a (l - a), the 2-point-mass equivalent
position = [{f(CYL_X[k])}, 0, {f(zb + ROD_A)}]    # centre of mass, {ROD_A * 1e3:.1f} mm above the big end
{conrod_tdc_velocity(k) if k in film else ""}  [[body.marker]]
  name = "big_end"
  at = [0, 0, {f(-ROD_A)}]
  z = [1, 0, 0]
  x = [0, 0, 1]
  [[body.marker]]
  name = "small_end"
  at = [0, 0, {f(L_ROD - ROD_A)}]
  z = [1, 0, 0]
  x = [0, 0, 1]
"""
        lines.append(f"""
# ---- cylinder {n}: conrod and piston ({'TDC' if THROW_UP[k] else 'BDC'} at crank angle 0)
{conrod}
[[body]]
name = "piston{n}"
type = "rigid"
mass = {f(PISTON_M)}                        # piston 0.319 + pin 0.116 + rings 0.030 kg
inertia = {vec(PISTON_I)}
position = [{f(CYL_X[k])}, 0, {f(zs)}]       # centre of mass taken on the pin axis
  [[body.marker]]
  name = "pin"
  z = [1, 0, 0]
  x = [0, 0, 1]
  [[body.marker]]
  name = "slide"                   # z along the cylinder axis (the guide)
  z = [0, 0, 1]
  x = [1, 0, 0]
  [[body.marker]]
  name = "crown"
  at = [0, 0, {f(COMPRESSION_H)}]{piston_film_markers() if k in film else ""}

{big_end}
{small_end_text}
{guide}
[[load]]
name = "gas{n}"                    # (p - 1 bar) x bore area on the crown, fires at {FIRING_OFFSET[k]} deg
type = "force"
at = "piston{n}.crown"
direction = [0, 0, -1]
abscissa = "crank-angle"
file = "cylinder_pressure.csv"
columns = ["crank_deg", "p_bar"]
scale = {f(GAS_SCALE)}              # N/bar: 1e5 Pa/bar x pi 0.086^2 / 4
period_deg = 720
offset_deg = {FIRING_OFFSET[k]}
""")
        if head_at is not None:
            lines.append(f"""
[[load]]
name = "head{n}"                   # the same pressure on the cylinder head, bolted to the deck
type = "force"
at = "{head_at(k)}"
direction = [0, 0, 1]
abscissa = "crank-angle"
file = "cylinder_pressure.csv"
columns = ["crank_deg", "p_bar"]
scale = {f(GAS_SCALE)}
period_deg = 720
offset_deg = {FIRING_OFFSET[k]}
""")


def mounts(lines, block, maxwell):
    lines.append("""
# ---- engine mounts: 4 rubber mounts at the pads; each a bushing (longitudinal x, lateral y, small
# rotational rates) in parallel with a progressive vertical spring-damper (eq. 8 with eq. 9-10's
# k = k0 + kB (dx/xB)^2: 200 N/mm, doubling at 2 mm), ground points 50 mm below the pads.""")
    for m in range(4):
        n = m + 1
        lines.append(f"""
[[force]]
name = "mount{n}"
type = "bushing"
i = "{block}.mount{n}"
j = "ground.mount{n}"
stiffness = [{f(MOUNT_KXY)}, {f(MOUNT_KXY)}, 0, {f(MOUNT_KROT)}, {f(MOUNT_KROT)}, {f(MOUNT_KROT)}]
damping = [{f(MOUNT_DXY)}, {f(MOUNT_DXY)}, 0, 0, 0, 0]

[[force]]
name = "mount{n}_z"
type = "spring-damper"
i = "{block}.mount{n}"
j = "ground.mount{n}_base"
k = {f(MOUNT_KZ)}
d = {f(MOUNT_DZ)}
kB = {f(MOUNT_KB)}
xB = {f(MOUNT_XB)}
""")
    if maxwell:
        lines.append(f"""
# Mount 1 is a hydro mount: its fluid path is a Maxwell element (spring k in series with a damper c, the
# damper's deflection an element state) in parallel with the rubber: dynamic stiffness k c w i / (k + c w i),
# most damping at its corner k / (2 pi c) = {MAXWELL_K / (2 * math.pi * MAXWELL_C):.1f} Hz, near the bounce mode.
[[force]]
name = "mount1_hydro"
type = "maxwell"
i = "{block}.mount1"
j = "ground.mount1_base"
k = {f(MAXWELL_K)}
c = {f(MAXWELL_C)}
""")


def ground(lines, extra=""):
    lines.append("""
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "dyno"                    # the dynamometer's axis at the flywheel (speed driver, clock)
  at = [0.237, 0, 0]
  z = [1, 0, 0]
  x = [0, 0, 1]""")
    for m in range(4):
        lines.append(f"""  [[body.marker]]
  name = "mount{m + 1}"
  at = [{f(MOUNT_X[m])}, {f(MOUNT_Y[m])}, {f(MOUNT_Z)}]
  [[body.marker]]
  name = "mount{m + 1}_base"
  at = [{f(MOUNT_X[m])}, {f(MOUNT_Y[m])}, {f(MOUNT_Z - 0.05)}]""")
    lines.append(extra)


def tail(lines, end_cycles, integrator, markers, steady=None):
    """end_cycles: a fixed number of cycles; steady: a [steady_state] block instead (end_cycles ignored)."""
    end = "" if steady else f"\nend_cycles = {end_cycles}"
    lines.append(f"""
[[driver]]
name = "speed"                     # the dynamometer holds {RPM:.0f} rpm at the flywheel
type = "speed"
i = "crank.fly"
j = "ground.dyno"
rpm = {RPM:.0f}

[clock]
i = "crank.fly"
j = "ground.dyno"
zero_deg = 0
cycle_deg = 720{end}
{steady or ""}
[integrator]
{integrator}

[output]
sample_rate_hz = 24000             # 2 samples per crank degree (0.5 deg) at 2000 rpm, Nyquist 12 kHz
markers = {markers}
""")


def main_bearings(lines, kind, crank, block):
    if kind == "short":
        lines.append(f"""
# ---- main bearings: short (Ocvirk) hydrodynamic journal bearings, D 55 mm, L 24 mm (crankshaft.toml),
# radial clearance 30 um, SAE 5W-30 near 100 C: 0.008 Pa s (as testdata/scenes/bearing_crankshaft.toml)""")
    elif kind == "finite":
        lines.append(f"""
# ---- main bearings: finite (Reynolds) journal bearings with JFO cavitation (docs/bearing.md), D 55 mm, L 24 mm,
# radial clearance 30 um, 0.008 Pa s; oil fed at {FINITE_SUPPLY:.0e} Pa through a 5 mm hole in the upper shell
# (angle {FINITE_HOLE_DEG:g} deg from the shell marker's x = +z: the top, away from the gas load); {FINITE_GRID[0]} x
# {FINITE_GRID[1]} cells (the grid of testdata/scenes/bearing_crankshaft.toml)""")
    else:
        lines.append(f"""
# ---- main bearings: linear spring-dampers (bushings; the paper's eq. 8 in both radial directions):
# {MAIN_K:.0e} N/m, {MAIN_D:.0e} N s/m radially (an oil film at moderate eccentricity, damping ratio ~0.2 of the
# crank's bounce on them); no axial, tilt or spin stiffness""")
    for b in range(5):
        n = b + 1
        if kind in ("short", "finite"):
            lines.append(f"""
[[force]]
name = "main{n}"
type = "journal-bearing"
model = "{kind}"
i = "{crank}.journal{n}"
j = "{block}.shell{n}"
diameter = {JB['diameter']}
width = {JB['width']}
radial_clearance = {JB['radial_clearance']}
viscosity = {JB['viscosity']}
""")
        if kind == "finite":
            lines[-1] += f"""supply_pressure = {FINITE_SUPPLY:g}
cavitation = "jfo"
grid = [{FINITE_GRID[0]}, {FINITE_GRID[1]}]
  [[force.hole]]
  angle_deg = {FINITE_HOLE_DEG:g}
  diameter = 0.005
"""
        if kind == "bushing":
            lines.append(f"""
[[force]]
name = "main{n}"
type = "bushing"
i = "{crank}.journal{n}"
j = "{block}.shell{n}"
stiffness = [{f(MAIN_K)}, {f(MAIN_K)}, 0, 0, 0, 0]
damping = [{f(MAIN_D)}, {f(MAIN_D)}, 0, 0, 0, 0]
""")
    lines.append(f"""
# ---- thrust bearing at main 3: axial only ({THRUST_K:.0e} N/m, {THRUST_D:.0e} N s/m)
[[force]]
name = "thrust"
type = "bushing"
i = "{crank}.journal3"
j = "{block}.shell3"
stiffness = [0, 0, {f(THRUST_K)}, 0, 0, 0]
damping = [0, 0, {f(THRUST_D)}, 0, 0, 0]
""")


CRANK_Q = [math.sqrt(0.5), math.sqrt(0.5), 0, 0]    # crank y (throw 1) -> global z, crank z -> -y


def flexible_scene(name, title, mains, lines_doc, integrator, block_modes, crank_modes, steady=None, film=(),
                   end_cycles=3, outdir=HERE, guidance="in-line"):
    lines = [header(title, lines_doc)]
    lines.append('[scene]\nname = "' + name + '"\ngravity = [0, 0, 0]\n')
    ground(lines)
    lines.append(f"""
# ---- the block: flexible, Craig-Bampton (block.toml), its lowest {block_modes} coordinates (to
# {BLOCK_MODE_F[block_modes - 1]:.0f} Hz); interfaces main1..5, mount1..4, head1..4, liner1..4 are markers
[[body]]
name = "block"
type = "flexible"
superelement = "block.h5"
modes = {block_modes}
position = [0, 0, 0]
  [[body.marker]]""")
    for b in range(5):
        if b:
            lines.append("  [[body.marker]]")
        lines.append(f"""  name = "shell{b + 1}"                # main bearing shell, z along the crank axis
  point = "main{b + 1}"
  z = [1, 0, 0]
  x = [0, 0, 1]""")
    for k in range(4):
        if k not in film:
            lines.append(f"""  [[body.marker]]
  name = "liner{k + 1}_plane"           # the plane of cylinder and crank axes (the tilt stop): z thrust (y)
  point = "liner{k + 1}"
  z = [0, 1, 0]
  x = [0, 0, 1]""")
    for k in film:
        lines.append(f"""  [[body.marker]]
  name = "bore{k + 1}"                 # the liner frame of the piston-liner film: z the cylinder axis, x thrust
  point = "liner{k + 1}"
  z = [0, 0, 1]
  x = [0, 1, 0]""")
    lines.append(f"""
# ---- the crankshaft with pulley and flywheel: flexible beam, Craig-Bampton (../crankshaft.toml, whose
# frame has main1 at its origin and throw 1 along its y): placed with main1 at x = {CRANK_ORIGIN_X} m and
# turned +90 deg about x, so throw 1 points up (crank y -> global z). Its lowest {crank_modes} coordinates
# (to {CRANK_MODE_F[crank_modes - 1]:.0f} Hz).
[[body]]
name = "crank"
type = "flexible"
superelement = "crankshaft.h5"
modes = {crank_modes}
position = [{CRANK_ORIGIN_X}, 0, 0]
orientation = {vec(CRANK_Q)}
angular_velocity = [{f(OMEGA)}, 0, 0]""")
    for b in range(5):
        lines.append(f"""  [[body.marker]]
  name = "journal{b + 1}"
  point = "main{b + 1}"
  z = [1, 0, 0]
  x = [0, 1, 0]""")
    for k in range(4):
        lines.append(f"""  [[body.marker]]
  name = "crankpin{k + 1}"
  point = "pin{k + 1}"
  z = [1, 0, 0]
  x = [0, 1, 0]""")
    lines.append("""  [[body.marker]]
  name = "fly"
  point = "flywheel"
  z = [1, 0, 0]
  x = [0, 1, 0]""")
    mounts(lines, "block", maxwell=True)
    main_bearings(lines, mains, "crank", "block")
    if "head" in guidance.split("+"):
        lines.append(head_body())
        head_at = lambda k: f"head.pad{k + 1}"  # noqa: E731
    else:
        head_at = lambda k: f"block.head{k + 1}"  # noqa: E731
    crank_train(lines, "block", lambda k: f"crank.crankpin{k + 1}", head_at,
                lambda k: f"block.liner{k + 1}", film, guidance=guidance)
    markers = ["block.jacket4_thrust", "block.oilpan_flange", "block.deck", "block.skirt", "block.mount1",
               "block.mount2", "block.mount3", "block.mount4", "block.liner4", "crank.pulley", "crank.fly"]
    markers += [f"piston{k + 1}.pin" for k in film]
    tail(lines, end_cycles, integrator, "[" + ", ".join(f'"{m}"' for m in markers) + "]", steady)
    (Path(outdir) / f"{name}.toml").write_text("".join(l if l.endswith("\n") else l + "\n" for l in lines))


def rigid_scene():
    lines = [header("The engine's rigid twin (tests/engine: energy balance and mount forces)", [
        "The baseline engine.toml with the block and the crankshaft as rigid bodies (each with its",
        "superelement's mass, centre of mass and inertia: block.h5 and crankshaft.h5) and linear spring-damper",
        "main bearings; everything else as in the baseline: mounts (with the Maxwell element), conrods, pistons,",
        "their guidance, gas on pistons and heads, 2000 rpm at the flywheel. Two cycles in a few seconds."])]
    lines.append('[scene]\nname = "engine-rigid"\ngravity = [0, 0, 0]\n')
    ground(lines)
    head = "".join(f"""  [[body.marker]]
  name = "head{k + 1}"
  at = [{f(CYL_X[k] - BLOCK_C[0])}, {f(-BLOCK_C[1])}, {f(0.230 - BLOCK_C[2])}]
  [[body.marker]]
  name = "liner{k + 1}"
  at = [{f(CYL_X[k] - BLOCK_C[0])}, {f(-BLOCK_C[1])}, {f(0.145 - BLOCK_C[2])}]
  [[body.marker]]
  name = "liner{k + 1}_plane"
  at = [{f(CYL_X[k] - BLOCK_C[0])}, {f(-BLOCK_C[1])}, {f(0.145 - BLOCK_C[2])}]
  z = [0, 1, 0]
  x = [0, 0, 1]
""" for k in range(4))
    shells = "".join(f"""  [[body.marker]]
  name = "shell{b + 1}"
  at = [{f(MAIN_X[b] - BLOCK_C[0])}, {f(-BLOCK_C[1])}, {f(-BLOCK_C[2])}]
  z = [1, 0, 0]
  x = [0, 0, 1]
""" for b in range(5))
    mnt = "".join(f"""  [[body.marker]]
  name = "mount{m + 1}"
  at = [{f(MOUNT_X[m] - BLOCK_C[0])}, {f(MOUNT_Y[m] - BLOCK_C[1])}, {f(MOUNT_Z - BLOCK_C[2])}]
""" for m in range(4))
    lines.append(f"""
# ---- the block as a rigid body: block.h5's invariants (mass, centre of mass, inertia about it)
[[body]]
name = "block"
type = "rigid"
mass = {f(BLOCK_M)}
inertia = {vec(BLOCK_I)}
position = {vec(BLOCK_C)}
{shells}{head}{mnt}""")
    cg = CRANK_ORIGIN_X + CRANK_CX
    journals = "".join(f"""  [[body.marker]]
  name = "journal{b + 1}"
  at = [{f(MAIN_X[b] - cg)}, 0, 0]
  z = [1, 0, 0]
  x = [0, 0, 1]
""" for b in range(5))
    pins = "".join(f"""  [[body.marker]]
  name = "crankpin{k + 1}"
  at = [{f(CYL_X[k] - cg)}, 0, {f(pin_z(k))}]
  z = [1, 0, 0]
  x = [0, 0, 1]
""" for k in range(4))
    lines.append(f"""
# ---- the crankshaft with pulley and flywheel as a rigid body: crankshaft.h5's mass and inertia (inertia
# about the centre of mass, crank axes: x axial {CRANK_I[0]}, radial {CRANK_I[1]}, {CRANK_I[2]} kg m^2; the
# small difference of the two radial values is dropped - the body turns, so one radial value, their mean)
[[body]]
name = "crank"
type = "rigid"
mass = {f(CRANK_M)}
inertia = [{f(CRANK_I[0])}, {f(0.5 * (CRANK_I[1] + CRANK_I[2]))}, {f(0.5 * (CRANK_I[1] + CRANK_I[2]))}]
position = [{f(cg)}, 0, 0]
angular_velocity = [{f(OMEGA)}, 0, 0]
{journals}{pins}  [[body.marker]]
  name = "fly"
  at = [{f(0.237 - cg)}, 0, 0]
  z = [1, 0, 0]
  x = [0, 0, 1]
""")
    mounts(lines, "block", maxwell=True)
    main_bearings(lines, "bushing", "crank", "block")
    crank_train(lines, "block", lambda k: f"crank.crankpin{k + 1}", lambda k: f"block.head{k + 1}",
                lambda k: f"block.liner{k + 1}")
    tail(lines, 2, 'method = "ida"\nrtol = 1e-7\natol = 1e-10\nmax_step = 5e-5',
         '["block.mount1", "block.mount2", "block.mount3", "block.mount4"]')
    (HERE / "engine_rigid.toml").write_text("".join(l if l.endswith("\n") else l + "\n" for l in lines))


def throws_scene():
    lines = [header("The statically determinate crank train (tests/engine: main-bearing loads)", [
        "The crankshaft split at the main bearings into 4 rigid throws, each held by its own 2 half bearings",
        "(stiff, well damped spring-dampers: bushings to ground at the main-bearing centres, 45 mm either side",
        "of its pin) and turned at 2000 rpm by its own speed driver. Each throw's centre of mass lies on the",
        "axis midway between its bearings, so the load on each half bearing is half the crank-pin force",
        "(the lever rule) - the hand calculation the test compares with. Main bearing k's load is the sum of",
        "its two halves (the rear half of throw k-1 and the front half of throw k). Ground stands for the",
        "block; conrods, pistons, joints and gas forces as in engine.toml."])]
    lines.append('[scene]\nname = "engine-rigid-throws"\ngravity = [0, 0, 0]\n')
    liners = "".join(f"""  [[body.marker]]
  name = "liner{k + 1}"
  at = [{f(CYL_X[k])}, 0, 0.145]
  [[body.marker]]
  name = "liner{k + 1}_plane"
  at = [{f(CYL_X[k])}, 0, 0.145]
  z = [0, 1, 0]
  x = [0, 0, 1]
""" for k in range(4))
    mains = "".join(f"""  [[body.marker]]
  name = "main{b + 1}"
  at = [{f(MAIN_X[b])}, 0, 0]
  z = [1, 0, 0]
  x = [0, 0, 1]
""" for b in range(5))
    lines.append(f"""
[[body]]
name = "ground"
type = "ground"
{mains}{liners}""")
    for k in range(4):
        n = k + 1
        lines.append(f"""
# ---- throw {n}: journals at x = {MAIN_X[k]} and {MAIN_X[k + 1]} m, pin at x = {CYL_X[k]} m
[[body]]
name = "throw{n}"
type = "rigid"
mass = 4.1                        # a quarter of the 16.4 kg crankshaft, balanced on its axis
inertia = [0.012, 0.010, 0.010]
position = [{f(CYL_X[k])}, 0, 0]
angular_velocity = [{f(OMEGA)}, 0, 0]
  [[body.marker]]
  name = "front"
  at = [-0.045, 0, 0]
  z = [1, 0, 0]
  x = [0, 0, 1]
  [[body.marker]]
  name = "rear"
  at = [0.045, 0, 0]
  z = [1, 0, 0]
  x = [0, 0, 1]
  [[body.marker]]
  name = "pin"
  at = [0, 0, {f(pin_z(k))}]
  z = [1, 0, 0]
  x = [0, 0, 1]

[[force]]
name = "throw{n}_front"           # half of main bearing {n}
type = "bushing"
i = "throw{n}.front"
j = "ground.main{n}"
stiffness = [{f(MAIN_K)}, {f(MAIN_K)}, {f(THRUST_K)}, 0, 0, 0]
damping = [{f(MAIN_D)}, {f(MAIN_D)}, {f(THRUST_D)}, 0, 0, 0]

[[force]]
name = "throw{n}_rear"            # half of main bearing {n + 1}
type = "bushing"
i = "throw{n}.rear"
j = "ground.main{n + 1}"
stiffness = [{f(MAIN_K)}, {f(MAIN_K)}, {f(THRUST_K)}, 0, 0, 0]
damping = [{f(MAIN_D)}, {f(MAIN_D)}, {f(THRUST_D)}, 0, 0, 0]

[[driver]]
name = "speed{n}"
type = "speed"
i = "throw{n}.front"
j = "ground.main{n}"
rpm = {RPM:.0f}
""")
    crank_train(lines, "ground", lambda k: f"throw{k + 1}.pin", None, lambda k: f"ground.liner{k + 1}")
    lines.append(f"""
[clock]
i = "throw1.front"
j = "ground.main1"
zero_deg = 0
cycle_deg = 720
end_cycles = 1

[integrator]
# generalized-alpha at a fixed 10 us (20 steps per period of the throws' 3.3 kHz bounce on their bearings,
# solve --advise); IDA at rtol 1e-6 needs 51k steps (58 % rejected) and 30 s for the cycle, this 6000 steps
method = "generalized-alpha"
step = 1e-5
rho_inf = 0.8

[output]
sample_rate_hz = 24000
markers = ["throw1.pin"]
""")
    (HERE / "engine_rigid_throws.toml").write_text("".join(l if l.endswith("\n") else l + "\n" for l in lines))


BLOCK_MODE_F = [636.161, 1025.75, 1302.63, 1336.03, 1363.26, 1415.82, 1417.34, 1555.54, 1560.25, 1965.43,
                1987.44, 2138.89, 2329.29, 2468.85, 2520.6, 2690.54, 2893.79, 2899.78, 2902.25, 2962.23,
                3052.79, 3088.65, 3245.17, 3266.99, 3279.48, 3361.12, 3501.09, 3599.36, 3765.77, 3808.98,
                3821.5, 3994.95, 4097.56, 4130.03, 4175.21, 4208.01, 4336.54, 4377.14, 4414.03, 4494.68,
                4575.73, 4603.28, 4653.2, 4793.24, 4824.59, 5020.83]
CRANK_MODE_F = [136.112, 153.096, 324.267, 388.356, 444.977, 445.16, 784.165, 831.481, 1055.92, 1091.13,
                1327.3, 1670.42, 1749.8, 1951.47, 1967.3, 2354.79, 2446.1, 2465.31, 2490.97, 3012.91]

INTEGRATOR = 'method = "ida"\nrtol = 1e-5\natol = 1e-8\nmax_step = 2e-5'
# the lubricated piston: velocity_atol keeps IDA from chasing the nanometre ringing of the piston's lateral and
# tilt velocities on the stiff squeeze film (docs/bearing.md section 15.6)
INTEGRATOR_FILM = INTEGRATOR + '\nvelocity_atol = 1e-5'
# the finite main bearings: rtol 1e-6. At 1e-5 the films' Newton tolerance (film_tolerance 1e-8) leaves an error
# IDA accepts, and it excites the block: over the first 240 deg the block's 0.5-2 kHz content doubles and the
# mounts' forces are 7 % RMS off a 1e-7 run (1e-6: 1.6e-4), for the same CPU (the steps are set by Newton's
# convergence on the films, not by the error test; docs/engine.md "Main bearings").
INTEGRATOR_FINITE = INTEGRATOR_FILM.replace('rtol = 1e-5', 'rtol = 1e-6')
BASELINE_DOC = ["Baseline of the engine scene family (docs/engine.md): the flexible block on 4 mounts (one with",
                "a Maxwell hydro element), the flexible crankshaft with pulley and flywheel on 5 short journal",
                "bearings and a thrust bearing, 4 rigid conrods and pistons on revolute big ends and cylindrical",
                "small ends (floating pins), pistons held on their bore axes (in-line) and against turning about",
                "their pins (in-plane), gas forces on pistons and heads, speed driver.",
                "Superelements made beside this file's copy by `make -f Makefile.workflow engine`:",
                "block.h5 (condense block.toml, ~3 min, ~2-4 GB) and crankshaft.h5 (condense ../crankshaft.toml)."]
STEADY_DOC = ["engine.toml run to its periodic steady state ([steady_state]: the 4 mounts' vertical forces and main",
              "bearing 3's force repeat from one 720 deg cycle to the next within an estimated distance of 1e-2;",
              "the last cycle is the result); everything else identical (docs/engine.md)."]
FILM4_DOC = ["engine_steady.toml with piston 4 guided by the piston-liner element (the skirt film with asperity",
             "contact on a rigid liner whose frame is the block's liner4 point, block.bore4) instead of its",
             "in-line guidance; skirt, oil and roughness of testdata/slap level (b); pistons 1-3 keep their",
             "in-line guidance. Run to the periodic steady state (docs/engine.md)."]
FINITE_DOC = ["engine_film4.toml with the 5 main bearings finite (Reynolds equation on a 60 x 20 grid, JFO",
              "cavitation, oil fed at 3 bar through a hole in the upper shell) instead of short (Ocvirk): the",
              "benchmark configuration of issue 15 (block to 5 kHz, beam crank, finite mains, lubricated",
              "piston 4). Run to the periodic steady state (docs/engine.md)."]

# ---- the run-up (docs/engine.md "Results"): engine.toml with the speed driver's table instead of its constant
# rpm; the scene ends by time. Written from flexible_scene's baseline text, each change checked to apply once.
RUNUP_RPM = (1000.0, 3000.0)
RUNUP_HOLD_S, RUNUP_RAMP_S = 0.2, 1.2


def runup_scene(ramp_s=RUNUP_RAMP_S, hold_s=RUNUP_HOLD_S, out=HERE / "engine_runup.toml"):
    import tempfile
    rpm0, rpm1 = RUNUP_RPM
    with tempfile.TemporaryDirectory() as tmp:
        flexible_scene("engine_runup", f"The engine's run-up, {rpm0:.0f} to {rpm1:.0f} rpm in {ramp_s:g} s",
                       "short", ["engine.toml with the speed driver's rpm(t) table: "
                                 f"{rpm0:.0f} rpm held for {hold_s:g} s (the mounts' start-up transient),",
                                 f"then a linear ramp to {rpm1:.0f} rpm in {ramp_s:g} s; ends at "
                                 f"{hold_s + ramp_s:g} s. For order cuts of the mounts over speed",
                                 "(postproc orders --cuts; docs/engine.md \"Results\")."],
                       INTEGRATOR, 45, 20, outdir=tmp)
        text = (Path(tmp) / "engine_runup.toml").read_text()
    end_s = hold_s + ramp_s
    omega0 = rpm0 * 2 * math.pi / 60

    def once(old, new):
        nonlocal text
        assert text.count(old) == 1, old
        text = text.replace(old, new)

    once(f"angular_velocity = [{f(OMEGA)}, 0, 0]", f"angular_velocity = [{f(omega0)}, 0, 0]")
    once(f"# the dynamometer holds {RPM:.0f} rpm at the flywheel",
         f"# the dynamometer's run-up {rpm0:.0f} -> {rpm1:.0f} rpm")
    once(f"rpm = {RPM:.0f}\n", f"table = [[0, {rpm0:.0f}], [{hold_s:g}, {rpm0:.0f}], [{end_s:g}, {rpm1:.0f}]]"
         "    # [time s, rpm], linear between points\n")
    once("\ncycle_deg = 720\nend_cycles = 3\n", f"\nend_time = {end_s:g}\n")
    once("sample_rate_hz = 24000             # 2 samples per crank degree (0.5 deg) at 2000 rpm, Nyquist 12 kHz",
         "sample_rate_hz = 24000             # 4 .. 1.33 samples per crank degree over 1000 .. 3000 rpm")
    Path(out).write_text(text)


if __name__ == "__main__":
    import sys
    if sys.argv[1:2] == ["runup"]:   # make_scenes.py runup --seconds S -o FILE: a run-up of another length
        import argparse
        ap = argparse.ArgumentParser(prog="make_scenes.py runup")
        ap.add_argument("--seconds", type=float, default=RUNUP_RAMP_S, help="ramp time, s")
        ap.add_argument("-o", "--output", type=Path, required=True)
        a = ap.parse_args(sys.argv[2:])
        runup_scene(a.seconds, out=a.output)
        sys.exit(0)
    flexible_scene("engine", "The engine: a 2.0 l four-cylinder in-line gasoline engine at 2000 rpm, full load", "short",
                   BASELINE_DOC, INTEGRATOR, 45, 20)
    flexible_scene("engine_bushing_mains", "The engine with spring-damper main bearings (fidelity variant)", "bushing",
                   ["engine.toml with the 5 journal bearings replaced by linear spring-dampers (bushings, the",
                    "paper's eq. 8); everything else identical (docs/engine.md)."],
                   INTEGRATOR, 45, 20)
    flexible_scene("engine_steady", "The engine at its periodic steady state", "short", STEADY_DOC,
                   INTEGRATOR, 45, 20, steady=steady_block())
    flexible_scene("engine_film4", "The engine at its periodic steady state, cylinder 4's piston lubricated",
                   "short", FILM4_DOC, INTEGRATOR_FILM, 45, 20, steady=steady_block(), film=(3,))
    flexible_scene("engine_finite_mains", "The engine with finite main bearings and cylinder 4's piston lubricated",
                   "finite", FINITE_DOC, INTEGRATOR_FINITE, 45, 20, steady=steady_block(), film=(3,))
    rigid_scene()
    throws_scene()
    runup_scene()
