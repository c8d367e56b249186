# Installs the build tree into a scratch prefix, then configures, builds and
# runs tests/package/consumer (every component; LoadRig from runtime_io; its
# own -Wall -Wextra -Werror) and tests/package/runtime_only (COMPONENTS
# runtime, with tinygltf and nlohmann_json unfindable) against it with
# find_package(facerig); then runs the installed player, when there is one,
# headless from another folder on its default rig: the built-in head
# installed beside it; builds the C ABI's C99 consumer with the flags of the
# installed facerig.pc and runs it on the installed head; and checks
# facerig-bench's help texts (build tree).
# -D BUILD_DIR=... -D SOURCE_DIR=... -D WORK_DIR=... -D RIG=... [-D PLAYER=ON] [-D CAPI=ON]
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

# The C ABI from the installed tree as a C program finds it: pkg-config
# gives the flags, the C99 consumer (hosts/c/tests/consumer.c) builds with
# -Werror against the installed facerig.h and runs on the installed head.
file(GLOB pc_files ${prefix}/lib*/pkgconfig/facerig.pc ${prefix}/lib/*/pkgconfig/facerig.pc)
if(CAPI AND NOT pc_files)
  message(FATAL_ERROR "the C ABI was built but no facerig.pc was installed under ${prefix}")
endif()
if(CAPI)
  list(GET pc_files 0 pc_file)
  get_filename_component(pc_dir ${pc_file} DIRECTORY)
  find_program(cc NAMES cc gcc REQUIRED)
  find_program(pkg_config NAMES pkg-config REQUIRED)
  execute_process(COMMAND ${CMAKE_COMMAND} -E env PKG_CONFIG_PATH=${pc_dir} ${pkg_config} --cflags --libs facerig
                  OUTPUT_VARIABLE pc_flags OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE pc_result)
  if(NOT pc_result EQUAL 0 OR NOT pc_flags MATCHES "-lfacerig")
    message(FATAL_ERROR "pkg-config --cflags --libs facerig failed: ${pc_flags}")
  endif()
  separate_arguments(pc_flags UNIX_COMMAND "${pc_flags}")
  run(${cc} -std=c99 -Wall -Wextra -Werror -pedantic ${SOURCE_DIR}/hosts/c/tests/consumer.c ${pc_flags} -lm
      -o ${WORK_DIR}/c_consumer)
  set(installed_head ${prefix}/share/facerig/default_head.frig)
  if(EXISTS ${installed_head})
    get_filename_component(lib_dir ${pc_file} DIRECTORY)
    get_filename_component(lib_dir ${lib_dir} DIRECTORY)
    run(${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${lib_dir} ${WORK_DIR}/c_consumer ${installed_head})
  endif()
endif()

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
