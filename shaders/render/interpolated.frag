// ndfmip's GPU renderer, fragment stage for faceted-sphere scenes (interpolated normals): per
// pixel the CPU's renderInterpolated (src/render/interpolated_render.cpp) with one sample at
// the pixel's centre. renormalized shades the renormalised interpolated normal; cubemap-toksvig
// (Toksvig, "Anti-aliasing Specular Highlights from Interpolated Normals") looks the
// interpolated normal up in the normalisation cube map mipmapped without renormalisation, at
// the LOD of the normal's change to the neighbouring pixels, and shades the shortened result
// as Na: |Na| widens the lobe (T eqs. 1 and 6). Needs the library, raycast.glsl and faceted.glsl.

#define NDFMIP_MAX_LIGHTS 16
#define NDFMIP_INTERPOLATED_RENORMALIZED 0
#define NDFMIP_INTERPOLATED_CUBEMAP_TOKSVIG 1

uniform vec3 ndfmipBackground;
uniform int ndfmipLightCount;
uniform int ndfmipLightType[NDFMIP_MAX_LIGHTS]; // 0 directional, 1 point
uniform vec3 ndfmipLightDirection[NDFMIP_MAX_LIGHTS];
uniform vec3 ndfmipLightPosition[NDFMIP_MAX_LIGHTS];
uniform vec3 ndfmipLightColor[NDFMIP_MAX_LIGHTS];
uniform vec2 ndfmipPixelShift;

uniform int ndfmipInterpolatedMethod; // NDFMIP_INTERPOLATED_*
uniform int ndfmipMapping;            // cubemap-toksvig: the roughness mapping (toksvig.glsl)
uniform float ndfmipVarianceScale;

layout(location = 0) out vec4 ndfmipColour;

vec3 ndfmipShadeInterpolated(float px, float py) {
    NdfmipRay ray = ndfmipCameraRay(px, py);
    NdfmipFacetedHit hit = ndfmipIntersectFaceted(ray);
    if (!hit.hit) return ndfmipBackground;
    vec3 view = -ray.direction;
    if (dot(view, hit.faceNormal) <= 0.0f) return vec3(0.0f); // inside the sphere
    vec3 normal = normalize(hit.interpolated);
    bool toksvig = ndfmipInterpolatedMethod == NDFMIP_INTERPOLATED_CUBEMAP_TOKSVIG;
    if (toksvig) {
        // The analytic ray differentials the CPU uses (not dFdx): the neighbours' rays on
        // the hit triangle's plane.
        vec3 nx = ndfmipInterpolatedOnPlane(hit.triangle, ndfmipCameraRay(px + 1.0f, py), hit.interpolated);
        vec3 ny = ndfmipInterpolatedOnPlane(hit.triangle, ndfmipCameraRay(px, py + 1.0f), hit.interpolated);
        float lod = ndfmipNormalCubeLod(hit.interpolated, nx, ny) + ndfmipNormalCubeLodBias;
        normal = textureLod(ndfmipNormalCube, hit.interpolated, lod).xyz;
    }
    vec3 radiance = vec3(0.0f);
    for (int i = 0; i < ndfmipLightCount; ++i) {
        vec3 l = ndfmipLightDirection[i];
        vec3 irradiance = ndfmipLightColor[i];
        if (ndfmipLightType[i] == 1) { // point lights fall off as 1/d^2
            vec3 d = ndfmipLightPosition[i] - hit.position;
            float d2 = dot(d, d);
            l = d2 > 0.0f ? d / sqrt(d2) : vec3(0.0f, 0.0f, 1.0f);
            irradiance = d2 > 0.0f ? ndfmipLightColor[i] / d2 : vec3(0.0f);
        }
        if (dot(l, hit.faceNormal) <= 0.0f) continue; // behind the facet
        // World space: the shade functions read only dot products.
        if (toksvig)
            radiance += irradiance * ndfmipShadeToksvig(ndfmipMaterial, ndfmipMaterialAlbedo, normal, l, view,
                                                        ndfmipMapping, ndfmipVarianceScale);
        else
            radiance += irradiance * ndfmipShadeNormal(ndfmipMaterial, ndfmipMaterialAlbedo, normal, l, normalize(l + view));
    }
    return radiance;
}

void main() {
    // The CPU renderer's pixel (x, y) from the top-left, sampled at its centre.
    float px = gl_FragCoord.x + ndfmipPixelShift.x;
    float py = ndfmipImageSize.y - gl_FragCoord.y + ndfmipPixelShift.y;
    ndfmipColour = vec4(ndfmipShadeInterpolated(px, py), 1.0f);
}
