// A small steel block for the fuzzer: 100 x 20 x 20 mm, coarse enough that gmsh meshes it in a moment.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.1, 0.02, 0.02};
Physical Volume("BLOCK") = {1};
