// Render glue for the sh bake: layers "sh0" .. (NDFMIP_LAYERS, set by the renderer: four
// coefficients each) of a bake of order ndfmipShOrder; the material's A_l as uniforms. The
// lights' sums take the order as a uniform: as a constant (as NDFMIP_ENV_SH_ORDER for the
// environment's sums) their loops would unroll too, at each call site, and llvmpipe's
// compile time grow for no need (a light costs ~200 loop iterations).
uniform int ndfmipShOrder;
uniform float ndfmipShDiffuse[NDFMIP_SH_MAX_ORDER + 1];
uniform float ndfmipShSpecular[NDFMIP_SH_MAX_ORDER + 1];

// The texel's coefficients as one array (those past the bake's count are never read).
float[NDFMIP_SH_MAX_COEFFICIENTS] ndfmipShCoefficients(vec4 p[NDFMIP_LAYERS]) {
    float g[NDFMIP_SH_MAX_COEFFICIENTS];
    for (int k = 0; k < NDFMIP_LAYERS; ++k)
        for (int c = 0; c < 4; ++c)
            if (4 * k + c < NDFMIP_SH_MAX_COEFFICIENTS) g[4 * k + c] = p[k][c];
    return g;
}

vec3 ndfmipShadeTexel(vec4 p[NDFMIP_LAYERS], vec3 albedo, vec3 l, vec3 v) {
    return ndfmipShadeSh(ndfmipMaterial, albedo, ndfmipShCoefficients(p), ndfmipShDiffuse, ndfmipShSpecular,
                         ndfmipShOrder, l, v);
}
#ifdef NDFMIP_ENVIRONMENT
// Under an environment, the SH-lighting way (sh_lighting_shading.glsl).
vec3 ndfmipShadeEnvironment(vec4 p[NDFMIP_LAYERS], vec3 albedo, NdfmipHit hit, vec3 view) {
    float g[NDFMIP_SH_MAX_COEFFICIENTS] = ndfmipShCoefficients(p);
    // The lighting is in the hit's tangent frame, as g is: the plane's rotated on the CPU, a
    // sphere's per hit (ndfmipEnvShRotate, once per hit in main.frag's ndfmipLookup).
    vec3 meanNormal = ndfmipTangentToEnvironment(hit, ndfmipShMeanNormal(g[1], g[2], g[3]));
    float kappa = ndfmipKappaFromLength(length(meanNormal));
    return ndfmipShadeShLighting(ndfmipMaterial.brdf, albedo, ndfmipMaterial.specular, g, meanNormal, kappa,
                                 ndfmipLobeConcentration(ndfmipMaterial));
}
#endif
