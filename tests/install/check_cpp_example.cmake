# The C++ example (examples/cpp) built against woven installed from this build tree:
#   cmake --install BUILD --component development --prefix WORK/prefix
#   configure, build and run examples/cpp with CMAKE_PREFIX_PATH=WORK/prefix
# and the drape it prints must be at rest, below its start's energy, and finite.
# -DBUILD=<woven build> -DSOURCE=<examples/cpp> -DWORK=<scratch folder> -DGENERATOR=... -DCXX=...
file(REMOVE_RECURSE ${WORK})
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  set(out "${out}" PARENT_SCOPE)
endfunction()

run(${CMAKE_COMMAND} --install ${BUILD} --component development --prefix ${WORK}/prefix)
foreach(f lib/cmake/woven/woven-config.cmake lib/cmake/woven/woven-config-version.cmake include/woven/sim/drape.hpp)
  if(NOT EXISTS ${WORK}/prefix/${f})
    message(FATAL_ERROR "not installed: ${f}")
  endif()
endforeach()
if(EXISTS ${WORK}/prefix/include/woven/cli)
  message(FATAL_ERROR "the command line's headers are installed (include/woven/cli)")
endif()
run(${CMAKE_COMMAND} -S ${SOURCE} -B ${WORK}/build -G ${GENERATOR} -DCMAKE_BUILD_TYPE=Release
    -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_PREFIX_PATH=${WORK}/prefix)
run(${CMAKE_COMMAND} --build ${WORK}/build)
run(${WORK}/build/drape_sphere 9)
message("${out}")
if(NOT out MATCHES "grid 9 x 9, at rest")
  message(FATAL_ERROR "the example's drape is not at rest")
endif()
if(NOT out MATCHES "energy (-?[0-9.]+) J \\(start (-?[0-9.]+) J\\)")
  message(FATAL_ERROR "no energy line")
endif()
set(energy ${CMAKE_MATCH_1})
set(start ${CMAKE_MATCH_2})
# The cloth falls onto the sphere: gravity's energy drops by about m g dz (0.5 m x 0.5 m of
# cotton, ~30 g, falling up to 0.3 m at the edges: tens of mJ); the drape is below the start.
if(NOT energy LESS start)
  message(FATAL_ERROR "the drape's energy ${energy} J is not below the start's ${start} J")
endif()
