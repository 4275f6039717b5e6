# Flexible bodies in solve (included by tests/solve/CMakeLists.txt).
nvh_add_test(solve_flexible_tests SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_flexible.cpp
  ${CMAKE_CURRENT_LIST_DIR}/test_jacobian_flexible.cpp LIBS nvh_solve nvh_condense)
# The valvetrain's flexible rocker, lever and pushrod (testdata/valvetrain/rocker.toml, lever.toml, pushrod.toml):
# condensed in the test, then run in the valvetrain scenes against closed forms.
nvh_add_test(flexible_rocker_tests SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_flexible_rocker.cpp
  ${CMAKE_CURRENT_LIST_DIR}/test_flexible_lever.cpp ${CMAKE_CURRENT_LIST_DIR}/test_flexible_pushrod.cpp
  LIBS nvh_solve nvh_condense)
# Centrifugal geometric stiffening of a flexible body against the rotating-beam reference.
nvh_add_test(geometric_stiffening_tests SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_geometric_stiffening.cpp
  ${CMAKE_CURRENT_LIST_DIR}/test_kane_spinup.cpp
  LIBS nvh_solve nvh_condense)
# A flexible body on a fixed axis (`axis`): the pinned-free rod against Blevins, the Jacobian, the same
# pendulum on a revolute joint, the errors.
nvh_add_test(flexible_rotor_tests SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_flexible_rotor.cpp LIBS nvh_solve nvh_condense)
