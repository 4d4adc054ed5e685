# Offline shader artifacts: one GLSL 4.50 shader (a list of fragment files, concatenated as the
# runtime loader does) compiled to SPIR-V and translated to HLSL Shader Model 5 and GLSL ES, each
# output checked by a compiler at build time.
#
#   ndfmip_shader_artifacts(NAME <name> STAGE <vert|frag|comp> SOURCES <file>...
#                           [COMPONENT <install component>] [EXCLUDE_FROM_ALL])
#
# Builds, in target ndfmip_shaders_<name> (part of ALL):
#   ${CMAKE_BINARY_DIR}/shaders/glsl/<name>.<stage>        the concatenation (with #line directives)
#   ${CMAKE_BINARY_DIR}/shaders/spirv/<name>.<stage>.spv   glslangValidator -G (OpenGL semantics)
#   ${CMAKE_BINARY_DIR}/shaders/hlsl/<name>.<stage>.hlsl   spirv-cross --hlsl --shader-model 50
#   ${CMAKE_BINARY_DIR}/shaders/essl/<name>.<stage>        spirv-cross --es --version 300 (310 for comp)
# and installs the last three and the SOURCES to share/ndfmip/shaders/{spirv,hlsl,essl,glsl}
# (COMPONENT defaults to "shaders"; EXCLUDE_FROM_ALL keeps them out of a plain install).
# Sets NDFMIP_SHADER_ARTIFACTS_<name> in the caller to the three artifact paths, or to nothing
# when glslangValidator or spirv-cross is missing (a warning, no target: the build goes on).
#
# SPIR-V is made under OpenGL semantics (-G) rather than Vulkan (-V) because our shaders are
# OpenGL shaders: -V refuses uniforms outside a block. Locations missing on stage inputs and
# outputs are assigned (--aml). Function names survive every step (OpName).

find_program(NDFMIP_GLSLANG_VALIDATOR glslangValidator)
find_program(NDFMIP_SPIRV_CROSS spirv-cross)
find_program(NDFMIP_SPIRV_VAL spirv-val) # optional: a check of the SPIR-V itself
set(NDFMIP_SHADER_CONCAT_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/ShaderConcat.cmake)

function(ndfmip_shader_artifacts)
    cmake_parse_arguments(PARSE_ARGV 0 ARG "EXCLUDE_FROM_ALL" "NAME;STAGE;COMPONENT" "SOURCES")
    if(NOT ARG_NAME OR NOT ARG_SOURCES OR NOT ARG_STAGE MATCHES "^(vert|frag|comp)$")
        message(FATAL_ERROR "ndfmip_shader_artifacts(NAME <name> STAGE vert|frag|comp SOURCES <files>...)")
    endif()
    set(NDFMIP_SHADER_ARTIFACTS_${ARG_NAME} "" PARENT_SCOPE)
    if(NOT NDFMIP_GLSLANG_VALIDATOR OR NOT NDFMIP_SPIRV_CROSS)
        get_property(warned GLOBAL PROPERTY NDFMIP_SHADER_TOOLS_WARNED)
        if(NOT warned)
            message(WARNING "Shader artifacts (SPIR-V, HLSL, GLSL ES) not built: glslangValidator or "
                            "spirv-cross missing (apt: glslang-tools spirv-cross; scripts/setup)")
            set_property(GLOBAL PROPERTY NDFMIP_SHADER_TOOLS_WARNED TRUE)
        endif()
        return()
    endif()
    if(NOT ARG_COMPONENT)
        set(ARG_COMPONENT shaders)
    endif()

    set(sources "")
    foreach(source IN LISTS ARG_SOURCES)
        get_filename_component(source "${source}" ABSOLUTE)
        list(APPEND sources "${source}")
    endforeach()
    set(dir ${CMAKE_BINARY_DIR}/shaders)
    set(base ${ARG_NAME}.${ARG_STAGE})
    set(glsl ${dir}/glsl/${base})
    set(spv ${dir}/spirv/${base}.spv)
    set(hlsl ${dir}/hlsl/${base}.hlsl)
    set(essl ${dir}/essl/${base})
    set(checks ${dir}/checks)
    set(essl_version 300)
    if(ARG_STAGE STREQUAL "comp")
        set(essl_version 310) # GLSL ES has compute shaders from 3.10
    endif()

    add_custom_command(OUTPUT ${glsl}
        COMMAND ${CMAKE_COMMAND} -DOUTPUT=${glsl} -P ${NDFMIP_SHADER_CONCAT_SCRIPT} ${sources}
        DEPENDS ${sources} ${NDFMIP_SHADER_CONCAT_SCRIPT}
        COMMENT "Shader ${ARG_NAME}: concatenating ${ARG_STAGE} sources" VERBATIM)

    # Every output is written to the scratch folder, checked there and only then moved into
    # place, so a failed check leaves no output that a later build would take as up to date.
    set(validate_spirv "")
    if(NDFMIP_SPIRV_VAL)
        set(validate_spirv COMMAND ${NDFMIP_SPIRV_VAL} --target-env opengl4.5 ${checks}/${base}.spv)
    endif()
    add_custom_command(OUTPUT ${spv}
        COMMAND ${CMAKE_COMMAND} -E make_directory ${dir}/spirv ${checks}
        COMMAND ${NDFMIP_GLSLANG_VALIDATOR} -G --aml -S ${ARG_STAGE} -o ${checks}/${base}.spv ${glsl}
        ${validate_spirv}
        COMMAND ${CMAKE_COMMAND} -E rename ${checks}/${base}.spv ${spv}
        DEPENDS ${glsl}
        COMMENT "Shader ${ARG_NAME}: GLSL 4.50 to SPIR-V" VERBATIM)

    # Each translation is checked by glslang: the ES file as GLSL ES (its #version 300 es says
    # so), the HLSL by glslang's HLSL front end, which checks only while generating SPIR-V (-V),
    # so that SPIR-V goes to a scratch file.
    add_custom_command(OUTPUT ${hlsl}
        COMMAND ${CMAKE_COMMAND} -E make_directory ${dir}/hlsl ${checks}
        COMMAND ${NDFMIP_SPIRV_CROSS} --hlsl --shader-model 50 --output ${checks}/${base}.hlsl ${spv}
        COMMAND ${NDFMIP_GLSLANG_VALIDATOR} -D -V -e main -S ${ARG_STAGE}
                -o ${checks}/${base}.hlsl.spv ${checks}/${base}.hlsl
        COMMAND ${CMAKE_COMMAND} -E rename ${checks}/${base}.hlsl ${hlsl}
        DEPENDS ${spv}
        COMMENT "Shader ${ARG_NAME}: SPIR-V to HLSL SM 5.0, checked by glslang's HLSL front end" VERBATIM)
    add_custom_command(OUTPUT ${essl}
        COMMAND ${CMAKE_COMMAND} -E make_directory ${dir}/essl ${checks}
        COMMAND ${NDFMIP_SPIRV_CROSS} --es --version ${essl_version} --output ${checks}/${base}.essl ${spv}
        COMMAND ${NDFMIP_GLSLANG_VALIDATOR} -S ${ARG_STAGE} ${checks}/${base}.essl
        COMMAND ${CMAKE_COMMAND} -E rename ${checks}/${base}.essl ${essl}
        DEPENDS ${spv}
        COMMENT "Shader ${ARG_NAME}: SPIR-V to GLSL ES ${essl_version}, checked by glslang" VERBATIM)

    add_custom_target(ndfmip_shaders_${ARG_NAME} ALL DEPENDS ${spv} ${hlsl} ${essl} SOURCES ${sources})

    set(install_options COMPONENT ${ARG_COMPONENT})
    if(ARG_EXCLUDE_FROM_ALL)
        list(APPEND install_options EXCLUDE_FROM_ALL)
    endif()
    set(destination ${CMAKE_INSTALL_DATADIR}/ndfmip/shaders)
    install(FILES ${spv} DESTINATION ${destination}/spirv ${install_options})
    install(FILES ${hlsl} DESTINATION ${destination}/hlsl ${install_options})
    install(FILES ${essl} DESTINATION ${destination}/essl ${install_options})
    install(FILES ${sources} DESTINATION ${destination}/glsl ${install_options})

    set(NDFMIP_SHADER_ARTIFACTS_${ARG_NAME} ${spv} ${hlsl} ${essl} PARENT_SCOPE)
endfunction()
