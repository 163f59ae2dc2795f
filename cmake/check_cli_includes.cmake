# The `weft` tool (plugin/cli) uses the public API only: none of its files may include a header
# of core/ or gpu/. weft_check_cli_includes(CLI_DIR CORE_DIR GPU_DIR) scans every .c and .h under
# CLI_DIR for quoted includes and stops the configuration with the offending file and header
# named. The same check runs as a script (a ctest test):
#   cmake -DCLI_DIR=... -DCORE_DIR=... -DGPU_DIR=... -P check_cli_includes.cmake
# A header is the tool's own when a file of that name is under CLI_DIR (those win); weft/*.h is
# the public API.
if(CMAKE_SCRIPT_MODE_FILE)
  cmake_minimum_required(VERSION 3.20)   # the policies of the project (IN_LIST) in script mode
endif()

function(weft_cli_include_violations cli_dir core_dir gpu_dir out_var)
  file(GLOB_RECURSE own_headers "${cli_dir}/*.h")
  set(own "")
  foreach(h ${own_headers})
    get_filename_component(name ${h} NAME)
    list(APPEND own ${name})
  endforeach()
  file(GLOB_RECURSE inner_headers "${core_dir}/*.h" "${gpu_dir}/*.h")
  set(inner "")
  foreach(h ${inner_headers})
    get_filename_component(name ${h} NAME)
    file(RELATIVE_PATH rel "${core_dir}/.." ${h})
    list(APPEND inner ${name})
    set(where_${name} ${rel})
  endforeach()
  file(GLOB_RECURSE sources "${cli_dir}/*.c" "${cli_dir}/*.h")
  set(bad "")
  foreach(src ${sources})
    file(STRINGS ${src} lines REGEX "^[ \t]*#[ \t]*include[ \t]*\"")
    foreach(line ${lines})
      string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*\"([^\"]+)\".*" "\\1" inc "${line}")
      get_filename_component(name "${inc}" NAME)
      if(inc MATCHES "^weft/" OR name IN_LIST own)
        continue()
      endif()
      if(name IN_LIST inner)
        file(RELATIVE_PATH rel_src "${cli_dir}/../.." ${src})
        list(APPEND bad "${rel_src}: includes ${where_${name}}")
      endif()
    endforeach()
  endforeach()
  set(${out_var} "${bad}" PARENT_SCOPE)
endfunction()

function(weft_check_cli_includes cli_dir core_dir gpu_dir)
  weft_cli_include_violations(${cli_dir} ${core_dir} ${gpu_dir} bad)
  if(bad)
    string(REPLACE ";" "\n  " text "${bad}")
    message(FATAL_ERROR "the weft tool must use weft.h only (docs/design/tool.md):\n  ${text}")
  endif()
endfunction()

if(CMAKE_SCRIPT_MODE_FILE AND CLI_DIR)
  weft_check_cli_includes(${CLI_DIR} ${CORE_DIR} ${GPU_DIR})
  message(STATUS "no core/ or gpu/ header included under ${CLI_DIR}")
endif()
