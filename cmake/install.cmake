# `cmake --install`: the libraries below the command line as one CMake package, used from another
# project as
#   find_package(woven 0.1 REQUIRED)
#   target_link_libraries(app PRIVATE woven::woven)
# The package is the static libraries woven_kes ... woven_render (exported as woven::kes ...
# woven::render), their headers under <prefix>/include/woven/ and woven-config.cmake, which finds
# the same Debian packages the build used (cmake/dependencies.cmake). Component `development`
# holds all of it (`cmake --install build --component development` installs the library alone).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(woven_exported woven_common woven_stb woven_cairo woven_cholmod woven_kes woven_geometry woven_model woven_sim
    woven_testers woven_analysis woven_io woven_render)
foreach(t IN LISTS woven_exported)
  string(REPLACE "woven_" "" name ${t})
  set_target_properties(${t} PROPERTIES EXPORT_NAME ${name})
endforeach()

# woven::woven: every library (an application links this one).
add_library(woven_library INTERFACE)
target_link_libraries(woven_library INTERFACE woven_io woven_render woven_testers woven_analysis)
set_target_properties(woven_library PROPERTIES EXPORT_NAME woven)
add_library(woven::woven ALIAS woven_library)

install(TARGETS ${woven_exported} woven_library EXPORT woven-targets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT development)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/src/woven/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/woven COMPONENT development
  FILES_MATCHING PATTERN "*.hpp"
  PATTERN cli EXCLUDE PATTERN app EXCLUDE PATTERN batch EXCLUDE)

set(woven_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/woven)
install(EXPORT woven-targets NAMESPACE woven:: DESTINATION ${woven_cmake_dir} COMPONENT development)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/woven-config.cmake.in
  ${PROJECT_BINARY_DIR}/woven-config.cmake INSTALL_DESTINATION ${woven_cmake_dir})
# 0.x: a minor version may change the interface, so only the same minor version is compatible.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/woven-config-version.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/woven-config.cmake ${PROJECT_BINARY_DIR}/woven-config-version.cmake
  DESTINATION ${woven_cmake_dir} COMPONENT development)
