// Generic 4-cylinder in-line engine block (cast iron), built from boxes and cylinders - no realism
// beyond a plausible modal density: a crankcase with 4 bays between 5 main-bearing bulkheads, a narrower
// upper block with 4 siamesed cylinder liners (bore 86 mm, pitch 90 mm) standing in a water jacket
// under a 20 mm deck, the main-bearing bore (60 mm) through the bulkheads, and 4 engine-mount pads on
// the sides of the crankcase. Units: m. Axes: x along the crank axis (cylinder 1 at x < 0), z up along
// the cylinders, y = z cross x; the crank axis is the x axis.
// Physical groups (node sets): MOUNT1..MOUNT4, the outer faces of the mount pads; BLOCK, the volume.
SetFactory("OpenCASCADE");

L = 0.400;         // block length along x
pitch = 0.090;     // cylinder and main-bearing pitch
bore = 0.086;      // cylinder bore
liner = 0.006;     // liner wall
deck = 0.230;      // deck height above the crank axis
skirt = -0.060;    // bottom of the crankcase (oil-pan flange)
top_w = 0.130;     // width of the upper block
case_w = 0.240;    // width of the crankcase
wall = 0.010;      // crankcase side walls
bulk = 0.022;      // bulkhead thickness
main_d = 0.060;    // main-bearing bore diameter

// Upper block and crankcase.
Box(1) = {-L / 2, -top_w / 2, 0.060, L, top_w, deck - 0.060};
Box(2) = {-L / 2, -case_w / 2, skirt, L, case_w, 0.060 - skirt + 0.020};
block() = BooleanUnion{ Volume{1}; Delete; }{ Volume{2}; Delete; };

// Mount pads (50 x 20 x 50 mm) on both sides at x = -/+ 0.110.
For i In {0:3}
  px = (i % 2 == 0) ? -0.110 : 0.110;
  sy = (i < 2) ? 1 : -1;
  Box(10 + i) = {px - 0.025, (sy > 0) ? case_w / 2 : -case_w / 2 - 0.020, -0.010, 0.050, 0.020, 0.050};
EndFor
block() = BooleanUnion{ Volume{block()}; Delete; }{ Volume{10:13}; Delete; };

// Crankcase bays between the bulkheads (open at the bottom).
For i In {0:3}
  x0 = -2 * pitch + i * pitch + bulk / 2;
  Box(20 + i) = {x0, -case_w / 2 + wall, skirt - 0.010, pitch - bulk, case_w - 2 * wall, 0.080 - skirt + 0.010};
EndFor
// Water jacket around the liners, and the cylinder bores.
Box(30) = {-L / 2 + 0.012, -top_w / 2 + 0.010, 0.100, L - 0.024, top_w - 0.020, deck - 0.020 - 0.100};
For i In {0:3}
  cx = -1.5 * pitch + i * pitch;
  Cylinder(40 + i) = {cx, 0, 0.070, 0, 0, deck - 0.070 + 0.010, bore / 2 + liner};
  Cylinder(50 + i) = {cx, 0, 0.040, 0, 0, deck - 0.040 + 0.010, bore / 2};
EndFor
jacket() = BooleanDifference{ Volume{30}; Delete; }{ Volume{40:43}; Delete; };
// The main-bearing bore through all bulkheads.
Cylinder(60) = {-L / 2 - 0.010, 0, 0, L + 0.020, 0, 0, main_d / 2};
block() = BooleanDifference{ Volume{block()}; Delete; }{ Volume{20:23, jacket(), 50:53, 60}; Delete; };

For i In {0:3}
  px = (i % 2 == 0) ? -0.110 : 0.110;
  sy = (i < 2) ? 1 : -1;
  y = sy * (case_w / 2 + 0.020);
  e = 1e-4;
  Physical Surface(Sprintf("MOUNT%g", i + 1)) = Surface In BoundingBox{px - 0.026, y - e, -0.011, px + 0.026, y + e, 0.041};
EndFor
Physical Volume("BLOCK") = block();

Mesh.MeshSizeMax = 0.012;
Mesh.SecondOrderLinear = 1;  // straight-sided quadratic tetrahedra (never inverted at curved corners)
