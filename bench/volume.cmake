# Volume (solid) benchmarks: condense against CalculiX on the same gmsh mesh (run_volume_bench.sh).
add_executable(bench_volume_mesh volume_mesh.cpp)
target_link_libraries(bench_volume_mesh PRIVATE nvh_condense nvh_warnings)
