// Render glue for the vmf bake: layers "lobe0" .. "lobe<J-1>" (NDFMIP_LOBES = J, set by the
// renderer), then, with NDFMIP_LOBE_COLOURS, "color0" .. whose colours replace the albedo.
vec3 ndfmipShadeTexel(vec4 p[NDFMIP_LAYERS], vec3 albedo, vec3 l, vec3 v) {
    vec3 sum = vec3(0.0f);
    for (int j = 0; j < NDFMIP_LOBES; ++j) {
        vec3 lobeAlbedo = albedo;
#ifdef NDFMIP_LOBE_COLOURS
        lobeAlbedo = p[j].x > 0.0f ? p[NDFMIP_LOBES + j].rgb / p[j].x * ndfmipMaterialAlbedo : vec3(0.0f);
#endif
        sum += ndfmipShadeVmfLobe(ndfmipMaterial, lobeAlbedo, p[j], l, v);
    }
    return sum;
}
#ifdef NDFMIP_ENVIRONMENT
// Under an environment (render/environment.glsl).
vec3 ndfmipShadeEnvironment(vec4 p[NDFMIP_LAYERS], vec3 albedo, NdfmipHit hit, vec3 view) {
    vec3 sum = vec3(0.0f);
    for (int j = 0; j < NDFMIP_LOBES; ++j) {
        vec3 lobeAlbedo = albedo;
#ifdef NDFMIP_LOBE_COLOURS
        lobeAlbedo = p[j].x > 0.0f ? p[NDFMIP_LOBES + j].rgb / p[j].x * ndfmipMaterialAlbedo : vec3(0.0f);
#endif
#ifdef NDFMIP_ENVIRONMENT_SH
        NdfmipLobe lobe = ndfmipUnpackLobe(p[j]);
        if (lobe.alpha > 0.0f) {
            vec3 mu = normalize(ndfmipTangentToEnvironment(hit, lobe.mu)); // the environment frame
            NdfmipVmfBands bands = ndfmipVmfBands(lobe.kappa, max(ndfmipEnvShOrder, 1));
            NdfmipEnvShTransfer t = ndfmipVmfLobeTransfer(ndfmipMaterial.brdf, ndfmipMaterial.exponent, lobe.kappa, bands, true);
            sum += ndfmipShadeVmfLobeShLighting(ndfmipMaterial.brdf, lobeAlbedo, ndfmipMaterial.specular, mu, lobe.alpha,
                                                lobe.kappa, bands.a[1], ndfmipLobeConcentration(ndfmipMaterial), t);
        }
#else
        sum += ndfmipShadeVmfLobeEnvironment(ndfmipMaterial, lobeAlbedo, p[j], ndfmipTangentFrame(hit), view);
#endif
    }
    return sum;
}
#endif
