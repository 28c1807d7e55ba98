# The installed CMake package: `find_package(effigi CONFIG REQUIRED)` in a plugin project
# gives the imported targets effigi::effigi (libeffigi and the public headers),
# effigi::conformance (the check library), effigi::cli and effigi::conform (the two
# programs) and the function effigi_add_component (cmake/EffigiComponent.cmake).
# Every path in it is relative to the install prefix, so an install can be moved.
include(CMakePackageConfigHelpers)

set(EFFIGI_CMAKE_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/effigi)
install(EXPORT effigiTargets NAMESPACE effigi:: DESTINATION ${EFFIGI_CMAKE_INSTALL_DIR} FILE effigiTargets.cmake)
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/effigiConfig.cmake.in
  ${CMAKE_BINARY_DIR}/cmake/effigiConfig.cmake
  INSTALL_DESTINATION ${EFFIGI_CMAKE_INSTALL_DIR}
  PATH_VARS CMAKE_INSTALL_INCLUDEDIR CMAKE_INSTALL_LIBDIR CMAKE_INSTALL_DATADIR)
# Before 1.0 a minor version may break the plugin ABI.
write_basic_package_version_file(${CMAKE_BINARY_DIR}/cmake/effigiConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES
  ${CMAKE_BINARY_DIR}/cmake/effigiConfig.cmake
  ${CMAKE_BINARY_DIR}/cmake/effigiConfigVersion.cmake
  ${CMAKE_CURRENT_LIST_DIR}/EffigiComponent.cmake
  DESTINATION ${EFFIGI_CMAKE_INSTALL_DIR})
