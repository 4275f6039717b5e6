# Bearing benchmark: evaluations per second of the short and finite bearings, warm and cold start.
add_executable(bench_bearing_evaluations ${CMAKE_CURRENT_SOURCE_DIR}/bearing_evaluations.cpp)
target_link_libraries(bench_bearing_evaluations PRIVATE nvh_bearing nvh_warnings)
# Bearing benchmark: a rigid crankshaft on 5 main bearings in solve (finite, short, spring-damper bearings).
add_executable(bench_bearing_crankshaft ${CMAKE_CURRENT_SOURCE_DIR}/bearing_crankshaft.cpp)
target_link_libraries(bench_bearing_crankshaft PRIVATE nvh_solve nvh_warnings)
target_compile_definitions(bench_bearing_crankshaft PRIVATE NVH_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
