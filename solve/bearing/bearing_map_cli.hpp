#pragma once
// `solve bearing-map BEARING.toml -o OUT.h5 [--csv OUT.csv] [--eccentricities ...] [--speed-rpm N]`:
// the static characteristics of one bearing over eccentricity ratio (bearing_map.hpp), written as HDF5
// (one dataset per column under /map, units as attributes, provenance) and optionally as CSV.
// solve's main() dispatches here when its first argument is "bearing-map" (argv[0] = "bearing-map").
namespace nvh::bearing {

/// Runs the tool; returns the process exit code (0 ok, 1 bad input or failed run, 2 bad command line).
int bearing_map_main(int argc, char** argv);

}  // namespace nvh::bearing
