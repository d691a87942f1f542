# Fails the build when a file of one wing of the host libraries includes a header of a wing above
# it (io < signals < run < bus < cli): the libraries link in that order, and an upward include
# would make a lower wing depend on a higher one. Run by sim_host/CMakeLists.txt:
#   cmake -DSOURCE_DIR=<sim_host> -DSTAMP=<file touched on success> -P check_wing_includes.cmake
set(wings io signals run bus cli)
set(violations "")
foreach(wing IN LISTS wings)
  list(FIND wings ${wing} rank)
  file(GLOB_RECURSE files "${SOURCE_DIR}/src/${wing}/*.[ch]pp"
       "${SOURCE_DIR}/include/stickslip/host/${wing}/*.hpp")
  foreach(file IN LISTS files)
    file(STRINGS "${file}" includes REGEX "^#include \"stickslip/host/[a-z]+/")
    foreach(line IN LISTS includes)
      string(REGEX REPLACE "^#include \"stickslip/host/([a-z]+)/.*" "\\1" included "${line}")
      list(FIND wings ${included} included_rank)
      if(included_rank GREATER rank)
        file(RELATIVE_PATH shown "${SOURCE_DIR}" "${file}")
        list(APPEND violations "  ${shown} (${wing}) includes ${included}: ${line}")
      endif()
    endforeach()
  endforeach()
endforeach()
if(violations)
  list(JOIN violations "\n" text)
  message(FATAL_ERROR "sim_host: includes against the wings' direction (io < signals < run < "
                      "bus < cli):\n${text}")
endif()
file(TOUCH "${STAMP}")
