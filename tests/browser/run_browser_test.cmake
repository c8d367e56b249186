# ctest driver for tests/browser/check_glb.mjs: writes the GLBs a test needs
# (KIND default-head: the built-in head the build generates, and `facerig
# photo` of PHOTO on it; KIND ict-build:
# `facerig build` with ICT-FaceKit's shapes onto its identity005, and onto the
# textured built-in head) and checks them in headless Chromium with three.js.
# Screenshots and reports go to OUT_DIR.
#   cmake -D KIND=... -D NODE=... -D CHROMIUM=... -D FACERIG=... -D DEFAULT_HEAD_GLB=...
#         -D ICT_DIR=... -D PHOTO=... -D OUT_DIR=... -P run_browser_test.cmake
foreach(required NODE CHROMIUM OUT_DIR)
  if(NOT ${required} OR ${required} MATCHES "NOTFOUND$")
    message(FATAL_ERROR "${required} is not set: install node and Debian's chromium (scripts/install-deps.sh), "
                        "then npm ci --prefix tests/browser, and re-run cmake")
  endif()
endforeach()
file(MAKE_DIRECTORY ${OUT_DIR})

if(NOT EXISTS ${DEFAULT_HEAD_GLB})
  message(FATAL_ERROR "${DEFAULT_HEAD_GLB} is missing: build the target facerig_default_head")
endif()
function(facerig_build target output)
  execute_process(COMMAND ${FACERIG} build --template ${ICT_DIR} --target ${target} -o ${output}
                  RESULT_VARIABLE status OUTPUT_VARIABLE log ERROR_VARIABLE log)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "facerig build --target ${target} failed (${status}):\n${log}")
  endif()
endfunction()

if(KIND STREQUAL "default-head")
  # And a head made from a photograph (Debian python3-skimage's astronaut.png) on it.
  execute_process(COMMAND ${FACERIG} photo ${PHOTO} -o ${OUT_DIR}/photo_head.glb
                  RESULT_VARIABLE status OUTPUT_VARIABLE log ERROR_VARIABLE log)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "facerig photo ${PHOTO} failed (${status}):\n${log}")
  endif()
  set(glbs default-head=${DEFAULT_HEAD_GLB} photo-head=${OUT_DIR}/photo_head.glb)
elseif(KIND STREQUAL "ict-build")
  facerig_build(${ICT_DIR}/identity005.obj ${OUT_DIR}/ict_on_identity005.glb)
  facerig_build(${DEFAULT_HEAD_GLB} ${OUT_DIR}/ict_on_default_head.glb)
  set(glbs ict-on-identity005=${OUT_DIR}/ict_on_identity005.glb ict-on-default-head=${OUT_DIR}/ict_on_default_head.glb)
else()
  message(FATAL_ERROR "unknown KIND '${KIND}' (default-head or ict-build)")
endif()

execute_process(COMMAND ${NODE} ${CMAKE_CURRENT_LIST_DIR}/check_glb.mjs --out ${OUT_DIR} --chromium ${CHROMIUM}
                        ${glbs}
                RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "three.js in Chromium: checks failed (${status}); screenshots in ${OUT_DIR}")
endif()
