# `demcal doe` under `mpirun -np 2` must split the runs between the ranks and
# give the same store and table as one process. Run by ctest (tests/CMakeLists.txt):
#   cmake -DDEMCAL=... -DMPIEXEC=... -DSTUDY=... -DWORK=... -P mpi_check.cmake
file(REMOVE_RECURSE ${WORK})

execute_process(COMMAND ${DEMCAL} doe ${STUDY} --output ${WORK}/single --jobs 2 --quiet
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "single-process doe failed (${rc}):\n${out}\n${err}")
endif()

execute_process(COMMAND ${MPIEXEC} --allow-run-as-root --oversubscribe -np 2
                        ${DEMCAL} doe ${STUDY} --output ${WORK}/mpi --jobs 1
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "mpirun output:\n${out}\n${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "doe under mpirun -np 2 failed (${rc})")
endif()
foreach(rank 0 1)
  if(NOT out MATCHES "rank ${rank}/2: 2 runs here: 0 already stored, 2 run")
    message(FATAL_ERROR "rank ${rank} did not run its 2 of the 4 runs")
  endif()
endforeach()

file(GLOB single_runs RELATIVE ${WORK}/single/doe-tiny/runs ${WORK}/single/doe-tiny/runs/*.json)
file(GLOB mpi_runs RELATIVE ${WORK}/mpi/doe-tiny/runs ${WORK}/mpi/doe-tiny/runs/*.json)
list(LENGTH mpi_runs n)
if(NOT n EQUAL 4 OR NOT "${single_runs}" STREQUAL "${mpi_runs}")
  message(FATAL_ERROR "run files differ: single ${single_runs}, mpi ${mpi_runs}")
endif()
file(READ ${WORK}/single/doe-tiny/doe.csv single_csv)
file(READ ${WORK}/mpi/doe-tiny/doe.csv mpi_csv)
if(NOT single_csv STREQUAL mpi_csv)
  message(FATAL_ERROR "doe.csv differs:\n${single_csv}\nvs\n${mpi_csv}")
endif()
file(REMOVE_RECURSE ${WORK})
