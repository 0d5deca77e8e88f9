# What the SAM libraries link, found the same way by this project's build
# and by a project that uses an installed SAM (SAMConfig.cmake includes this
# file): a static libsam_*.a carries its private dependencies to the final
# link. All of them are Debian 12 packages (scripts/deps.sh).
include(CMakeFindDependencyMacro)
# Inside SAMConfig.cmake a missing one makes find_package(SAM) fail with its
# name; in this project's own build it stops the configuration.
macro(sam_dependency)
  if(CMAKE_FIND_PACKAGE_NAME STREQUAL "SAM")
    find_dependency(${ARGN})
  else()
    find_package(${ARGN} REQUIRED)
  endif()
endmacro()
sam_dependency(OpenMesh CONFIG)
sam_dependency(embree 3 CONFIG)
sam_dependency(OpenEXR 3 CONFIG)
sam_dependency(cJSON CONFIG)
sam_dependency(TinyGLTF CONFIG)
sam_dependency(meshoptimizer CONFIG)
sam_dependency(draco CONFIG)
sam_dependency(PNG)
sam_dependency(ZLIB)
sam_dependency(OpenMP)
sam_dependency(PkgConfig)
if(NOT TARGET PkgConfig::EPOXY)
  pkg_check_modules(EPOXY REQUIRED IMPORTED_TARGET GLOBAL epoxy)
endif()
if(NOT TARGET PkgConfig::STB)
  pkg_check_modules(STB REQUIRED IMPORTED_TARGET GLOBAL stb)
endif()

# Debian's cJSON config sets variables, not a target; wrap them in one.
if(NOT TARGET cjson)
  add_library(cjson INTERFACE IMPORTED GLOBAL)
  set_target_properties(cjson PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${CJSON_INCLUDE_DIRS}"
    INTERFACE_LINK_LIBRARIES "${CJSON_LIBRARIES}")
endif()
