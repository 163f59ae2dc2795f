# Installation and packaging (included by the top-level CMakeLists.txt after the targets exist):
#   include/weft/*.h                         the public headers
#   lib/libweft.so.10.x.y, .so.10, .so         the plugin (SONAME libweft.so.10 = the ABI number)
#   lib/pkgconfig/weft.pc                     pkg-config (relocatable: paths from ${pcfiledir})
#   lib/cmake/weft/weftConfig.cmake, weftConfigVersion.cmake, weftTargets*.cmake
#                                             find_package(weft) -> weft::weft
#   bin/weft                                  the command-line tool
#   share/weft/host_glue/                     loader sources, engine-loop example, Python bindings
#                                             (a pip package), Blender add-on
# (lib/ is CMAKE_INSTALL_LIBDIR: lib/<multiarch> for a /usr prefix on Debian.)
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

add_library(weft::weft ALIAS weft)   # the same name inside this build as for consumers

install(TARGETS weft EXPORT weftTargets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} NAMELINK_COMPONENT Development
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/plugin/include/weft
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.h")
install(TARGETS weft_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

set(WEFT_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/weft)
install(EXPORT weftTargets NAMESPACE weft:: DESTINATION ${WEFT_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/weftConfig.cmake.in
  ${PROJECT_BINARY_DIR}/weftConfig.cmake INSTALL_DESTINATION ${WEFT_CMAKE_DIR})
# 0.x: a minor version may break the ABI (WEFT_ABI), so only the same major.minor is compatible.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/weftConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/weftConfig.cmake ${PROJECT_BINARY_DIR}/weftConfigVersion.cmake
  DESTINATION ${WEFT_CMAKE_DIR})

# pkg-config file, relative to its own folder so that `cmake --install --prefix P` works.
set(WEFT_PC_DIR ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
file(RELATIVE_PATH WEFT_PC_TO_PREFIX /prefix/${WEFT_PC_DIR} /prefix)
string(REGEX REPLACE "/$" "" WEFT_PC_TO_PREFIX "${WEFT_PC_TO_PREFIX}")
foreach(dir LIBDIR INCLUDEDIR)
  if(IS_ABSOLUTE "${CMAKE_INSTALL_${dir}}")
    set(WEFT_PC_${dir} "${CMAKE_INSTALL_${dir}}")
  else()
    set(WEFT_PC_${dir} "\${prefix}/${CMAKE_INSTALL_${dir}}")
  endif()
endforeach()
configure_file(${PROJECT_SOURCE_DIR}/cmake/weft.pc.in ${PROJECT_BINARY_DIR}/weft.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/weft.pc DESTINATION ${WEFT_PC_DIR})

# host_glue, as sources: hosts copy the loader, put python/ on PYTHONPATH, install the add-on.
set(WEFT_GLUE_DIR ${CMAKE_INSTALL_DATADIR}/weft/host_glue)
install(FILES ${PROJECT_SOURCE_DIR}/host_glue/README.md DESTINATION ${WEFT_GLUE_DIR})
install(FILES ${PROJECT_SOURCE_DIR}/host_glue/loader/weft_loader.h
  ${PROJECT_SOURCE_DIR}/host_glue/loader/weft_loader_functions.h
  ${PROJECT_SOURCE_DIR}/host_glue/loader/weft_loader.c DESTINATION ${WEFT_GLUE_DIR}/loader)
install(FILES ${PROJECT_SOURCE_DIR}/host_glue/examples/engine_loop.c
  ${PROJECT_SOURCE_DIR}/host_glue/examples/character.h
  ${PROJECT_SOURCE_DIR}/host_glue/examples/character.c
  ${PROJECT_SOURCE_DIR}/host_glue/examples/toy_engine.h
  ${PROJECT_SOURCE_DIR}/host_glue/examples/toy_engine.c DESTINATION ${WEFT_GLUE_DIR}/examples)
install(FILES ${PROJECT_SOURCE_DIR}/host_glue/python/weft/__init__.py ${PROJECT_SOURCE_DIR}/host_glue/python/weft/_abi.py
  DESTINATION ${WEFT_GLUE_DIR}/python/weft)
install(FILES ${PROJECT_SOURCE_DIR}/host_glue/python/pyproject.toml
  ${PROJECT_SOURCE_DIR}/host_glue/python/setup.py DESTINATION ${WEFT_GLUE_DIR}/python)
install(FILES ${PROJECT_SOURCE_DIR}/host_glue/blender/weft_blender.py
  DESTINATION ${WEFT_GLUE_DIR}/blender)
