# ctest driver for tests/browser/check_glb.mjs: writes the GLB a test needs
# (KIND default-head: the built-in head the build generates; KIND ict-build:
# `facerig build` onto ICT-FaceKit's identity005) and checks it in headless
# Chromium with three.js. Screenshots and reports go to OUT_DIR.
#   cmake -D KIND=... -D NODE=... -D CHROMIUM=... -D FACERIG=... -D DEFAULT_HEAD_GLB=...
#         -D ICT_DIR=... -D OUT_DIR=... -P run_browser_test.cmake
foreach(required NODE CHROMIUM OUT_DIR)
  if(NOT ${required} OR ${required} MATCHES "NOTFOUND$")
    message(FATAL_ERROR "${required} is not set: install node and Debian's chromium (scripts/install-deps.sh), "
                        "then npm ci --prefix tests/browser, and re-run cmake")
  endif()
endforeach()
file(MAKE_DIRECTORY ${OUT_DIR})

if(KIND STREQUAL "default-head")
  set(glb ${DEFAULT_HEAD_GLB})
  if(NOT EXISTS ${glb})
    message(FATAL_ERROR "${glb} is missing: build the target facerig_default_head")
  endif()
elseif(KIND STREQUAL "ict-build")
  set(glb ${OUT_DIR}/ict_identity005_build.glb)
  execute_process(COMMAND ${FACERIG} build --template ${ICT_DIR} --target ${ICT_DIR}/identity005.obj -o ${glb}
                  RESULT_VARIABLE status OUTPUT_VARIABLE output ERROR_VARIABLE output)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "facerig build failed (${status}):\n${output}")
  endif()
else()
  message(FATAL_ERROR "unknown KIND '${KIND}' (default-head or ict-build)")
endif()

execute_process(COMMAND ${NODE} ${CMAKE_CURRENT_LIST_DIR}/check_glb.mjs --out ${OUT_DIR} --chromium ${CHROMIUM}
                        ${KIND}=${glb}
                RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "three.js in Chromium: checks failed (${status}); screenshots in ${OUT_DIR}")
endif()
