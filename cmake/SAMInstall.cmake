# What `cmake --install` puts under the prefix: the libraries SAM::core,
# SAM::build and SAM::runtime with their public headers (shaders are
# embedded in the runtime), the programs (sam_add_programs), a CMake package
# (find_package(SAM 0.1)) and a pkg-config file (sam.pc). The test
# tests/install builds a consumer against both.
include(CMakePackageConfigHelpers)
set(SAM_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/SAM)

set_target_properties(sam_core PROPERTIES EXPORT_NAME core)
set_target_properties(sam_builder PROPERTIES EXPORT_NAME build)
set_target_properties(sam_runtime PROPERTIES EXPORT_NAME runtime)
foreach(lib sam_core sam_builder sam_runtime)
  set_target_properties(${lib} PROPERTIES VERSION ${PROJECT_VERSION} SOVERSION ${PROJECT_VERSION_MAJOR})
endforeach()
if(NOT BUILD_SHARED_LIBS)
  # libsam_core.a holds C++ (the OpenMesh loader): a C program linking the
  # installed library needs the C++ runtime too. Only there: linking it
  # ahead of the sanitizer runtimes in this build's own programs broke
  # LeakSanitizer's exit scan (a bogus thread-local block) in sam_compare.
  target_link_libraries(sam_core INTERFACE "$<INSTALL_INTERFACE:stdc++>")
endif()

install(TARGETS sam_core sam_builder sam_runtime EXPORT SAMTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/sam_core/include/sam ${PROJECT_SOURCE_DIR}/sam_builder/include/sam
                  ${PROJECT_SOURCE_DIR}/sam_runtime/include/sam
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.h")
install(FILES ${PROJECT_BINARY_DIR}/generated/sam/sam_version.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/sam)

install(EXPORT SAMTargets NAMESPACE SAM:: DESTINATION ${SAM_CMAKE_DIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/SAMConfig.cmake.in ${PROJECT_BINARY_DIR}/SAMConfig.cmake
  INSTALL_DESTINATION ${SAM_CMAKE_DIR})
# 0.x: a minor release may change the API.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/SAMConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/SAMConfig.cmake ${PROJECT_BINARY_DIR}/SAMConfigVersion.cmake
              ${CMAKE_CURRENT_LIST_DIR}/SAMDependencies.cmake
  DESTINATION ${SAM_CMAKE_DIR})

# pkg-config finds the prefix from the file's own place, so an install
# under any --prefix works.
file(RELATIVE_PATH SAM_PC_TO_PREFIX /${CMAKE_INSTALL_LIBDIR}/pkgconfig /)
configure_file(${CMAKE_CURRENT_LIST_DIR}/sam.pc.in ${PROJECT_BINARY_DIR}/sam.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/sam.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
