# Installs the build tree into a scratch prefix, then configures, builds and
# runs tests/package/consumer (every component; LoadRig from runtime_io; its
# own -Wall -Wextra -Werror) and tests/package/runtime_only (COMPONENTS
# runtime, with tinygltf and nlohmann_json unfindable) against it with
# find_package(facerig); then runs the installed player, when there is one,
# headless from another folder on its default rig: the built-in head
# installed beside it; and checks facerig-bench's help texts (build tree).
# -D BUILD_DIR=... -D SOURCE_DIR=... -D WORK_DIR=... -D RIG=... [-D PLAYER=ON]
file(REMOVE_RECURSE ${WORK_DIR})
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE out
                  WORKING_DIRECTORY ${WORK_DIR})
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "failed: ${ARGN}\n${out}")
  endif()
  message(STATUS "${out}")
  set(run_output "${out}" PARENT_SCOPE)
endfunction()
file(MAKE_DIRECTORY ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})

# Consumers get usage requirements only: no warning flag in the exported targets.
file(GLOB exported ${prefix}/lib*/cmake/facerig/facerig*Targets.cmake)
foreach(file ${exported})
  file(STRINGS ${file} flags REGEX "-W[a-z]")
  if(flags)
    message(FATAL_ERROR "${file} gives consumers facerig's warning flags: ${flags}")
  endif()
endforeach()

run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/package/consumer -B ${WORK_DIR}/build
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_BUILD_TYPE=Release)
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run(${WORK_DIR}/build/consumer ${RIG})
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/package/runtime_only -B ${WORK_DIR}/build_runtime_only
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_BUILD_TYPE=Release)
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build_runtime_only)
run(${WORK_DIR}/build_runtime_only/runtime_only ${RIG})

# The benchmark tool (a developer's tool: built, not installed) speaks to
# users in its help texts, not of the project's issues.
if(EXISTS ${prefix}/bin/facerig-bench)
  message(FATAL_ERROR "facerig-bench is installed: it is a developer's tool")
endif()
set(bench ${BUILD_DIR}/bin/facerig-bench)
if(EXISTS ${bench})
  run(${bench} --help)
  string(REGEX MATCHALL "\n  [a-z]+" benchmarks "${run_output}")  # the listed subcommands
  if(NOT benchmarks)
    message(FATAL_ERROR "facerig-bench --help lists no benchmarks:\n${run_output}")
  endif()
  set(help "${run_output}")
  foreach(benchmark ${benchmarks})
    string(STRIP "${benchmark}" benchmark)
    run(${bench} ${benchmark} --help)
    string(APPEND help "${run_output}")
  endforeach()
  if(help MATCHES "[Ii]ssue")
    message(FATAL_ERROR "facerig-bench's help mentions issues:\n${help}")
  endif()
endif()

if(PLAYER)
  # From a folder of its own (the run's working directory), a few frames.
  file(GLOB player ${prefix}/bin/facerig-player)
  run(${player} --headless --duration 0.2 --fps 10 --size 64x64 --frames ${WORK_DIR}/frames)
  file(REAL_PATH ${prefix} real_prefix)  # the player names it from its resolved executable
  set(expected_rig "rig ${real_prefix}/share/facerig/default_head.frig:")
  string(FIND "${run_output}" "${expected_rig}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "the installed player did not load ${expected_rig}\n${run_output}")
  endif()
  if(NOT EXISTS ${WORK_DIR}/frames/frame_00000.png)
    message(FATAL_ERROR "the installed player wrote no frames into ${WORK_DIR}/frames")
  endif()
endif()
