#!/usr/bin/env bash
# condense --keep-mesh: the XDMF parses as XML (python3's xml.etree), names an existing grid of the
# right topology, and every DataItem it refers to exists in the companion .h5 with the shape it states;
# the shapes are those of the superelement (ratio of the observation point's shape to 1e-12).
# usage: check_keep_mesh.sh CONDENSE_EXE WORK_DIR
set -euo pipefail
condense="$1"
work="$2"
rm -rf "$work"
mkdir -p "$work"
cd "$work"
cat > bar.geo <<'GEO'
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.1, 0.02, 0.02};
Physical Surface("LEFT") = Surface In BoundingBox{-1e-4, -1, -1, 1e-4, 1, 1};
Physical Volume("BAR") = {1};
Mesh.MeshSizeMax = 0.01;
GEO
cat > bar.toml <<'TOML'
[component]
name = "bar"
kind = "volume"
[material.steel]
E = 210e9
nu = 0.3
rho = 7850.0
[volume]
mesh = "bar.geo"
material = "steel"
[[fix]]
surface = "LEFT"
dofs = "x y z"
[[observe]]
name = "tip"
at = [0.1, 0.02, 0.02]
[reduction]
method = "modal"
modes = 5
TOML
"$condense" bar.toml -o bar.h5 --keep-mesh -q
/usr/bin/python3 - <<'PY'
import xml.etree.ElementTree as ET
import h5py, numpy as np
root = ET.parse("bar.xdmf").getroot()
assert root.tag == "Xdmf" and root.get("Version") == "3.0", root.attrib
grids = root.findall("./Domain/Grid")
assert len(grids) == 1, len(grids)
grid = grids[0]
topology = grid.find("Topology")
assert topology.get("TopologyType") == "Tetrahedron_10", topology.attrib
items = grid.findall(".//DataItem")
attributes = grid.findall("Attribute")
se = h5py.File("bar.h5", "r")
mesh = h5py.File("bar.mesh.h5", "r")
assert mesh.attrs["format"] == "superelement-mesh", dict(mesh.attrs)
n = se["/modes/frequency_hz"].shape[0]
assert n == 5 and len(attributes) == n, (n, len(attributes))
for item in items:
    file, path = item.text.strip().split(":")
    assert file == "bar.mesh.h5", file
    shape = tuple(int(d) for d in item.get("Dimensions").split())
    assert path in mesh, path
    assert mesh[path].shape == shape, (path, mesh[path].shape, shape)
nodes = mesh["/mesh/position"].shape[0]
assert int(topology.get("NumberOfElements")) == mesh["/mesh/C3D10/connectivity"].shape[0]
conn = mesh["/mesh/C3D10/connectivity"][:]
assert conn.min() == 0 and conn.max() == nodes - 1
# The tip observation shape equals the full shape at that node (same coordinates).
tip = se["/observe/position"][0]
k = np.argmin(np.linalg.norm(mesh["/mesh/position"][:] - tip, axis=1))
for j in range(n):
    full = mesh["/shapes/shape_%04d" % (j + 1)][k]
    obs = se["/observe/shape"][0, 0:3, j]
    assert np.allclose(full, obs, rtol=0, atol=1e-12 * np.abs(obs).max()), (j, full, obs)
print("keep-mesh: %d nodes, %d elements, %d shapes; XDMF and HDF5 consistent" % (nodes, conn.shape[0], n))
PY
