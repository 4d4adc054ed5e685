// ndfmip shading library: LEAN mapping (Olano and Baker 2010; needs brdf.glsl).
//
// Textures: the lean bake's "lean_moments" (RGBA: E[bx], E[by], E[bx^2], E[by^2]) and
// "lean_cross" (R: E[bx by]), both mipmapped and trilinear.

// The filtered slope covariance (xx, yy, xy).
vec3 ndfmipLeanCovariance(vec4 moments, float crossMoment) {
    return vec3(max(moments.z - moments.x * moments.x, 0.0f), max(moments.w - moments.y * moments.y, 0.0f),
                crossMoment - moments.x * moments.y);
}

// The material's squared roughness as the slope-moment lobes read it: Beckmann's and GGX's
// alpha^2, Blinn-Phong's through alpha^2 = 2/(s + 2) (Walter et al.); -1 for no such lobe.
float ndfmipSlopeLobeAlpha2(NdfmipMaterial m) {
    if (m.brdf == NDFMIP_BLINN_PHONG) return 2.0f / (m.exponent + 2.0f);
    if (m.brdf == NDFMIP_BECKMANN || m.brdf == NDFMIP_GGX) return m.roughness * m.roughness;
    return -1.0f;
}

// The anisotropic Beckmann lobe of the slope Gaussian plus the material's slope variance
// (Beckmann alpha^2/2 per axis; GGX as Beckmann).
float ndfmipLeanLobe(NdfmipMaterial m, vec4 moments, float crossMoment, vec3 h) {
    float alpha2 = ndfmipSlopeLobeAlpha2(m);
    if (alpha2 < 0.0f || h.z <= 0.0f) return 0.0f;
    vec3 own = ndfmipLeanCovariance(moments, crossMoment);
    float sxx = own.x + 0.5f * alpha2;
    float syy = own.y + 0.5f * alpha2;
    float sxy = own.z;
    float det = max(sxx * syy - sxy * sxy, 1e-12f);
    float dx = h.x / h.z - moments.x;
    float dy = h.y / h.z - moments.y;
    float q = (syy * dx * dx - 2.0f * sxy * dx * dy + sxx * dy * dy) / det;
    return exp(-0.5f * q) / (2.0f * NDFMIP_PI * sqrt(det) * h.z * h.z * h.z * h.z);
}

// Cosines about the mean slope's normal, the NDF read as a lobe of variance (vx + vy)/2 per axis.
vec3 ndfmipShadeLeanLobe(NdfmipMaterial m, vec3 albedo, vec4 moments, float crossMoment, vec3 l, vec3 v, float lobe) {
    vec3 h = normalize(l + v);
    vec3 n = normalize(vec3(moments.x, moments.y, 1.0f));
    vec3 own = ndfmipLeanCovariance(moments, crossMoment);
    float variance = 0.5f * (own.x + own.y);
    float kappa = variance > 0.0f ? 1.0f / variance : 1e30f;
    float cosDiffuse = max(dot(n, l), 0.0f);
    float cosSpecular = ndfmipSpecularCosine(n, kappa, ndfmipLobeConcentration(m), h, l);
    return cosDiffuse * albedo * (1.0f / NDFMIP_PI) + cosSpecular * m.specular * lobe;
}

vec3 ndfmipShadeLean(NdfmipMaterial m, vec3 albedo, vec4 moments, float crossMoment, vec3 l, vec3 v) {
    return ndfmipShadeLeanLobe(m, albedo, moments, crossMoment, l, v, ndfmipLeanLobe(m, moments, crossMoment, normalize(l + v)));
}
