# Build-time half of ndfmip_shader_artifacts: writes OUTPUT = "#version 450 core" followed by
# the files given after the script name, in order, the same text the runtime loader
# (loadShaderFiles) builds. Each file is preceded by a #line directive naming it, so that
# glslangValidator reports errors against the file and its own line numbers.
#
#   cmake -DOUTPUT=<file> -P ShaderConcat.cmake <source>...
# Arguments after the script's own path are the sources.
set(sources "")
math(EXPR last "${CMAKE_ARGC} - 1")
set(first -1)
foreach(i RANGE ${last})
    if(first GREATER_EQUAL 0 AND i GREATER_EQUAL first)
        list(APPEND sources "${CMAKE_ARGV${i}}")
    elseif(CMAKE_ARGV${i} STREQUAL "-P")
        math(EXPR first "${i} + 2")
    endif()
endforeach()
if(NOT sources)
    message(FATAL_ERROR "ShaderConcat: no source files")
endif()

set(text "#version 450 core\n#extension GL_GOOGLE_cpp_style_line_directive : require\n")
foreach(source IN LISTS sources)
    file(READ "${source}" body)
    get_filename_component(name "${source}" NAME)
    # The same refusal as loadShaderFiles: the files are fragments, the header is added here.
    if(body MATCHES "(^|\n)[ \t]*#[ \t]*(version|include)")
        message(FATAL_ERROR "${source}: has #${CMAKE_MATCH_2} (shader files are concatenated after "
                            "'#version 450 core' and cannot include each other)")
    endif()
    string(APPEND text "#line 1 \"${name}\"\n${body}")
    if(NOT body MATCHES "\n$")
        string(APPEND text "\n")
    endif()
endforeach()

file(WRITE "${OUTPUT}" "${text}")
