# ctest shader_artifacts: the SPIR-V, HLSL and GLSL ES made by ndfmip_shader_artifacts exist, are
# what they claim to be and still name FUNCTION; then the install component puts them, and the
# GLSL source, under share/ndfmip/shaders.
#
#   cmake -DSPIRV= -DHLSL= -DESSL= -DSOURCE= -DFUNCTION= -DBUILD_DIR= -DCOMPONENT= -DWORK_DIR=
#         -P check_shader_artifacts.cmake
foreach(file ${SPIRV} ${HLSL} ${ESSL})
    if(NOT EXISTS ${file})
        message(FATAL_ERROR "missing artifact ${file}")
    endif()
endforeach()

file(READ ${SPIRV} magic LIMIT 4 HEX)
if(NOT magic STREQUAL "03022307")
    message(FATAL_ERROR "${SPIRV}: no SPIR-V magic number (read ${magic})")
endif()
file(STRINGS ${SPIRV} names REGEX "${FUNCTION}")
if(NOT names)
    message(FATAL_ERROR "${SPIRV}: no OpName holding ${FUNCTION}")
endif()

file(READ ${HLSL} hlsl)
if(NOT hlsl MATCHES "${FUNCTION}\\(" OR NOT hlsl MATCHES "SV_Target")
    message(FATAL_ERROR "${HLSL}: no function ${FUNCTION} or no SV_Target output")
endif()
file(READ ${ESSL} essl)
if(NOT essl MATCHES "^#version 300 es" OR NOT essl MATCHES "${FUNCTION}\\(")
    message(FATAL_ERROR "${ESSL}: not GLSL ES 3.00 or no function ${FUNCTION}")
endif()

file(REMOVE_RECURSE ${WORK_DIR})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --component ${COMPONENT}
                        --prefix ${WORK_DIR}
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(rc)
    message(FATAL_ERROR "install of component ${COMPONENT} failed: ${rc}")
endif()
get_filename_component(spirv_name ${SPIRV} NAME)
get_filename_component(hlsl_name ${HLSL} NAME)
get_filename_component(essl_name ${ESSL} NAME)
get_filename_component(source_name ${SOURCE} NAME)
foreach(installed spirv/${spirv_name} hlsl/${hlsl_name} essl/${essl_name} glsl/${source_name})
    if(NOT EXISTS ${WORK_DIR}/share/ndfmip/shaders/${installed})
        message(FATAL_ERROR "not installed: share/ndfmip/shaders/${installed}")
    endif()
endforeach()
message("shader artifacts: ${spirv_name}, ${hlsl_name}, ${essl_name} name ${FUNCTION}; installed")
