# Installs the build tree into a scratch prefix, then configures, builds and
# runs tests/package/consumer (every component; LoadRig from runtime_io) and
# tests/package/runtime_only (COMPONENTS runtime, with tinygltf and
# nlohmann_json unfindable) against it with find_package(facerig).
# -D BUILD_DIR=... -D SOURCE_DIR=... -D WORK_DIR=... -D RIG=...
file(REMOVE_RECURSE ${WORK_DIR})
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "failed: ${ARGN}\n${out}")
  endif()
  message(STATUS "${out}")
endfunction()
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/prefix)
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/package/consumer -B ${WORK_DIR}/build
    -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=Release)
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run(${WORK_DIR}/build/consumer ${RIG})
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/package/runtime_only -B ${WORK_DIR}/build_runtime_only
    -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=Release)
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build_runtime_only)
run(${WORK_DIR}/build_runtime_only/runtime_only ${RIG})
