# Bearing benchmark: evaluations per second of the short and finite bearings, warm and cold start.
add_executable(bench_bearing_evaluations ${CMAKE_CURRENT_SOURCE_DIR}/bearing_evaluations.cpp)
target_link_libraries(bench_bearing_evaluations PRIVATE nvh_bearing nvh_warnings)
