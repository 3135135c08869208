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

# One model for everyone: the cube at 9 x 9 draped by the example's step loop (the installed
# library, testers::make_drape_model), by the command and by the Python module gives the same
# energy, to the last bit (the same model, solver and thread-independent sums; printed to 17
# digits and compared as doubles). Then the step loop with the box lowered after step 5: at rest.
run(${WORK}/build/drape_steps cube 9)
if(NOT out MATCHES "at rest" OR NOT out MATCHES "\nenergy ([-0-9.e]+) J")
  message(FATAL_ERROR "drape_steps cube 9: no drape at rest\n${out}")
endif()
set(cpp_energy ${CMAKE_MATCH_1})
if(WOVEN)
  run(${WOVEN} drape cube --grid 9 --no-render --quiet --out ${WORK}/cli)
  file(READ ${WORK}/cli/report.json report)
  string(JSON cli_energy GET "${report}" energy total_J)
  set(energies "C++ ${cpp_energy} J, command ${cli_energy} J")
  set(values ${cpp_energy} ${cli_energy})
  if(PYTHON AND PYTHONPATH)
    set(ENV{PYTHONPATH} ${PYTHONPATH})
    run(${PYTHON} -c "print(repr(__import__('woven').drape('cube', grid=9).report['energy']['total_J']))")  # no ';': a list
    string(STRIP "${out}" py_energy)
    string(APPEND energies ", Python ${py_energy} J")
    list(APPEND values ${py_energy})
  endif()
  message("same scene, three front ends: ${energies}")
  foreach(v ${values})
    if(NOT v EQUAL cpp_energy)
      message(FATAL_ERROR "the front ends drape the same scene to different energies: ${energies}")
    endif()
  endforeach()
endif()
run(${WORK}/build/drape_steps cube 9 5)
if(NOT out MATCHES "obstacles lowered by 0.02 m" OR NOT out MATCHES "at rest")
  message(FATAL_ERROR "drape_steps cube 9 5: the drape with the lowered box is not at rest\n${out}")
endif()
