# Installs gimg as a CMake package: find_package(gimg) gives gimg::engine, gimg::geometry and
# gimg::passes.
include(CMakePackageConfigHelpers)
install(TARGETS gimg_engine gimg_geometry gimg_passes EXPORT gimgTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(EXPORT gimgTargets NAMESPACE gimg:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/gimg)
configure_package_config_file("${PROJECT_SOURCE_DIR}/cmake/gimgConfig.cmake.in"
  "${PROJECT_BINARY_DIR}/gimgConfig.cmake" INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/gimg)
write_basic_package_version_file("${PROJECT_BINARY_DIR}/gimgConfigVersion.cmake"
  COMPATIBILITY SameMinorVersion)
install(FILES "${PROJECT_BINARY_DIR}/gimgConfig.cmake" "${PROJECT_BINARY_DIR}/gimgConfigVersion.cmake"
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/gimg)
