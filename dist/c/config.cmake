# Writes omneeConfig.cmake and omneeConfigVersion.cmake into
# PREFIX/lib/cmake/omnee for the library cargo-c installed under PREFIX:
#   cmake -DPREFIX=... -DVERSION=0.1.0 -DSONAME=libomnee.so.0.1 -P dist/c/config.cmake
# (dist/build.sh). A 0.y version promises compatibility within 0.y.z only,
# as the SONAME does: SameMinorVersion.
foreach(var PREFIX VERSION SONAME)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "config.cmake: -D${var}=... is required")
  endif()
endforeach()
set(OMNEE_VERSION "${VERSION}")
set(OMNEE_SONAME "${SONAME}")
set(OMNEE_LIBRARY "libomnee.so.${VERSION}")
if(NOT EXISTS "${PREFIX}/lib/${OMNEE_LIBRARY}")
  message(FATAL_ERROR "config.cmake: no ${PREFIX}/lib/${OMNEE_LIBRARY}")
endif()
set(dir "${PREFIX}/lib/cmake/omnee")
configure_file("${CMAKE_CURRENT_LIST_DIR}/omneeConfig.cmake.in" "${dir}/omneeConfig.cmake" @ONLY)
include(CMakePackageConfigHelpers)
write_basic_package_version_file("${dir}/omneeConfigVersion.cmake"
  VERSION "${VERSION}" COMPATIBILITY SameMinorVersion)
