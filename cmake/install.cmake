# `cmake --install`: the four libraries with their headers as pbs::raster, pbs::scene, pbs::surfels and
# pbs::evaluation for find_package(pbs), the `pbs` command and its image plug-in beside it, and the licence.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(PBS_CONFIG_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/pbs)
foreach(module raster scene surfels evaluation)
  set_target_properties(pbs_${module} PROPERTIES EXPORT_NAME ${module})
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${module}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endforeach()
install(FILES ${PBS_GENERATED_INCLUDE_DIR}/pbs/version.hpp DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/pbs)
install(TARGETS pbs_raster pbs_scene pbs_surfels pbs_evaluation EXPORT pbsTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
# The command finds its plug-in beside its own binary.
install(TARGETS pbs RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS pbs_image_io LIBRARY DESTINATION ${CMAKE_INSTALL_BINDIR})
install(EXPORT pbsTargets NAMESPACE pbs:: DESTINATION ${PBS_CONFIG_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/pbsConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/pbsConfig.cmake INSTALL_DESTINATION ${PBS_CONFIG_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/pbsConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/pbsConfig.cmake ${PROJECT_BINARY_DIR}/pbsConfigVersion.cmake
        DESTINATION ${PBS_CONFIG_DIR})
install(FILES ${PROJECT_SOURCE_DIR}/LICENSE DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/pbs)
