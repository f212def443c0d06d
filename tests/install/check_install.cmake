# ctest install_and_consume: installs the build into a fresh prefix, then builds and runs a
# consumer project against it (find_package(funnel) -> funnel::funnel), and checks that the
# installed CLI and Python package give the same trajectory.
# Variables: BUILD_DIR, SOURCE_DIR (tests/install), WORK_DIR, GENERATOR, CXX, PYTHON, PYTHON_DIR.

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  set(out "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})

foreach(file bin/funnel include/funnel/engine.hpp share/funnel/paper/fig03.toml)
  if(NOT EXISTS ${prefix}/${file})
    message(FATAL_ERROR "not installed: ${prefix}/${file}")
  endif()
endforeach()
file(GLOB_RECURSE config ${prefix}/*/funnelConfig.cmake)
file(GLOB_RECURSE archive ${prefix}/*/libfunnel.a)
if(NOT config OR NOT archive)
  message(FATAL_ERROR "the CMake package or libfunnel.a is missing under ${prefix}")
endif()

# The installed CLI: the reference trajectory's duration.
run(${prefix}/bin/funnel trajectory --release 0.3)
if(NOT out MATCHES "\"duration\": ([^,\n]+)")
  message(FATAL_ERROR "no duration in the installed CLI's output:\n${out}")
endif()
set(cli_duration ${CMAKE_MATCH_1})

# A consumer project built against the prefix only.
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/consumer -B ${WORK_DIR}/consumer -G ${GENERATOR}
    -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix})
run(${CMAKE_COMMAND} --build ${WORK_DIR}/consumer)
run(${WORK_DIR}/consumer/consumer)
if(NOT out MATCHES "status exited\nduration ([^\n]+)")
  message(FATAL_ERROR "unexpected consumer output:\n${out}")
endif()
if(NOT CMAKE_MATCH_1 STREQUAL cli_duration)
  message(FATAL_ERROR "consumer duration ${CMAKE_MATCH_1} differs from the CLI's ${cli_duration}")
endif()

# The installed Python package, found through the prefix's site-packages alone.
if(PYTHON_DIR)
  run(${CMAKE_COMMAND} -E env PYTHONPATH=${prefix}/${PYTHON_DIR} PYTHONDONTWRITEBYTECODE=1 ${PYTHON} -c
      "import funnel\nprint(funnel.__file__)\nprint(repr(funnel.simulate(release=0.3)['duration']))")
  if(NOT out MATCHES "^${prefix}/${PYTHON_DIR}/funnel/__init__.py\n([^\n]+)")
    message(FATAL_ERROR "the installed Python package was not the one imported:\n${out}")
  endif()
  if(NOT CMAKE_MATCH_1 STREQUAL cli_duration)
    message(FATAL_ERROR "Python duration ${CMAKE_MATCH_1} differs from the CLI's ${cli_duration}")
  endif()
else()
  message(STATUS "Python package not built: its installation is not checked")
endif()
message(STATUS "installed and consumed from ${prefix}: duration ${cli_duration}")
