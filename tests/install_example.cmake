# ctest install_example: installs demcal into a fresh prefix, then configures,
# builds and runs examples/fit-and-calibrate against it, as another project would.
# -DBUILD_DIR (demcal's build tree) -DSOURCE_DIR (its sources) -DWORK (scratch)
# -DCXX_COMPILER (the compiler demcal was built with) [-DEXTRA_FLAGS].
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message(STATUS "${out}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
endfunction()
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK}/prefix)
# -DEXTRA_FLAGS: compile and link flags the installed libraries need (a sanitizer build's).
set(extra "")
if(EXTRA_FLAGS)
  set(extra "-DCMAKE_CXX_FLAGS=${EXTRA_FLAGS}" "-DCMAKE_EXE_LINKER_FLAGS=${EXTRA_FLAGS}")
endif()
# The example is compiled by demcal's own compiler: a sanitizer build's libraries carry that
# compiler's instrumentation, which only its own runtime understands (clang-instrumented
# code linked against GCC's libasan reports overflows that are not there).
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples/fit-and-calibrate -B ${WORK}/build -G Ninja
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=${CXX_COMPILER}
    -DCMAKE_PREFIX_PATH=${WORK}/prefix ${extra})
run(${CMAKE_COMMAND} --build ${WORK}/build)
run(${WORK}/build/fit_and_calibrate ${SOURCE_DIR}/examples/fit-and-calibrate/table.csv)
