# Module helper: slamkit_add_module(<name> SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# creates the library slamkit_<name>, its alias slamkit::<name>, and installs it in the export set.

if(CHOLMOD_FOUND)
  set(SLAMKIT_SPARSE_BACKEND "CHOLMOD ${CHOLMOD_VERSION} supernodal (METIS: ${CHOLMOD_HAS_METIS}), Eigen SimplicialLDLT fallback")
else()
  set(SLAMKIT_SPARSE_BACKEND "Eigen SimplicialLDLT ONLY - CHOLMOD not found, expect slow solves (install libsuitesparse-dev)")
  message(WARNING "CHOLMOD not found: slamkit falls back to Eigen's sparse LDLT, which is much slower.")
endif()
if(SLAMKIT_BLAS_LIBRARY MATCHES "openblas")
  set(SLAMKIT_BLAS_DESCRIPTION "OpenBLAS (${SLAMKIT_BLAS_LIBRARY})")
elseif(SLAMKIT_BLAS_LIBRARY)
  set(SLAMKIT_BLAS_DESCRIPTION "${SLAMKIT_BLAS_LIBRARY} (not OpenBLAS: CHOLMOD supernodal will be slower; run scripts/install-deps.sh)")
else()
  set(SLAMKIT_BLAS_DESCRIPTION "unknown")
endif()
set(SLAMKIT_PARALLEL_BACKEND "std::thread pool (slamkit/core/parallel.h)")

function(slamkit_add_module name)
  cmake_parse_arguments(M "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(slamkit_${name} ${M_SOURCES})
  add_library(slamkit::${name} ALIAS slamkit_${name})
  set_target_properties(slamkit_${name} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME slamkit_${name})
  target_include_directories(slamkit_${name} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
    $<BUILD_INTERFACE:${PROJECT_BINARY_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_compile_features(slamkit_${name} PUBLIC cxx_std_17)
  target_compile_options(slamkit_${name} PRIVATE $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wpedantic>)
  target_link_libraries(slamkit_${name} PUBLIC ${M_PUBLIC_DEPS} PRIVATE ${M_PRIVATE_DEPS})
  install(TARGETS slamkit_${name} EXPORT slamkitTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
endfunction()
