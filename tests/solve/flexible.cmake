# Flexible bodies in solve (included by tests/solve/CMakeLists.txt).
nvh_add_test(solve_flexible_tests SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_flexible.cpp
  ${CMAKE_CURRENT_LIST_DIR}/test_jacobian_flexible.cpp LIBS nvh_solve nvh_condense)
