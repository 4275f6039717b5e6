// Hermetic refrigeration compressor shell (generic): a closed steel can 0.2 m tall, deep-drawn from 3 mm
// sheet - a cylinder with two elliptical domes, flattened at both ends - with 4 spring seats (short
// studs) standing on the flat inside of the bottom, on which the motor-compressor unit hangs by coil
// springs. Units: m. Axes: z up along the can's axis, origin on the axis at the bottom of the
// cylindrical part.
// Physical groups (node sets for the component file): SEAT1..SEAT4, the flat top face of each spring
// seat; SHELL, the volume.
SetFactory("OpenCASCADE");

R = 0.080;       // outer radius of the can
H = 0.130;       // height of the cylindrical part
dome = 0.045;    // height of each elliptical dome (outer), before flattening
flat = 0.035;    // the domes are cut flat this far from the cylinder (outer): total height H + 2 flat
t = 0.003;       // wall thickness (sheet)
seat_r = 0.035;  // radius of the circle of spring seats
seat_d = 0.016;  // spring seat (stud) diameter
seat_top = -flat + t + 0.020;  // height of the seat faces: 20 mm above the inner bottom

// A body of revolution: cylinder + two half-ellipsoids (spheres scaled along z), cut flat at both ends.
// Called for the outer skin (tag 10) and the inner skin (tag 20).
Macro Can
  Cylinder(tag + 1) = {0, 0, 0, 0, 0, H, r};
  Sphere(tag + 2) = {0, 0, H, r};
  Dilate {{0, 0, H}, {1, 1, d / r}} { Volume{tag + 2}; }
  Sphere(tag + 3) = {0, 0, 0, r};
  Dilate {{0, 0, 0}, {1, 1, d / r}} { Volume{tag + 3}; }
  Box(tag + 4) = {-r, -r, -f, 2 * r, 2 * r, H + 2 * f};
  body() = BooleanUnion{ Volume{tag + 1}; Delete; }{ Volume{tag + 2, tag + 3}; Delete; };
  body() = BooleanIntersection{ Volume{body()}; Delete; }{ Volume{tag + 4}; Delete; };
Return

tag = 10; r = R; d = dome; f = flat;
Call Can;
outer() = body();
tag = 20; r = R - t; d = dome - t; f = flat - t;
Call Can;
inner() = body();
can() = BooleanDifference{ Volume{outer()}; Delete; }{ Volume{inner()}; Delete; };

// Spring seats at 45, 135, 225, 315 degrees: studs from 0.5 mm inside the bottom plate up to seat_top.
For i In {0:3}
  a = Pi / 4 + i * Pi / 2;
  Cylinder(100 + i) = {seat_r * Cos(a), seat_r * Sin(a), -flat + t - 0.0005, 0, 0, seat_top + flat - t + 0.0005,
                       seat_d / 2};
EndFor
shell() = BooleanUnion{ Volume{can()}; Delete; }{ Volume{100:103}; Delete; };

For i In {0:3}
  a = Pi / 4 + i * Pi / 2;
  x = seat_r * Cos(a);
  y = seat_r * Sin(a);
  e = 1e-4;
  top() = Surface In BoundingBox{x - seat_d, y - seat_d, seat_top - e, x + seat_d, y + seat_d, seat_top + e};
  Physical Surface(Sprintf("SEAT%g", i + 1)) = top();
EndFor
Physical Volume("SHELL") = shell();

Mesh.MeshSizeMax = 0.010;
// Straight-sided quadratic tetrahedra: mid-edge nodes at the edges' midpoints, not moved onto the curved
// surfaces. Curving them inverted an element where a stud meets the bottom at some sizes; the chord of
// a 10 mm element on the 80 mm radius misses the surface by 0.16 mm on both skins alike.
Mesh.SecondOrderLinear = 1;
