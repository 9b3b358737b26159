# install() and an exported CMake package: a downstream project writes
#   find_package(hertzgear REQUIRED)
#   target_link_libraries(my_tool PRIVATE hertzgear::hertzgear_dynamics)
include(CMakePackageConfigHelpers)

set(_hg_targets hertzgear_common hertzgear_table hertzgear_dynamics hertzgear_geometry
                hertzgear_contact hertzgear_stiffness)
if(HERTZGEAR_WITH_FEM)
  list(APPEND _hg_targets hertzgear_meshing hertzgear_fem hertzgear_dealii hertzgear_gmsh)
  install(TARGETS hertzgear RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()

install(TARGETS ${_hg_targets} EXPORT hertzgearTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
foreach(_dir common table dynamics meshing contact stiffness fem)
  if(NOT _dir STREQUAL "fem" OR HERTZGEAR_WITH_FEM)
    install(DIRECTORY ${CMAKE_SOURCE_DIR}/${_dir}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/hertzgear/${_dir}
            FILES_MATCHING PATTERN "*.h")
  endif()
endforeach()
install(FILES ${HERTZGEAR_VERSION_H} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/hertzgear)
install(DIRECTORY ${CMAKE_SOURCE_DIR}/data/ DESTINATION ${CMAKE_INSTALL_DATADIR}/hertzgear)
if(HERTZGEAR_WITH_FEM)
  # The report and the figures of the accuracy and validation studies (app/scripts.h).
  install(PROGRAMS ${CMAKE_SOURCE_DIR}/scripts/hertzgear_report.py
                   ${CMAKE_SOURCE_DIR}/scripts/plot_accuracy_dynamics.py
                   ${CMAKE_SOURCE_DIR}/scripts/plot_accuracy_stiffness.py
                   ${CMAKE_SOURCE_DIR}/scripts/plot_hertz_validation.py
          DESTINATION ${CMAKE_INSTALL_DATADIR}/hertzgear/scripts)
  # The modules of the report script, beside it (it imports them from its own folder).
  install(DIRECTORY ${CMAKE_SOURCE_DIR}/scripts/hertzgear_report_lib
          DESTINATION ${CMAKE_INSTALL_DATADIR}/hertzgear/scripts
          FILES_MATCHING PATTERN "*.py"
          PATTERN "__pycache__" EXCLUDE)
endif()

set(_cfgdir ${CMAKE_INSTALL_LIBDIR}/cmake/hertzgear)
install(EXPORT hertzgearTargets NAMESPACE hertzgear:: DESTINATION ${_cfgdir})
set(HERTZGEAR_CONFIG_WITH_FEM ${HERTZGEAR_WITH_FEM})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/hertzgearConfig.cmake.in
  ${CMAKE_BINARY_DIR}/hertzgearConfig.cmake INSTALL_DESTINATION ${_cfgdir})
write_basic_package_version_file(${CMAKE_BINARY_DIR}/hertzgearConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMajorVersion)
install(FILES ${CMAKE_BINARY_DIR}/hertzgearConfig.cmake ${CMAKE_BINARY_DIR}/hertzgearConfigVersion.cmake
        DESTINATION ${_cfgdir})
