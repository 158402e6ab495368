# ctest build.solver_only: the solver-only build (BRT_SOLVER_ONLY: no OpenCASCADE, no VTK), which
# is what a GPU machine builds from a copy of the tree, must configure, build, and solve a
# .brtsolve file that the full build wrote.
#   cmake -DSRC=<source> -DBIN=<build dir> -DBENCH=<full build's brt_thickness_bench>
#         -DMODEL=<a STEP file> -P SolverOnlyBuild.cmake
foreach (var SRC BIN BENCH MODEL)
  if (NOT DEFINED ${var})
    message(FATAL_ERROR "SolverOnlyBuild.cmake: ${var} not set")
  endif ()
endforeach ()
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if (NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif ()
  set(LAST_OUTPUT "${out}" PARENT_SCOPE)
endfunction()
run(${CMAKE_COMMAND} -S ${SRC} -B ${BIN} -G Ninja -DCMAKE_BUILD_TYPE=Release -DBRT_SOLVER_ONLY=ON)
run(${CMAKE_COMMAND} --build ${BIN})
file(MAKE_DIRECTORY ${BIN}/dumps)
run(${BENCH} --device none --no-native --counts 1000 --export ${BIN}/dumps ${MODEL})
get_filename_component(name ${MODEL} NAME_WE)
run(${BIN}/brt_thickness_bench --device none --counts 1000 ${BIN}/dumps/${name}.brtsolve)
message("${LAST_OUTPUT}")
if (NOT LAST_OUTPUT MATCHES "${name}.brtsolve +1000 ")
  message(FATAL_ERROR "the solver-only bench printed no row for ${name}.brtsolve")
endif ()
