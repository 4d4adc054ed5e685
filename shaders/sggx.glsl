// ndfmip shading library: the slope-moment closed form for a GGX engine (needs brdf.glsl and
// lean.glsl), as shipped single-lobe filtering does it (Patry, "Samurai Shading in Ghost of
// Tsushima", SIGGRAPH 2020 course; Kaplanyan et al. 2016 for the kernel's roughness): one
// anisotropic GGX lobe about the mean slope whose squared-roughness tensor is the material's
// alpha^2 plus twice the slopes' covariance, the same tensor a GGX lobe of roughness alpha has
// per axis for a Gaussian of that covariance (alpha^2 = 2 sigma^2, Beckmann's relation).
//
// Textures: the lean bake's "lean_moments" and "lean_cross" (lean.glsl), hardware-filtered.

// Anisotropic GGX over slopes s = (h.x, h.y)/h.z - mean slope with the tensor A:
//   D(h) = 1 / (pi sqrt(det A) h.z^4 (1 + s^T A^-1 s)^2);
// for A = alpha^2 I, ndfmipGgx.
float ndfmipSggxLobe(NdfmipMaterial m, vec4 moments, float crossMoment, vec3 h) {
    float alpha2 = ndfmipSlopeLobeAlpha2(m);
    if (alpha2 < 0.0f || h.z <= 0.0f) return 0.0f;
    vec3 own = ndfmipLeanCovariance(moments, crossMoment);
    float axx = alpha2 + 2.0f * own.x;
    float ayy = alpha2 + 2.0f * own.y;
    float axy = 2.0f * own.z;
    float det = max(axx * ayy - axy * axy, 1e-12f);
    float dx = h.x / h.z - moments.x;
    float dy = h.y / h.z - moments.y;
    float q = (ayy * dx * dx - 2.0f * axy * dx * dy + axx * dy * dy) / det;
    float z2 = h.z * h.z;
    return 1.0f / (NDFMIP_PI * sqrt(det) * z2 * z2 * (1.0f + q) * (1.0f + q));
}

// LEAN's cosines about the mean slope's normal, with the GGX lobe.
vec3 ndfmipShadeSggx(NdfmipMaterial m, vec3 albedo, vec4 moments, float crossMoment, vec3 l, vec3 v) {
    return ndfmipShadeLeanLobe(m, albedo, moments, crossMoment, l, v, ndfmipSggxLobe(m, moments, crossMoment, normalize(l + v)));
}
