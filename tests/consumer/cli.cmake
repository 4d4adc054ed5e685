# Installs the built library into a scratch prefix, builds the command-line tool (tools/ndfmip)
# against that installed package alone (no source-tree headers: the tool uses public headers
# only), and runs it: a bake of the bundled map, whose manifest must name the method.
include(${CMAKE_CURRENT_LIST_DIR}/install_prefix.cmake)
# No optimisation: the tool's own code is thin, and this checks that it builds, quickly.
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE_DIR}/tools/ndfmip -B ${WORK_DIR}/build
                        -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=
                        "-DCMAKE_CXX_FLAGS=-O0 ${EXTRA_FLAGS}"
                RESULT_VARIABLE rc)
if(rc)
    message(FATAL_ERROR "configure of the tool against the installed package failed: ${rc}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK_DIR}/build --parallel 2 RESULT_VARIABLE rc)
if(rc)
    message(FATAL_ERROR "build of the tool against the installed package failed: ${rc}")
endif()
execute_process(COMMAND ${WORK_DIR}/build/ndfmip bake ${SOURCE_DIR}/data/normalmaps/pyramidwall_256.png
                        -o ${WORK_DIR}/bake --method toksvig
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(rc)
    message(FATAL_ERROR "the tool built against the installed package failed: ${rc}")
endif()
file(READ ${WORK_DIR}/bake/manifest.json manifest)
string(JSON method GET "${manifest}" method)
if(NOT method STREQUAL "toksvig")
    message(FATAL_ERROR "the bake's manifest names method '${method}', not toksvig")
endif()
