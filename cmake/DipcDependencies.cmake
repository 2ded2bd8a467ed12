# Finds dipc's dependencies and exposes them as imported targets:
#   MPI::MPI_CXX, dipc::petsc, dipc::metis, dipc::hdf5 (parallel only), nlohmann_json, GTest (tests only).
# PETSc: PETSC_DIR/PETSC_ARCH if set, otherwise PETSc.pc on PKG_CONFIG_PATH (Debian: petsc-dev).

find_package(MPI REQUIRED COMPONENTS C CXX)
find_package(PkgConfig REQUIRED)

# --- PETSc (>= 3.18) -------------------------------------------------------
if(DEFINED ENV{PETSC_DIR} AND NOT "$ENV{PETSC_DIR}" STREQUAL "")
  set(_petsc_pc_dirs "$ENV{PETSC_DIR}/$ENV{PETSC_ARCH}/lib/pkgconfig" "$ENV{PETSC_DIR}/lib/pkgconfig")
  set(ENV{PKG_CONFIG_PATH} "${_petsc_pc_dirs};$ENV{PKG_CONFIG_PATH}")
  string(REPLACE ";" ":" _pc "$ENV{PKG_CONFIG_PATH}")
  set(ENV{PKG_CONFIG_PATH} "${_pc}")
endif()
pkg_check_modules(PETSC REQUIRED IMPORTED_TARGET PETSc>=3.18)
add_library(dipc::petsc ALIAS PkgConfig::PETSC)
message(STATUS "dipc: PETSc ${PETSC_VERSION} from ${PETSC_PREFIX}")
# hypre itself, beside PETSc: the device hypre matrix (src/nonlinear/direct_matrix.cpp) calls
# hypre's ParCSR functions directly, which PETSc's pkg-config does not list.
find_library(DIPC_HYPRE_LIBRARY NAMES HYPRE HINTS ${PETSC_LIBRARY_DIRS} ${PETSC_PREFIX}/lib NO_DEFAULT_PATH)
if(NOT DIPC_HYPRE_LIBRARY)
  find_library(DIPC_HYPRE_LIBRARY NAMES HYPRE)
endif()
if(DIPC_HYPRE_LIBRARY)
  target_link_libraries(PkgConfig::PETSC INTERFACE "${DIPC_HYPRE_LIBRARY}")
endif()

# --- METIS 5 -----------------------------------------------------------------
find_path(METIS_INCLUDE_DIR metis.h PATH_SUFFIXES metis HINTS ENV METIS_DIR PATH_SUFFIXES include)
find_library(METIS_LIBRARY metis HINTS ENV METIS_DIR PATH_SUFFIXES lib)
if(NOT METIS_INCLUDE_DIR OR NOT METIS_LIBRARY)
  message(FATAL_ERROR "dipc: METIS 5 not found (Debian: apt-get install libmetis-dev; or set METIS_DIR)")
endif()
add_library(dipc::metis UNKNOWN IMPORTED)
set_target_properties(dipc::metis PROPERTIES IMPORTED_LOCATION "${METIS_LIBRARY}"
                      INTERFACE_INCLUDE_DIRECTORIES "${METIS_INCLUDE_DIR}")

# --- parallel HDF5 -------------------------------------------------------------
# Debian installs the Open MPI flavour under hdf5/openmpi; prefer it and refuse a serial HDF5,
# because dipc writes one file collectively from all ranks.
set(HDF5_PREFER_PARALLEL TRUE)
pkg_check_modules(HDF5_OMPI QUIET IMPORTED_TARGET hdf5-openmpi)
if(HDF5_OMPI_FOUND)
  add_library(dipc::hdf5 ALIAS PkgConfig::HDF5_OMPI)
  set(_hdf5_inc "${HDF5_OMPI_INCLUDE_DIRS}")
else()
  find_package(HDF5 REQUIRED COMPONENTS C)
  if(NOT HDF5_IS_PARALLEL)
    message(FATAL_ERROR "dipc: found a serial HDF5 (${HDF5_C_LIBRARIES}); dipc needs parallel HDF5 "
                        "(Debian: apt-get install libhdf5-openmpi-dev)")
  endif()
  add_library(dipc_hdf5_iface INTERFACE)
  target_include_directories(dipc_hdf5_iface INTERFACE ${HDF5_C_INCLUDE_DIRS})
  target_link_libraries(dipc_hdf5_iface INTERFACE ${HDF5_C_LIBRARIES})
  add_library(dipc::hdf5 ALIAS dipc_hdf5_iface)
  set(_hdf5_inc "${HDF5_C_INCLUDE_DIRS}")
endif()
include(CheckSymbolExists)
set(CMAKE_REQUIRED_INCLUDES ${_hdf5_inc} ${MPI_C_INCLUDE_DIRS})
check_symbol_exists(H5_HAVE_PARALLEL "H5pubconf.h" DIPC_HDF5_IS_PARALLEL)
unset(CMAKE_REQUIRED_INCLUDES)
if(NOT DIPC_HDF5_IS_PARALLEL)
  message(FATAL_ERROR "dipc: the HDF5 found (${_hdf5_inc}) is not built with MPI; dipc needs parallel HDF5")
endif()

# --- JSON, GoogleTest -------------------------------------------------------
find_package(nlohmann_json 3.9 REQUIRED)
if(DIPC_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
