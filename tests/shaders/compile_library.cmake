# The GLSL shading library compiles as GLSL 4.50: every file in order, and a fragment shader that
# calls each method's shade function (so none is left out as unused). cmake -P with GLSLANG,
# SHADERS (the shaders/ folder) and WORK (a scratch folder).
set(source "#version 450 core\n")
foreach(file brdf naive toksvig toksvig_lut sh vmf lean sggx ggx_aniso)
    file(READ ${SHADERS}/${file}.glsl text)
    string(APPEND source "#line 1\n${text}\n")
endforeach()
string(APPEND source [[
layout(location = 0) out vec4 colour;
uniform vec4 p;
void main() {
    NdfmipMaterial m;
    m.brdf = NDFMIP_GGX;
    m.exponent = 32.0f;
    m.roughness = 0.2f;
    m.specular = vec3(1.0f);
    vec3 l = normalize(vec3(0.3f, 0.1f, 1.0f));
    vec3 v = vec3(0.0f, 0.0f, 1.0f);
    float g[NDFMIP_SH_MAX_COEFFICIENTS];
    float a[NDFMIP_SH_MAX_ORDER + 1];
    for (int i = 0; i < NDFMIP_SH_MAX_COEFFICIENTS; ++i) g[i] = p.x;
    for (int i = 0; i <= NDFMIP_SH_MAX_ORDER; ++i) a[i] = p.y;
    vec3 c = ndfmipShadeNaive(m, vec3(0.5f), p.xyz, l, v) + ndfmipShadeRoughnessMips(m, vec3(0.5f), p.xyz, p.w, false, l, v)
           + ndfmipShadeToksvig(m, vec3(0.5f), p.xyz, l, v, NDFMIP_MAPPING_OURS, 2.0f)
           + ndfmipShadeToksvigLut(m, vec3(0.5f), p.xyz, p.w, l, v)
           + ndfmipShadeSh(m, vec3(0.5f), g, a, a, 7, l, v)
           + ndfmipShadeVmfLobe(m, vec3(0.5f), p, l, v) + ndfmipShadeLean(m, vec3(0.5f), p, p.x, l, v)
           + ndfmipShadeSggx(m, vec3(0.5f), p, p.x, l, v) + ndfmipShadeGgxAniso(m, vec3(0.5f), p.xyz, p.yzw, l, v);
    colour = vec4(c, 1.0f);
}
]])
file(MAKE_DIRECTORY ${WORK})
file(WRITE ${WORK}/library.frag "${source}")
execute_process(COMMAND ${GLSLANG} ${WORK}/library.frag RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT status EQUAL 0)
    message(FATAL_ERROR "the GLSL library does not compile:\n${out}${err}")
endif()
