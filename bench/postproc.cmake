# postproc benchmark (bench/postproc_bench.py): spectrum, 1/3-octave filter bank and order analysis of a
# 10-minute, 51.2 kHz signal against SciPy doing the same work; time, peak memory and their ratio.
#   cmake --build BUILD --target bench_postproc        (or: /usr/bin/python3 bench/postproc_bench.py --build BUILD)
add_custom_target(bench_postproc
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/postproc_bench.py --build ${PROJECT_BINARY_DIR}
  DEPENDS postproc
  USES_TERMINAL
  COMMENT "postproc against SciPy on a 10-minute signal at 51.2 kHz")
