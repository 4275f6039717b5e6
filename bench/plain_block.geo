// A plain steel block for bench/run_volume_bench.sh's second geometry (issue 17 item 1: "a plain block fixed on
// one face, TET10, 240k DOF, 30 modes"): 400 x 200 x 100 mm, fixed on its end face x = 0. Units: m.
// Physical groups (node sets): FIXED, the face x = 0; BLOCK, the volume.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.400, 0.200, 0.100};
e = 1e-6;
Physical Surface("FIXED") = Surface In BoundingBox{-e, -e, -e, e, 0.200 + e, 0.100 + e};
Physical Volume("BLOCK") = {1};
