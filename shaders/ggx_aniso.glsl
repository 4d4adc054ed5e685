// ndfmip shading library: one anisotropic GGX lobe about the mean normal (needs brdf.glsl), the
// lobe ggx-aniso fits per texel and what an engine's anisotropic GGX shades.
//
// Textures: ggx-aniso's "normal" (the lobe's unit axis) and "alpha_moments" (the lobe's
// squared-roughness tensor A in the frame (t, b) about that normal, plus twice the second moment
// of the normal's x and y: ndfmipGgxAnisoMoments), both hardware-filtered; the shader takes the
// blend's tensor from the two blends (ndfmipGgxAnisoTensor).

// The frame about a unit normal n: t the texture's x made orthogonal to n (Gram-Schmidt, as
// engines make a surface tangent orthogonal to the shading normal), b = n x t; from y where n
// lies along x.
vec3 ndfmipAnisoTangent(vec3 n) {
    vec3 t = vec3(1.0f, 0.0f, 0.0f) - n.x * n;
    float length2 = dot(t, t);
    if (length2 < 1e-8f) {
        t = vec3(0.0f, 1.0f, 0.0f) - n.y * n;
        length2 = dot(t, t);
    }
    return t / sqrt(length2);
}

// Anisotropic GGX about n with the squared-roughness tensor A = (A_tt, A_tb, A_bb) in (t, b):
//   D(h) = 1 / (pi sqrt(det A) (h.n)^4 (1 + s^T A^-1 s)^2),  s = (h.t, h.b) / h.n
// (Heitz 2014, eq. 86, the lobe stretched by A^1/2); for A = alpha^2 I, ndfmipGgx. With
// q = (h.t, h.b) A^-1 (h.t, h.b)^T the denominator's (h.n)^2 (1 + s^T A^-1 s) is (h.n)^2 + q.
float ndfmipGgxAnisoLobe(vec3 n, vec3 tensor, vec3 h) {
    float cosH = dot(n, h);
    if (cosH <= 0.0f) return 0.0f;
    vec3 t = ndfmipAnisoTangent(n);
    vec3 b = cross(n, t);
    float att = max(tensor.x, 1e-8f);
    float abb = max(tensor.z, 1e-8f);
    float atb = tensor.y;
    float det = max(att * abb - atb * atb, 1e-16f);
    float x = dot(h, t);
    float y = dot(h, b);
    float q = (abb * x * x - 2.0f * atb * x * y + att * y * y) / det;
    float d = cosH * cosH + q;
    return 1.0f / (NDFMIP_PI * sqrt(det) * d * d);
}

// What a blend of texels adds to their lobes, as Toksvig's rule adds the normals' spread to
// alpha^2 (alpha'^2 = alpha^2 + 2 sigma^2, roughness.h's varianceRoughness): twice the covariance
// of the blended texels' axes.
#define NDFMIP_GGX_ANISO_AXIS_SPREAD 2.0f

// The texel ggx-aniso stores for its lobe's tensor A about its unit axis n: M = A + 2 n_xy n_xy^T
// (M_tt, M_tb, M_bb; n_xy the axis's x and y in the texture's frame). A hardware blend of M and
// of the axes is then mean(A) + 2 (mean(n_xy n_xy^T) - mean(n_xy) mean(n_xy)^T): the blended
// lobes' own widths plus the spread between their axes, which a blend of A alone loses (LEAN
// mapping's second moments keep it the same way, Toksvig's |Na| for one isotropic lobe).
vec3 ndfmipGgxAnisoMoments(vec3 tensor, vec3 n) {
    return tensor + NDFMIP_GGX_ANISO_AXIS_SPREAD * vec3(n.x * n.x, n.x * n.y, n.y * n.y);
}

// The lobe's tensor from the blended "alpha_moments" and the blended, not renormalised, normal:
// at one texel its own A. The spread is taken in the texture's x and y, which the frame (t, b)
// about the blended normal is up to its tilt (second order in the tilt of the blended axes).
vec3 ndfmipGgxAnisoTensor(vec3 moments, vec3 filtered) {
    return moments - NDFMIP_GGX_ANISO_AXIS_SPREAD *
                         vec3(filtered.x * filtered.x, filtered.x * filtered.y, filtered.y * filtered.y);
}

// The isotropic alpha an engine's environment lighting reads for the lobe: the root mean of the
// tensor's two squared roughnesses (its trace / 2).
float ndfmipGgxAnisoAlpha(vec3 tensor) {
    return sqrt(max(0.5f * (tensor.x + tensor.z), 1e-8f));
}

// The engines' anisotropy inputs, decoded after their sampler has blended them. Each holds the
// direction of alpha_t as (d + 1)/2 in two channels and normalises it after the blend; the tensor
// of alpha_t along it and alpha_b across, in the frame (t, b) about the normal (the engines' frame
// is the surface's tangents, the same where the normal is upright and apart by the normal's tilt,
// second order in it, elsewhere).
vec3 ndfmipEngineAnisotropyTensor(vec2 rg, float alphaT, float alphaB) {
    vec2 d = 2.0f * rg - vec2(1.0f);
    float length2 = dot(d, d);
    d = length2 > 0.0f ? d / sqrt(length2) : vec2(1.0f, 0.0f);
    float b2 = alphaB * alphaB;
    float stretch = alphaT * alphaT - b2;
    return vec3(b2 + stretch * d.x * d.x, stretch * d.x * d.y, b2 + stretch * d.y * d.y);
}

// glTF's KHR_materials_anisotropy as three.js decodes it (lights_physical_fragment): `khr` =
// (roughness, the metallicRoughness texture's G; the anisotropyTexture's R, G, B), alpha_b =
// roughness^2, alpha_t = mix(alpha_b, 1, B^2).
vec3 ndfmipKhrAnisotropyTensor(vec4 khr) {
    float alphaB = khr.x * khr.x;
    float strength = clamp(khr.w, 0.0f, 1.0f);
    float alphaT = alphaB + strength * strength * (1.0f - alphaB); // mix(alphaB, 1, strength^2)
    return ndfmipEngineAnisotropyTensor(vec2(khr.y, khr.z), alphaT, alphaB);
}

// Kulla and Conty's parametrisation (Unreal's GetAnisotropicRoughness, Unity HDRP's
// ConvertAnisotropyToRoughness): `c` = (roughness, the direction's R, G, anisotropy k), alpha =
// roughness^2, alpha_t,b = alpha (1 +- k), each at least 0.001 as Unreal clamps them.
vec3 ndfmipKullaAnisotropyTensor(vec4 c) {
    float alpha = c.x * c.x;
    float k = clamp(c.w, 0.0f, 1.0f);
    return ndfmipEngineAnisotropyTensor(vec2(c.y, c.z), max(alpha * (1.0f + k), 0.001f),
                                        max(alpha * (1.0f - k), 0.001f));
}

// Burley's parametrisation (Godot 4's light_compute): `c` = (roughness, the flowmap's R, G,
// anisotropy k), alpha = roughness^2, aspect = sqrt(1 - 0.9 k), alpha_t = alpha / aspect, alpha_b =
// alpha aspect.
vec3 ndfmipBurleyAnisotropyTensor(vec4 c) {
    float alpha = c.x * c.x;
    float aspect = sqrt(1.0f - 0.9f * clamp(c.w, 0.0f, 1.0f));
    return ndfmipEngineAnisotropyTensor(vec2(c.y, c.z), alpha / aspect, alpha * aspect);
}

// An engine's specular anti-aliasing (ndfmipSpecularAaKernel, brdf.glsl) on the tensor: the
// kernel added to alpha^2 along every direction.
vec3 ndfmipSpecularAaTensor(vec3 tensor, float kernel) {
    return tensor + vec3(kernel, 0.0f, kernel);
}

// The lobe about the renormalised filtered normal, with its cosine: max(n.l, 0) (albedo / pi +
// specular D(h)), as ndfmipShadeNormal shades one normal.
vec3 ndfmipShadeGgxAniso(NdfmipMaterial m, vec3 albedo, vec3 filtered, vec3 tensor, vec3 l, vec3 v) {
    float len = sqrt(dot(filtered, filtered));
    vec3 n = len > 0.0f ? filtered / len : vec3(0.0f, 0.0f, 1.0f);
    float cosL = max(dot(n, l), 0.0f);
    if (cosL <= 0.0f) return vec3(0.0f);
    return cosL * (albedo * (1.0f / NDFMIP_PI) + m.specular * ndfmipGgxAnisoLobe(n, tensor, normalize(l + v)));
}
