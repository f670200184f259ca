# FindCHOLMOD: SuiteSparse's CHOLMOD (Debian libsuitesparse-dev ships no CMake config).
# Defines the imported target slamkit_deps::CHOLMOD, CHOLMOD_FOUND, CHOLMOD_VERSION,
# CHOLMOD_HAS_METIS and SLAMKIT_BLAS_LIBRARY (the BLAS that libblas.so.3 resolves to).
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(CHOLMOD_LIBRARY cholmod)
find_library(CHOLMOD_AMD_LIBRARY amd)
find_library(CHOLMOD_CAMD_LIBRARY camd)
find_library(CHOLMOD_COLAMD_LIBRARY colamd)
find_library(CHOLMOD_CCOLAMD_LIBRARY ccolamd)
find_library(CHOLMOD_CONFIG_LIBRARY suitesparseconfig)
find_library(CHOLMOD_METIS_LIBRARY metis)

if(CHOLMOD_INCLUDE_DIR AND EXISTS "${CHOLMOD_INCLUDE_DIR}/cholmod_core.h")
  file(STRINGS "${CHOLMOD_INCLUDE_DIR}/cholmod_core.h" _v REGEX "#define CHOLMOD_(MAIN|SUB|SUBSUB)_VERSION +[0-9]+")
  string(REGEX REPLACE ".*MAIN_VERSION +([0-9]+).*" "\\1" _maj "${_v}")
  string(REGEX REPLACE ".*SUB_VERSION +([0-9]+).*SUBSUB.*" "\\1" _min "${_v}")
  string(REGEX REPLACE ".*SUBSUB_VERSION +([0-9]+).*" "\\1" _pat "${_v}")
  set(CHOLMOD_VERSION "${_maj}.${_min}.${_pat}")
endif()

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(CHOLMOD
  REQUIRED_VARS CHOLMOD_LIBRARY CHOLMOD_INCLUDE_DIR CHOLMOD_AMD_LIBRARY CHOLMOD_COLAMD_LIBRARY CHOLMOD_CONFIG_LIBRARY
  VERSION_VAR CHOLMOD_VERSION)

if(CHOLMOD_FOUND AND NOT TARGET slamkit_deps::CHOLMOD)
  add_library(slamkit_deps::CHOLMOD UNKNOWN IMPORTED)
  set(_deps ${CHOLMOD_AMD_LIBRARY} ${CHOLMOD_COLAMD_LIBRARY} ${CHOLMOD_CONFIG_LIBRARY})
  foreach(_lib CHOLMOD_CAMD_LIBRARY CHOLMOD_CCOLAMD_LIBRARY CHOLMOD_METIS_LIBRARY)
    if(${_lib})
      list(APPEND _deps ${${_lib}})
    endif()
  endforeach()
  set_target_properties(slamkit_deps::CHOLMOD PROPERTIES
    IMPORTED_LOCATION "${CHOLMOD_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${CHOLMOD_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${_deps}")
endif()
set(CHOLMOD_HAS_METIS FALSE)
if(CHOLMOD_METIS_LIBRARY)
  set(CHOLMOD_HAS_METIS TRUE)
endif()

# Which BLAS will CHOLMOD's supernodal kernels run on? libcholmod links libblas.so.3, which
# Debian's alternatives point to OpenBLAS, ATLAS or the reference BLAS.
find_file(SLAMKIT_BLAS_SONAME libblas.so.3 PATHS /usr/lib/${CMAKE_LIBRARY_ARCHITECTURE} /usr/lib NO_DEFAULT_PATH)
if(SLAMKIT_BLAS_SONAME)
  get_filename_component(SLAMKIT_BLAS_LIBRARY "${SLAMKIT_BLAS_SONAME}" REALPATH)
endif()
mark_as_advanced(CHOLMOD_INCLUDE_DIR CHOLMOD_LIBRARY CHOLMOD_AMD_LIBRARY CHOLMOD_CAMD_LIBRARY
  CHOLMOD_COLAMD_LIBRARY CHOLMOD_CCOLAMD_LIBRARY CHOLMOD_CONFIG_LIBRARY CHOLMOD_METIS_LIBRARY SLAMKIT_BLAS_SONAME)
