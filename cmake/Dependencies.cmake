# How each Debian package is found: see ../shared/notes/debian-packages.md (kept in docs/build.md).
find_package(Eigen3 3.4 REQUIRED CONFIG)
find_package(Spectra 1.0 REQUIRED CONFIG)
find_package(CLI11 REQUIRED CONFIG)
find_package(toml11 REQUIRED CONFIG)
# libcrypto (libssl-dev): SHA-256 of the provenance (common/sha256.cpp), target OpenSSL::Crypto.
find_package(OpenSSL REQUIRED COMPONENTS Crypto)

# The serial HDF5 (the MPI build comes in with SUNDIALS; never use pkg-config "hdf5").
find_package(HDF5 REQUIRED COMPONENTS C)
if(HDF5_IS_PARALLEL)
  message(FATAL_ERROR "Found the parallel (MPI) HDF5 at ${HDF5_INCLUDE_DIRS}; the serial one is needed "
                      "(Debian: libhdf5-dev puts it in /usr/include/hdf5/serial).")
endif()

find_package(PkgConfig REQUIRED)
pkg_check_modules(ARPACK REQUIRED IMPORTED_TARGET arpack)

# CHOLMOD (SuiteSparse): headers in /usr/include/suitesparse, used through Eigen's CholmodSupport.
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse REQUIRED)
find_library(CHOLMOD_LIBRARY cholmod REQUIRED)
find_library(SUITESPARSECONFIG_LIBRARY suitesparseconfig REQUIRED)
add_library(nvh_cholmod INTERFACE)
target_include_directories(nvh_cholmod SYSTEM INTERFACE ${CHOLMOD_INCLUDE_DIR})
target_link_libraries(nvh_cholmod INTERFACE ${CHOLMOD_LIBRARY} ${SUITESPARSECONFIG_LIBRARY})

# KLU (SuiteSparse; sparse LU for circuit-like and Reynolds matrices), used directly by solve/bearing.
find_library(KLU_LIBRARY klu REQUIRED)
find_library(AMD_LIBRARY amd REQUIRED)
find_library(COLAMD_LIBRARY colamd REQUIRED)
find_library(BTF_LIBRARY btf REQUIRED)
add_library(nvh_klu INTERFACE)
target_include_directories(nvh_klu SYSTEM INTERFACE ${CHOLMOD_INCLUDE_DIR})
target_link_libraries(nvh_klu INTERFACE ${KLU_LIBRARY} ${AMD_LIBRARY} ${COLAMD_LIBRARY} ${BTF_LIBRARY}
                                        ${SUITESPARSECONFIG_LIBRARY})

# gmsh (in-process meshing, condense/gmsh_mesh.cpp): Debian's libgmsh-dev has the header gmsh.h and
# libgmsh.so only (no CMake config, no pkg-config file).
find_path(GMSH_INCLUDE_DIR gmsh.h REQUIRED)
find_library(GMSH_LIBRARY gmsh REQUIRED)
add_library(nvh_gmsh INTERFACE)
target_include_directories(nvh_gmsh SYSTEM INTERFACE ${GMSH_INCLUDE_DIR})
target_link_libraries(nvh_gmsh INTERFACE ${GMSH_LIBRARY})

# SUNDIALS (solve's IDA integrator with the KLU sparse direct solver). Its CMake config needs OpenMP for C,
# hence LANGUAGES C CXX in the top-level project().
find_package(SUNDIALS 6.4 REQUIRED CONFIG
             COMPONENTS ida nvecserial sunmatrixdense sunmatrixsparse sunlinsoldense sunlinsolklu)

# LAPACK (solve's dense LU of IDA's Newton matrix, solve/newton_matrix_solver.cpp): Debian's liblapack-dev,
# which libopenblas0-serial serves through the liblapack.so.3 alternative (OpenBLAS's blocked dgetrf).
find_package(LAPACK REQUIRED)

# FFTW (postproc's spectra): pkg-config only.
pkg_check_modules(FFTW3 REQUIRED IMPORTED_TARGET fftw3)

# METIS (fill-reducing orderings): header metis.h and libmetis.so only; idx_t is 32-bit.
find_path(METIS_INCLUDE_DIR metis.h REQUIRED)
find_library(METIS_LIBRARY metis REQUIRED)
add_library(nvh_metis INTERFACE)
target_include_directories(nvh_metis SYSTEM INTERFACE ${METIS_INCLUDE_DIR})
target_link_libraries(nvh_metis INTERFACE ${METIS_LIBRARY})

if(NVH_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
