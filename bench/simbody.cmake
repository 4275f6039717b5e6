# The peer benchmark against Simbody (bench/run_simbody_bench.sh): built only when Simbody is found
# (Debian: libsimbody-dev installs /usr/lib/x86_64-linux-gnu/cmake/simbody/SimbodyConfig.cmake, which
# defines the imported targets SimTKcommon, SimTKmath, SimTKsimbody and Simbody_INCLUDE_DIR).
find_package(Simbody QUIET CONFIG)
if(Simbody_FOUND)
  add_executable(simbody_slider_crank_free ${CMAKE_CURRENT_SOURCE_DIR}/simbody/simbody_slider_crank_free.cpp)
  target_include_directories(simbody_slider_crank_free SYSTEM PRIVATE ${Simbody_INCLUDE_DIR})
  target_link_libraries(simbody_slider_crank_free PRIVATE ${Simbody_LIBRARIES})
  # Simbody 3.7's headers do not compile as C++20 (ambiguous reversed operator== of its type ids).
  set_target_properties(simbody_slider_crank_free PROPERTIES CXX_STANDARD 17 CXX_STANDARD_REQUIRED ON)
  message(STATUS "Simbody ${Simbody_VERSION}: building the peer benchmark simbody_slider_crank_free")
else()
  message(STATUS "Simbody not found (Debian: libsimbody-dev): the peer benchmark simbody_slider_crank_free is not built")
endif()
