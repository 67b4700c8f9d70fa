# install(): the libraries another project links, as an exported CMake package.
#   cmake --install build --prefix /opt/demcal
#   find_package(demcal REQUIRED)   # with CMAKE_PREFIX_PATH=/opt/demcal
#   target_link_libraries(app PRIVATE demcal::surrogate demcal::calibrate)
# examples/fit-and-calibrate/ is such a project; the ctest `install_example`
# installs into a temporary prefix and builds and runs it.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(DEMCAL_EXPORTED_LIBRARIES io dem surrogate calibrate config engines study)
foreach(lib IN LISTS DEMCAL_EXPORTED_LIBRARIES)
  # In the build tree the headers are found from the source root, installed
  # under include/demcal, both as "<library>/<header>.hpp".
  set_target_properties(demcal_${lib} PROPERTIES
    EXPORT_NAME ${lib}
    INTERFACE_INCLUDE_DIRECTORIES
      "$<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>;$<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/demcal>")
  install(TARGETS demcal_${lib} EXPORT demcalTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${lib}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/demcal/${lib}
          FILES_MATCHING PATTERN "*.hpp")
  add_library(demcal::${lib} ALIAS demcal_${lib})
endforeach()
install(TARGETS demcal RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

install(EXPORT demcalTargets NAMESPACE demcal:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/demcal)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/demcalConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/demcalConfig.cmake
                              INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/demcal)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/demcalConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/demcalConfig.cmake ${PROJECT_BINARY_DIR}/demcalConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/demcal)
