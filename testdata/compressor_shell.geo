// Hermetic refrigeration compressor shell (generic): a closed steel can about 0.2 m tall, drawn from
// 3 mm sheet - a cylinder with two elliptical domes - with 4 spring seats (short studs) standing on the
// inside of the bottom dome, on which the motor-compressor unit hangs by coil springs.
// Units: m. Axis: z up, the can's axis on the z axis, bottom dome apex at z = -dome.
// Physical groups (become node sets SEAT1..SEAT4 and SHELL, usable as interface.surface):
//   SEAT1..SEAT4: the flat top face of each spring seat; SHELL: the volume.
SetFactory("OpenCASCADE");

R = 0.080;      // outer radius of the can
H = 0.110;      // height of the cylindrical part
dome = 0.045;   // height of each elliptical dome (outer)
t = 0.003;      // wall thickness (sheet)
seat_r = 0.050; // radius of the circle of spring seats
seat_d = 0.016; // spring seat (stud) diameter
seat_top = -dome + 0.035;  // height of the seat faces (z)

// Outer and inner skins: cylinder + two half-ellipsoids (spheres scaled along z).
Cylinder(1) = {0, 0, 0, 0, 0, H, R};
Sphere(2) = {0, 0, H, R};
Dilate {{0, 0, H}, {1, 1, dome / R}} { Volume{2}; }
Sphere(3) = {0, 0, 0, R};
Dilate {{0, 0, 0}, {1, 1, dome / R}} { Volume{3}; }
outer() = BooleanUnion{ Volume{1}; Delete; }{ Volume{2, 3}; Delete; };

Ri = R - t;
di = dome - t;
Cylinder(11) = {0, 0, 0, 0, 0, H, Ri};
Sphere(12) = {0, 0, H, Ri};
Dilate {{0, 0, H}, {1, 1, di / Ri}} { Volume{12}; }
Sphere(13) = {0, 0, 0, Ri};
Dilate {{0, 0, 0}, {1, 1, di / Ri}} { Volume{13}; }
inner() = BooleanUnion{ Volume{11}; Delete; }{ Volume{12, 13}; Delete; };


// Spring seats: studs standing on the inner skin up to seat_top, at 45, 135, 225, 315 degrees; each is
// cut to the cavity so its foot follows the curved dome exactly.
For i In {0:3}
  a = Pi / 4 + i * Pi / 2;
  Cylinder(100 + i) = {seat_r * Cos(a), seat_r * Sin(a), -dome, 0, 0, seat_top + dome, seat_d / 2};
EndFor
studs() = BooleanIntersection{ Volume{100:103}; Delete; }{ Volume{inner()}; };
can() = BooleanDifference{ Volume{outer()}; Delete; }{ Volume{inner()}; Delete; };
shell() = BooleanUnion{ Volume{can()}; Delete; }{ Volume{studs()}; Delete; };

For i In {0:3}
  a = Pi / 4 + i * Pi / 2;
  x = seat_r * Cos(a);
  y = seat_r * Sin(a);
  e = 1e-4;
  top() = Surface In BoundingBox{x - seat_d, y - seat_d, seat_top - e, x + seat_d, y + seat_d, seat_top + e};
  Physical Surface(Sprintf("SEAT%g", i + 1)) = top();
  // Finer around the stud, whose foot meets the dome at a shallow angle.
  MeshSize{ Point In BoundingBox{x - seat_d, y - seat_d, -dome - e, x + seat_d, y + seat_d, seat_top + e} } = 0.004;
EndFor
Physical Volume("SHELL") = shell();

Mesh.MeshSizeMax = 0.008;
