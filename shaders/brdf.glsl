// ndfmip shading library: BRDFs and the pieces every method shares.
//
// Plain GLSL 4.50 functions, no bindings, no #version: paste the files into a shader in this
// order (brdf.glsl first, then the method's file). The same text is compiled as C++ by the
// ndfmip library (include/ndfmip/glsl.h), so the renderer, the tests and a GPU run the same
// formulas. Hence the dialect: float literals with an f suffix, no swizzles, no out
// parameters, no switch, constants as #defines.
//
// Tangent frame: z is the geometric normal; l, v, h unit vectors towards the light, the viewer
// and their half vector. Every shade function returns reflected radiance per unit irradiance.

#define NDFMIP_PI 3.14159265358979f

// Material BRDFs (NdfmipMaterial.brdf).
#define NDFMIP_LAMBERT 0
#define NDFMIP_BLINN_PHONG 1
#define NDFMIP_BECKMANN 2
#define NDFMIP_GGX 3

struct NdfmipMaterial {
    int brdf;        // NDFMIP_LAMBERT .. NDFMIP_GGX
    float exponent;  // Blinn-Phong s
    float roughness; // Beckmann / GGX alpha (not perceptual)
    vec3 specular;   // specular colour
};

// Normalised Blinn-Phong lobe over half vectors, (s + 1)/(2 pi) (n.h)^s (Toksvig eq. 7; Han et
// al. eq. 28). pow(0, 0) is undefined in GLSL: s = 0 is the constant lobe.
float ndfmipBlinnPhong(float cosH, float s) {
    float c = max(cosH, 0.0f);
    return (s + 1.0f) / (2.0f * NDFMIP_PI) * (s > 0.0f ? pow(c, s) : 1.0f);
}

// Beckmann distribution, projected area normalised: exp(-tan^2 t / a^2) / (pi a^2 cos^4 t).
float ndfmipBeckmann(float cosH, float alpha) {
    if (cosH <= 0.0f) return 0.0f;
    float c2 = cosH * cosH;
    float a2 = alpha * alpha;
    return exp((c2 - 1.0f) / (c2 * a2)) / (NDFMIP_PI * a2 * c2 * c2);
}

// GGX (Trowbridge-Reitz): a^2 / (pi (cos^2 t (a^2 - 1) + 1)^2).
float ndfmipGgx(float cosH, float alpha) {
    if (cosH <= 0.0f) return 0.0f;
    float a2 = alpha * alpha;
    float d = cosH * cosH * (a2 - 1.0f) + 1.0f;
    return a2 / (NDFMIP_PI * d * d);
}

// The material's lobe at n.h with a given exponent (Blinn-Phong) or alpha (Beckmann, GGX).
float ndfmipLobe(int brdf, float cosH, float exponent, float alpha) {
    if (brdf == NDFMIP_BLINN_PHONG) return ndfmipBlinnPhong(cosH, exponent);
    if (brdf == NDFMIP_BECKMANN) return ndfmipBeckmann(cosH, alpha);
    if (brdf == NDFMIP_GGX) return ndfmipGgx(cosH, alpha);
    return 0.0f;
}

// The lobe read as a vMF concentration about h: Blinn-Phong (n.h)^s ~ exp(s (n.h - 1)), so s;
// Beckmann and GGX through Walter et al.'s s = 2/alpha^2 - 2.
float ndfmipLobeConcentration(NdfmipMaterial m) {
    if (m.brdf == NDFMIP_BLINN_PHONG) return m.exponent;
    if (m.brdf == NDFMIP_BECKMANN || m.brdf == NDFMIP_GGX)
        return max(2.0f / max(m.roughness * m.roughness, 1e-8f) - 2.0f, 0.0f);
    return 0.0f;
}

// Banerjee et al.'s concentration for a mean resultant length r (H Algorithm 1, line 13):
// kappa = r (3 - r^2) / (1 - r^2); 0 for r <= 0 (or NaN), 1e30 (a single normal) for r >= 1.
float ndfmipKappaFromLength(float r) {
    if (!(r > 0.0f)) return 0.0f;
    if (r >= 1.0f) return 1e30f;
    return r * (3.0f - r * r) / ((1.0f - r) * (1.0f + r));
}

// Langevin's function A(k) = coth(k) - 1/k, the mean length of a vMF of concentration k: k/3
// below 1e-3, where it cancels; coth is 1 to float precision beyond k = 20, and some GPUs' tanh
// overflows to NaN there (exp(2k) / exp(2k)).
float ndfmipLangevin(float k) {
    if (k < 1e-3f) return k / 3.0f;
    return (k > 20.0f ? 1.0f : 1.0f / tanh(k)) - 1.0f / k;
}

// The cosine of a filtered specular term: the mean n.l over the normals that reflect. An NDF
// lobe of concentration kappa about mu times the BRDF lobe (lobeKappa about h) is a vMF of
// natural parameter w = kappa mu + lobeKappa h, whose mean normal is A(|w|) w/|w| (Langevin's
// A). kappa >= 1e30 stands for a single normal.
float ndfmipSpecularCosine(vec3 mu, float kappa, float lobeKappa, vec3 h, vec3 l) {
    if (!(kappa < 1e30f)) return max(dot(mu, l), 0.0f);
    vec3 w = kappa * mu + lobeKappa * h;
    float k = sqrt(dot(w, w));
    if (!(k > 0.0f)) return 0.0f;
    float meanLength = ndfmipLangevin(k);
    return max(meanLength * dot(w, l) / k, 0.0f);
}

// An engine's geometric specular anti-aliasing (Kaplanyan 2016; Tokuyoshi and Kaplanyan 2019, as
// Filament and HDRP shade it): the shading normal's change to the next pixel across and down
// (du, dv) taken as a spread within the pixel, 2 variance (|du|^2 + |dv|^2) added to alpha^2 up to
// `threshold`. ndfmipSpecularAaAlpha: alpha so widened, alpha^2 at most 1.
float ndfmipSpecularAaKernel(vec3 du, vec3 dv, float variance, float threshold) {
    return min(2.0f * variance * (dot(du, du) + dot(dv, dv)), threshold);
}
float ndfmipSpecularAaAlpha(float alpha, float kernel) {
    return sqrt(min(alpha * alpha + kernel, 1.0f));
}
// A stored roughness (alpha, or the perceptual sqrt(alpha)) so widened, in its own encoding.
float ndfmipSpecularAaStored(float stored, bool isAlpha, float kernel) {
    float r = clamp(stored, 0.0f, 1.0f);
    float widened = ndfmipSpecularAaAlpha(isAlpha ? r : r * r, kernel);
    return isAlpha ? widened : sqrt(widened);
}

// One true unit normal n, h = normalize(l + v): max(n.l, 0) (albedo / pi + specular D(n.h));
// the ground truth's integrand.
vec3 ndfmipShadeNormal(NdfmipMaterial m, vec3 albedo, vec3 n, vec3 l, vec3 h) {
    float cosL = max(dot(n, l), 0.0f);
    if (cosL <= 0.0f) return vec3(0.0f);
    float lobe = ndfmipLobe(m.brdf, dot(n, h), m.exponent, m.roughness);
    return cosL * (albedo * (1.0f / NDFMIP_PI) + m.specular * lobe);
}
