# `cmake --install`: the gradmesh command (and gradmesh-imaging, which it runs, in
# libexec/gradmesh/), the static libraries under their gradmesh_ names,
# their headers under include/gradmesh/ (the umbrella header include/gradmesh/gradmesh.h), a
# CMake package (find_package(gradmesh), target gradmesh::gradmesh) and a pkg-config file.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

# In link order (a library before what it uses), as the pkg-config file lists them.
set(GRADMESH_LIBRARIES converters_pipeline converters_fit formats_all formats_mesh_readers
    formats_eps formats_pdf formats_mesh_shading formats_svg formats_gmb formats_raster
    formats_registry meshcore)
set(GRADMESH_HEADER_DIRS meshcore/include converters/include)
foreach(dir registry gmb svg eps pdf raster mesh_shading)
  list(APPEND GRADMESH_HEADER_DIRS formats/${dir}/include)
endforeach()

set(GRADMESH_PC_LIBS "")
foreach(lib ${GRADMESH_LIBRARIES})
  set_target_properties(${lib} PROPERTIES OUTPUT_NAME gradmesh_${lib})
  target_include_directories(${lib} INTERFACE
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/gradmesh>)
  string(APPEND GRADMESH_PC_LIBS " -lgradmesh_${lib}")
endforeach()

# The one target a program links: every library and the umbrella header.
add_library(gradmesh_library INTERFACE)
set_target_properties(gradmesh_library PROPERTIES EXPORT_NAME gradmesh)
target_link_libraries(gradmesh_library INTERFACE ${GRADMESH_LIBRARIES})
target_include_directories(gradmesh_library INTERFACE
  $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
add_library(gradmesh::gradmesh ALIAS gradmesh_library)

install(TARGETS gradmesh RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS gradmesh-imaging RUNTIME DESTINATION ${GRADMESH_IMAGING_DIR})
install(TARGETS ${GRADMESH_LIBRARIES} gradmesh_library EXPORT gradmeshTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
foreach(dir ${GRADMESH_HEADER_DIRS})
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${dir}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/gradmesh
          FILES_MATCHING PATTERN "*.h")
endforeach()
install(FILES ${PROJECT_SOURCE_DIR}/include/gradmesh/gradmesh.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/gradmesh)

set(GRADMESH_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/gradmesh)
install(EXPORT gradmeshTargets NAMESPACE gradmesh:: DESTINATION ${GRADMESH_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/gradmeshConfig.cmake.in
  ${PROJECT_BINARY_DIR}/gradmeshConfig.cmake INSTALL_DESTINATION ${GRADMESH_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/gradmeshConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/gradmeshConfig.cmake
        ${PROJECT_BINARY_DIR}/gradmeshConfigVersion.cmake DESTINATION ${GRADMESH_CMAKE_DIR})
configure_file(${PROJECT_SOURCE_DIR}/cmake/gradmesh.pc.in ${PROJECT_BINARY_DIR}/gradmesh.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/gradmesh.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
install(FILES ${GRADMESH_MAN_PAGE} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
install(FILES ${GRADMESH_BASH_COMPLETION} DESTINATION ${CMAKE_INSTALL_DATADIR}/bash-completion/completions
        RENAME gradmesh)
