#!/usr/bin/python3
"""Write the flexible connecting rod of Simeon's slider crank as a superelement (docs/hdf5-format.md).

The problem "Slider crank" of the Test Set for IVP Solvers (F. Mazzia, C. Magherini, University of Bari;
contributed by B. Simeon, 1998; B. Simeon, "Modelling a flexible slider crank mechanism by a mixed system of
DAEs and PDEs", Math. Modelling of Systems 2, 1-18, 1996) discretizes the rod (length L = 0.3 m, square
section b = h = 8 mm, E = 2e11 Pa, rho = 7870 kg/m^3) in a frame attached to the crank pin, x along the rod,
with n = 4 elastic coordinates q (the test set's crank.f, subroutine RESMBS, as shipped in the R package
deTestSet: repository rforge/bvpsolve, file pkg/deTestSet/src/Ex_crank.f):

  lateral      v(x) = q1 sin(pi xi) + q2 sin(2 pi xi),                      xi = x / L
  longitudinal u(x) = q3 4 xi (1 - xi) + q4 xi (2 xi - 1)   (quadratic, nodes at the middle and the end)

and these matrices and vectors (m = rho b h L, FACM = m, FACK = E b h / L, FACB = b h L; RESMBS's names):

  MQ = m [[1/2, 0, 0, 0], [0, 1/2, 0, 0], [0, 0, 8, 1], [0, 0, 1, 2]]
  KQ = (E b h / L) [[pi^4/24 (h/L)^2, 0, 0, 0], [0, 2 pi^4/3 (h/L)^2, 0, 0], [0, 0, 16/3, -8/3],
                    [0, 0, -8/3, 7/3]]
  c1 = FACB (0, 0, 2/3, 1/6)          = int N_u dxi      c2 = FACB (2/pi, 0, 0, 0)        = int N_v dxi
  c12 = L FACB (0, 0, 1/3, 1/6)       = L int xi N_u      c21 = L FACB (1/pi, -1/(2 pi), 0, 0) = L int xi N_v
  BQ(j, i) = FACB int (N_u,j N_v,i - N_v,j N_u,i) dxi:
    BQ(3, 1) = 16/pi^3, BQ(4, 1) = 1/pi - 8/pi^3, BQ(4, 2) = -1/(2 pi), antisymmetric.

Every entry but one is the exact integral of the shape functions above (checked in this file). The exception:
the test set's longitudinal mass block m [[8, 1], [1, 2]] is 15 times the consistent int rho N_u N_u^T dx =
m/15 [[8, 1], [1, 2]]. The test set uses that one matrix MQ everywhere (the elastic mass, the rod's inertia
J2 + 2 rho c12.q + q^T MQ q, the centrifugal term phi2'^2 MQ q), so the file carries it in /reduced/mass and
in /invariants/quadratic (S_xx); S_00 + S_11 + S_22 = /reduced/mass then holds as the format requires, and
solve's floating frame (docs/scene-flexible.md) reproduces RESMBS's equations term by term
(docs/verification.md, "Simeon's flexible slider crank").

The rigid invariants are those of a prismatic bar L x h x b with its end at the origin: mass m = 0.151104 kg,
centre (L/2, 0, 0), second moment diag(m L^2/3, m h^2/12, m b^2/12): J2 = m (L^2/3 + h^2/12) = 0.0045339259
kg m^2 about the pin, the test set's J2.

The coordinates in the file are the mass-orthonormal modes eta of (KQ, MQ), q = B eta (B is written to
/assumed_modes/basis, which solve ignores): the format's `modal` basis. Interface points: "pin" (x = 0, the
frame origin, no displacement) and "tip" (x = L: u = q4, v = 0); observation point "middle" (x = L/2:
u = q3, v = q1). Their rotation rows hold the slope rz = v'(x).

Run by Debian's /usr/bin/python3 (python3-h5py, python3-numpy):
  /usr/bin/python3 make_simeon_rod.py [-o simeon_rod.h5]
"""

import argparse
import datetime
import hashlib
import math
import os
import shlex
import socket
import sys

import h5py
import numpy as np

# The test set's parameters (RESMBS's common block /crankcom/; deTestSet R/ex_crank.R).
L2 = 0.30  # m, rod length
BB = 0.0080  # m, section width (out of plane, z)
HH = 0.0080  # m, section height (in plane, y)
EE = 0.20e12  # Pa
RHO = 7870.0  # kg/m^3
PI = math.pi
# RESMBS's own pi (PARAMETER PI = 3.1415927D0, 8 digits) in its matrices and vectors: the model is the test
# set's, so its constants use it; the shape functions' values at the points and the quadrature checks use pi.
PI_TESTSET = 3.1415927


def assumed_mode_model(consistent_mass=False):
    """MQ, KQ and the invariants in the test set's coordinates q (m, per unit q); with consistent_mass the
    longitudinal mass block is the consistent int rho N_u N_u^T dx (1/15 of the test set's)."""
    m = RHO * BB * HH * L2
    fack = EE * BB * HH / L2
    kq = np.zeros((4, 4))
    kq[0, 0] = fack * PI_TESTSET**4 / 24.0 * (HH / L2) ** 2
    kq[1, 1] = fack * PI_TESTSET**4 * 2.0 / 3.0 * (HH / L2) ** 2
    kq[2:, 2:] = fack * np.array([[16.0 / 3.0, -8.0 / 3.0], [-8.0 / 3.0, 7.0 / 3.0]])
    # Shape-function integrals (xi in [0, 1]); N_u: longitudinal rows, N_v: lateral rows.
    int_nu = np.array([0, 0, 2.0 / 3.0, 1.0 / 6.0])  # c1 / FACB
    int_nv = np.array([2.0 / PI_TESTSET, 0, 0, 0])  # c2 / FACB
    int_xi_nu = np.array([0, 0, 1.0 / 3.0, 1.0 / 6.0])  # c12 / (L FACB)
    int_xi_nv = np.array([1.0 / PI_TESTSET, -0.5 / PI_TESTSET, 0, 0])  # c21 / (L FACB)
    int_nu_nv = np.zeros((4, 4))  # [i, j] = int N_u,i N_v,j dxi
    int_nu_nv[2, 0] = 16.0 / PI_TESTSET**3
    int_nu_nv[3, 0] = 1.0 / PI_TESTSET - 8.0 / PI_TESTSET**3
    int_nu_nv[3, 1] = -0.5 / PI_TESTSET
    int_nv_nv = np.diag([0.5, 0.5, 0, 0])
    int_nu_nu = np.zeros((4, 4))
    # The test set's block: 15 x the consistent 1/15 [[8, 1], [1, 2]].
    int_nu_nu[2:, 2:] = np.array([[8.0, 1.0], [1.0, 2.0]])
    if consistent_mass:
        int_nu_nu /= 15.0
    mq = m * (int_nu_nu + int_nv_nv)

    n = 4
    translational = np.zeros((3, n))  # S_bar = int rho S dV
    translational[0] = m * int_nu
    translational[1] = m * int_nv
    position = np.zeros((3, 3, n))  # I_tilde[k, l] = int rho x_k S_l dV (y, z: centred section, 0)
    position[0, 0] = m * L2 * int_xi_nu
    position[0, 1] = m * L2 * int_xi_nv
    rotational = np.zeros((3, n))  # int rho x~ S dV: row k = eps_kab I_tilde[a, b]
    for k in range(3):
        a, b = (k + 1) % 3, (k + 2) % 3
        rotational[k] = position[a, b] - position[b, a]
    quadratic = np.zeros((3, 3, n, n))  # S[k, l] = int rho S_k^T S_l dV
    quadratic[0, 0] = m * int_nu_nu
    quadratic[1, 1] = m * int_nv_nv
    quadratic[0, 1] = m * int_nu_nv
    quadratic[1, 0] = m * int_nu_nv.T
    assert np.allclose(quadratic[0, 0] + quadratic[1, 1] + quadratic[2, 2], mq, rtol=0, atol=1e-15)

    second = np.diag([m * L2**2 / 3.0, m * HH**2 / 12.0, m * BB**2 / 12.0])
    com = np.array([L2 / 2.0, 0, 0])
    j_origin = np.trace(second) * np.eye(3) - second
    j_com = j_origin - m * (com @ com * np.eye(3) - np.outer(com, com))

    # Points: rows ux uy uz rx ry rz per unit q; rz = v'(x) = (pi/L) q1 cos(pi xi) + (2 pi/L) q2 cos(2 pi xi).
    def point(xi):
        s = np.zeros((6, n))
        s[0] = [0, 0, 4 * xi * (1 - xi), xi * (2 * xi - 1)]
        s[1] = [round(math.sin(PI * xi), 15), round(math.sin(2 * PI * xi), 15), 0, 0]
        s[5] = [PI / L2 * math.cos(PI * xi), 2 * PI / L2 * math.cos(2 * PI * xi), 0, 0]
        return s

    points = {"pin": (0.0, point(0.0)), "tip": (L2, point(1.0)), "middle": (0.5 * L2, point(0.5))}
    return dict(m=m, mq=mq, kq=kq, translational=translational, rotational=rotational, position=position,
                quadratic=quadratic, second=second, com=com, j_origin=j_origin, j_com=j_com, points=points)


def check_integrals():
    """The shape-function integrals above against a Gauss-Legendre quadrature (exact for these degrees)."""
    xi, w = np.polynomial.legendre.leggauss(40)
    xi, w = 0.5 * (xi + 1), 0.5 * w
    nu = np.array([0 * xi, 0 * xi, 4 * xi * (1 - xi), xi * (2 * xi - 1)])
    nv = np.array([np.sin(PI * xi), np.sin(2 * PI * xi), 0 * xi, 0 * xi])
    assert np.allclose(nu @ w, [0, 0, 2 / 3, 1 / 6], atol=1e-14)
    assert np.allclose(nv @ w, [2 / PI, 0, 0, 0], atol=1e-14)
    assert np.allclose(nu @ (w * xi), [0, 0, 1 / 3, 1 / 6], atol=1e-14)
    assert np.allclose(nv @ (w * xi), [1 / PI, -0.5 / PI, 0, 0], atol=1e-14)
    nunv = (nu * w) @ nv.T
    assert np.allclose(nunv[2:, :2], [[16 / PI**3, 0], [1 / PI - 8 / PI**3, -0.5 / PI]], atol=1e-14)
    assert np.allclose((nv * w) @ nv.T, np.diag([0.5, 0.5, 0, 0]), atol=1e-14)
    # The consistent longitudinal mass is 1/15 of the test set's block.
    assert np.allclose(((nu * w) @ nu.T)[2:, 2:] * 15, [[8, 1], [1, 2]], atol=1e-13)
    # Stiffness: int EA u'^2 and int EI v''^2 (per FACK = E b h / L and E b h / L (h/L)^2 / 12 ...).
    dnu = np.array([0 * xi, 0 * xi, 4 * (1 - 2 * xi), 4 * xi - 1])
    assert np.allclose(((dnu * w) @ dnu.T)[2:, 2:], [[16 / 3, -8 / 3], [-8 / 3, 7 / 3]], atol=1e-13)
    ddnv = np.array([-(PI**2) * np.sin(PI * xi), -4 * PI**2 * np.sin(2 * PI * xi)])
    # E I / L^3 int (d2v/dxi2)^2 = E b h^3 / (12 L^3) ...: against KQ / (E b h / L (h/L)^2) = pi^4/24, 2 pi^4/3
    assert np.allclose(((ddnv * w) @ ddnv.T) / 12, np.diag([PI**4 / 24, 2 * PI**4 / 3]), atol=1e-11)


def modal_basis(kq, mq):
    """B with B^T MQ B = 1, B^T KQ B = diag(omega^2) ascending; each column's largest entry positive."""
    linv = np.linalg.inv(np.linalg.cholesky(mq))  # MQ = L L^T
    lam, vec = np.linalg.eigh(linv @ kq @ linv.T)
    b = linv.T @ vec
    order = np.argsort(lam)
    lam, b = lam[order], b[:, order]
    for j in range(b.shape[1]):
        if b[np.argmax(np.abs(b[:, j])), j] < 0:
            b[:, j] = -b[:, j]
    return lam, b


def write(path, consistent_mass=False):
    check_integrals()
    mdl = assumed_mode_model(consistent_mass)
    lam, b = modal_basis(mdl["kq"], mdl["mq"])
    n = b.shape[1]
    mass = b.T @ mdl["mq"] @ b
    stiff = b.T @ mdl["kq"] @ b
    mass, stiff = 0.5 * (mass + mass.T), 0.5 * (stiff + stiff.T)
    utf8 = h5py.string_dtype("utf-8")
    tmp = path + ".tmp-make_simeon_rod"
    with h5py.File(tmp, "w") as f:
        f.attrs["format"] = "superelement"
        f.attrs["format_version"] = "1.1"
        f.attrs["units"] = "SI"
        f.attrs["component"] = "simeon-rod-consistent-mass" if consistent_mass else "simeon-rod"
        f.attrs["kind"] = "beam"
        f.attrs["method"] = "modal"
        f.attrs["orthonormalized"] = np.int64(1)
        f.attrs["coordinates"] = np.int64(n)
        script = os.path.abspath(__file__)
        with open(script, "rb") as s:
            sha = hashlib.sha256(s.read()).hexdigest()
        f.attrs["tool"] = "make_simeon_rod.py"
        f.attrs["tool_version"] = "1.0"
        f.attrs["command_line"] = " ".join(shlex.quote(a) for a in sys.argv)
        f.attrs["created_utc"] = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
        f.attrs["host"] = socket.gethostname()
        f.attrs.create("input_files", [script], dtype=utf8)
        f.attrs.create("input_sha256", [sha], dtype=utf8)

        g = f.create_group("modes")
        g["frequency_hz"] = np.sqrt(np.maximum(lam, 0)) / (2 * PI)
        g["frequency_hz"].attrs["units"] = "Hz"
        g.attrs["rigid_body_modes_removed"] = np.int64(6)
        g.attrs["rigid_body_modes_contained"] = np.int64(0)

        g = f.create_group("reduced")
        g["mass"] = mass
        g["stiffness"] = stiff
        g["damping"] = np.zeros((n, n))
        g["damping"].attrs["damping_ratio"] = 0.0
        g["damping"].attrs["units"] = "generalized, as stiffness times s"
        g.create_dataset("coordinates", data=[f"mode {j + 1}" for j in range(n)], dtype=utf8)

        for group, names in (("interface", ["pin", "tip"]), ("observe", ["middle"])):
            g = f.create_group(group)
            g.create_dataset("name", data=names, dtype=utf8)
            g["position"] = np.array([[mdl["points"][p][0], 0, 0] for p in names])
            g["position"].attrs["units"] = "m"
            g["shape"] = np.array([mdl["points"][p][1] @ b for p in names])

        g = f.create_group("invariants")
        g.attrs["formulation"] = "Shabana, Dynamics of Multibody Systems, 3rd ed., 2005, sec. 5.5"
        g["mass"] = mdl["m"]
        g["center_of_mass"] = mdl["com"]
        g["inertia"] = mdl["j_com"]
        g["inertia_origin"] = mdl["j_origin"]
        g["second_moment"] = mdl["second"]
        g["translational_coupling"] = mdl["translational"] @ b
        g["rotational_coupling"] = mdl["rotational"] @ b
        g["position_coupling"] = mdl["position"] @ b
        g["quadratic"] = np.einsum("ai,klab,bj->klij", b, mdl["quadratic"], b)

        g = f.create_group("assumed_modes")
        g.attrs["description"] = ("the test set's coordinates q = basis @ eta (q1, q2 lateral sine modes, m; "
                                  "q3, q4 longitudinal at the middle and the end, m); solve ignores this group")
        g["basis"] = b
        g["mass"] = mdl["mq"]
        g["stiffness"] = mdl["kq"]
    os.replace(tmp, path)
    return b


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("-o", "--output", default=os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                          "simeon_rod.h5"))
    p.add_argument("--print-initial", action="store_true",
                   help="print the test set's initial q, q' (deTestSet ini = 1) as modal coordinates eta")
    p.add_argument("--consistent-mass", action="store_true",
                   help="the consistent longitudinal mass (1/15 of the test set's block): "
                   "not the test set's model")
    args = p.parse_args()
    b = write(args.output, args.consistent_mass)
    if args.print_initial:
        q0 = np.array([0, 0, 0.103339863e-4, 0.169327969e-4])
        qd0 = np.array([0.444896105, 0.463434311e-2, -0.178591076e-5, -0.268938672e-5])
        fmt = lambda v: "[" + ", ".join(repr(float(x)) for x in v) + "]"
        print("modal_coordinates =", fmt(np.linalg.solve(b, q0)))
        print("modal_velocities =", fmt(np.linalg.solve(b, qd0)))


if __name__ == "__main__":
    main()
