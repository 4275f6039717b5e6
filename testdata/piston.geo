// Generic passenger-car piston (cast aluminium), bore 86 mm: a cup of 60 mm height with an 8 mm crown
// and a 3.5 mm skirt, two pin bosses with the 22 mm pin bore along y, and the slot for the conrod's
// small end between them. No ring grooves. Units: m. Axes: z up (crown on top), the pin axis along y
// through the origin.
// Physical groups (node sets): PIN_BORE, the pin bore's faces; CROWN, the top face; PISTON, the volume.
SetFactory("OpenCASCADE");

R = 0.043;          // piston radius
top = 0.030;        // crown top (z)
bottom = -0.030;    // skirt bottom (z)
crown = 0.008;      // crown thickness
skirt = 0.0035;     // skirt wall
boss_r = 0.016;     // outer radius of the pin bosses
pin_r = 0.011;      // pin bore radius
slot = 0.012;       // half width of the small-end slot between the bosses (y)

Cylinder(1) = {0, 0, bottom, 0, 0, top - bottom, R};
Cylinder(2) = {0, 0, bottom - 0.001, 0, 0, top - crown - bottom + 0.001, R - skirt};
cup() = BooleanDifference{ Volume{1}; Delete; }{ Volume{2}; Delete; };
// Pin bosses: a cylinder along y across the inside, hanging from the crown by a web, minus the slot.
Cylinder(3) = {0, -(R - skirt) - 0.001, 0, 0, 2 * (R - skirt) + 0.002, 0, boss_r};
Box(4) = {-0.006, -(R - skirt) - 0.001, 0, 0.012, 2 * (R - skirt) + 0.002, top - crown + 0.001};
boss() = BooleanUnion{ Volume{3}; Delete; }{ Volume{4}; Delete; };
Box(5) = {-R, -slot, -R, 2 * R, 2 * slot, top - crown + R - 0.002};
boss() = BooleanDifference{ Volume{boss()}; Delete; }{ Volume{5}; Delete; };
piston() = BooleanUnion{ Volume{cup()}; Delete; }{ Volume{boss()}; Delete; };
Cylinder(6) = {0, -R - 0.001, 0, 0, 2 * R + 0.002, 0, pin_r};
piston() = BooleanDifference{ Volume{piston()}; Delete; }{ Volume{6}; Delete; };

e = 1e-4;
Physical Surface("CROWN") = Surface In BoundingBox{-R - e, -R - e, top - e, R + e, R + e, top + e};
Physical Surface("PIN_BORE") = Surface In BoundingBox{-pin_r - e, -R - e, -pin_r - e, pin_r + e, R + e, pin_r + e};
Physical Volume("PISTON") = piston();

Mesh.MeshSizeMax = 0.005;
Mesh.SecondOrderLinear = 1;  // straight-sided quadratic tetrahedra (never inverted at curved corners)
