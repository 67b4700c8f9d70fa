# Writes the header that names the build (study/run_record.cpp, bench/pile_benchmark.cpp):
# "<project version>+<git describe --always --dirty>", or the project version alone outside
# a git checkout. Run by the target demcal_version at every build, not once at configure
# time, so that an incremental build after a commit or an edit records the tree it was
# built from; the header is replaced only when the text changes, so an unchanged tree
# recompiles nothing.
#   cmake -DSOURCE_DIR=... -DOUTPUT=... -DPROJECT_VERSION=... [-DGIT_EXECUTABLE=...] -P version.cmake
set(version "${PROJECT_VERSION}")
if(GIT_EXECUTABLE)
  execute_process(COMMAND ${GIT_EXECUTABLE} describe --always --dirty
                  WORKING_DIRECTORY ${SOURCE_DIR}
                  OUTPUT_VARIABLE describe OUTPUT_STRIP_TRAILING_WHITESPACE
                  ERROR_QUIET)
  if(describe)
    set(version "${PROJECT_VERSION}+${describe}")
  endif()
endif()
set(text "// Written by cmake/version.cmake at build time; do not edit.\n#pragma once\n#define DEMCAL_VERSION \"${version}\"\n")
if(EXISTS "${OUTPUT}")
  file(READ "${OUTPUT}" old)
endif()
if(NOT old STREQUAL text)
  file(WRITE "${OUTPUT}" "${text}")
endif()
