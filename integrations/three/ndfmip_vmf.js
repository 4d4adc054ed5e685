// ndfmip's vMF lobes in three.js: MeshStandardMaterial shaded with the lobe textures of
// `ndfmip bake --method vmf --export ktx2 --export-textures planes` (lobe0.ktx2 .. lobe<J-1>.ktx2,
// each (alpha, alpha r mu) per texel with every level ndfmip's; Han et al. 2007, eq. 33).
//
//   import { loadVmfLobes, useVmfLobes } from './ndfmip_vmf.js';
//   const lobes = await loadVmfLobes(ktx2Loader, ['bake/ktx2/lobe0.ktx2', ...]);
//   const material = new THREE.MeshStandardMaterial({ color, roughness, metalness: 0 });
//   useVmfLobes(material, { lobes, tiling: [1, 1] });
//
// The formulas are the library's own (ndfmip_vmf_glsl.js, generated from shaders/brdf.glsl and
// shaders/vmf.glsl at build time); this file only joins them to three's lighting:
// - point and directional lights (three's RE_Direct): the sum over lobes of ndfmipShadeVmfLobe,
//   GGX with alpha = roughness² (three's perceptual roughness, roughnessMap included), albedo the
//   material's diffuse colour (map included), times the light's colour: three's irradiance
//   (a point light's falls off as 1/d² with decay 2 and distance 0), as ndfmip's renderer does;
// - the scene's environment (a PMREM envMap): per lobe, three's irradiance about the lobe's mean
//   normal mu and three's prefiltered radiance about mu at the widened roughness
//   (ndfmipVmfWidenedAlpha), weighted by the lobe's alpha; three's own split-sum factors
//   (Fresnel, its DFG table at the material's roughness) then apply as for any standard material.
// The surface's tangent frame is ndfmip's: z the geometric normal, x the texture's u direction,
// y = z × x; texture rows run from the top (v = 1 of the mesh's uv) as the bake stores them.
import * as THREE from 'three';
import { ndfmipVmfGlsl } from './ndfmip_vmf_glsl.js';

export { ndfmipVmfGlsl };

// Sampling as the bake's planes need it (docs/SHADERS.md): the file's levels as the mips, never
// generated, trilinear, repeat, linear data.
export function prepareLobeTexture(texture) {
    texture.wrapS = texture.wrapT = THREE.RepeatWrapping;
    texture.minFilter = THREE.LinearMipmapLinearFilter;
    texture.magFilter = THREE.LinearFilter;
    texture.generateMipmaps = false;
    texture.colorSpace = THREE.NoColorSpace;
    texture.needsUpdate = true;
    return texture;
}

// Loads the lobe textures (KTX2 RGBA16F, `bake --half`; RGBA32F filters only where the browser
// has OES_texture_float_linear) with a KTX2Loader on which detectSupport was called; rejects,
// naming the file, when one cannot be read.
export async function loadVmfLobes(ktx2Loader, urls) {
    return Promise.all(urls.map(url => ktx2Loader.loadAsync(url).then(prepareLobeTexture, error => {
        throw new Error(`ndfmip_vmf: cannot load ${url}: ${error && error.message ? error.message : error}`);
    })));
}

// The GLSL joined to MeshStandardMaterial's fragment shader for J lobes.
function declarations(count) {
    const samplers = Array.from({ length: count }, (_, j) => `uniform sampler2D ndfmipLobe${j};`).join('\n');
    return /* glsl */ `
${ndfmipVmfGlsl}
#define NDFMIP_THREE_LOBES ${count}
${samplers}
uniform vec2 ndfmipTiling;
uniform vec3 ndfmipSpecular;

// Set in main() before the lights: the lobes' texels, the tangent frame (view space), the albedo
// and the GGX alpha.
vec4 ndfmipTexels[NDFMIP_THREE_LOBES];
vec3 ndfmipTangent;
vec3 ndfmipBitangent;
vec3 ndfmipNormal;
vec3 ndfmipAlbedo;
float ndfmipAlpha;

vec3 ndfmipToTangent(vec3 w) { return vec3(dot(w, ndfmipTangent), dot(w, ndfmipBitangent), dot(w, ndfmipNormal)); }
vec3 ndfmipFromTangent(vec3 w) { return w.x * ndfmipTangent + w.y * ndfmipBitangent + w.z * ndfmipNormal; }

NdfmipMaterial ndfmipThreeMaterial() {
    NdfmipMaterial m;
    m.brdf = NDFMIP_GGX;
    m.exponent = 0.0;
    m.roughness = ndfmipAlpha;
    m.specular = ndfmipSpecular;
    return m;
}

// three's RE_Direct: the lobe sum per unit irradiance (it carries the cosine) times the light's
// colour; lights below the geometric horizon, or a viewer there, add nothing (as in ndfmip's renderer).
void RE_Direct_NdfmipVmf(const in IncidentLight directLight, const in vec3 geometryPosition, const in vec3 geometryNormal,
                         const in vec3 geometryViewDir, const in vec3 geometryClearcoatNormal,
                         const in PhysicalMaterial material, inout ReflectedLight reflectedLight) {
    vec3 l = ndfmipToTangent(directLight.direction);
    vec3 v = ndfmipToTangent(geometryViewDir);
    if (l.z <= 0.0 || v.z <= 0.0) return;
    NdfmipMaterial m = ndfmipThreeMaterial();
    vec3 sum = vec3(0.0);
    for (int j = 0; j < NDFMIP_THREE_LOBES; ++j) sum += ndfmipShadeVmfLobe(m, ndfmipAlbedo, ndfmipTexels[j], l, v);
    reflectedLight.directDiffuse += directLight.color * sum;
}
#undef RE_Direct
#define RE_Direct RE_Direct_NdfmipVmf
`;
}

// In main(), after the normal is known: the frame (z the interpolated geometric normal, x the
// texture's u direction from screen derivatives, as three's own tangent frame is made), then the
// lobes' texels (hardware trilinear at the pixel's footprint).
function setup(count) {
    const fetches = Array.from({ length: count },
        (_, j) => `ndfmipTexels[${j}] = texture(ndfmipLobe${j}, ndfmipUv);`).join('\n    ');
    return /* glsl */ `
{
    vec2 ndfmipUv = vec2(vUv.x, 1.0 - vUv.y) * ndfmipTiling;
    ndfmipNormal = normalize(nonPerturbedNormal);
    vec3 q0 = dFdx(-vViewPosition);
    vec3 q1 = dFdy(-vViewPosition);
    vec2 st0 = dFdx(vUv);
    vec2 st1 = dFdy(vUv);
    // dp/du from dp = q0 dx + q1 dy and (du, dv) = (st0 dx + st1 dy): the 2x2 system inverted.
    float det = st0.x * st1.y - st1.x * st0.y;
    vec3 dpdu = (q0 * st1.y - q1 * st0.y) * (det < 0.0 ? -1.0 : 1.0);
    ndfmipTangent = normalize(dpdu - dot(dpdu, ndfmipNormal) * ndfmipNormal);
    ndfmipBitangent = cross(ndfmipNormal, ndfmipTangent);
    ndfmipAlbedo = diffuseColor.rgb;
    ndfmipAlpha = roughnessFactor * roughnessFactor;
    ${fetches}
}
`;
}

// The environment: per lobe, irradiance and prefiltered radiance about its mean normal.
function environment() {
    return /* glsl */ `
#if defined( RE_IndirectDiffuse ) && defined( USE_LIGHTMAP )
    irradiance += texture2D( lightMap, vLightMapUv ).rgb * lightMapIntensity;
#endif
#if defined( USE_ENVMAP ) && defined( ENVMAP_TYPE_PMREM )
{
    for (int j = 0; j < NDFMIP_THREE_LOBES; ++j) {
        NdfmipLobe lobe = ndfmipUnpackLobe(ndfmipTexels[j]);
        if (!(lobe.alpha > 0.0)) continue;
        vec3 mu = ndfmipFromTangent(lobe.mu);
        iblIrradiance += lobe.alpha * getIBLIrradiance(mu);
        float roughnessJ = sqrt(ndfmipVmfWidenedAlpha(ndfmipAlpha, lobe.kappa));
        radiance += lobe.alpha * getIBLRadiance(geometryViewDir, mu, roughnessJ);
    }
}
#endif
`;
}

// Makes `material` (a MeshStandardMaterial or MeshPhysicalMaterial) shade with the lobes:
// options.lobes the J textures (loadVmfLobes), options.tiling the texture repeats over the uv
// square (default [1, 1]), options.specular ndfmip's specular colour (default [1, 1, 1]).
// Returns the material; its uniforms are material.userData.ndfmip.
export function useVmfLobes(material, options) {
    const lobes = options.lobes;
    if (!Array.isArray(lobes) || lobes.length < 1 || lobes.length > 8)
        throw new Error('ndfmip_vmf: options.lobes must hold 1 to 8 lobe textures');
    const uniforms = {
        ndfmipTiling: { value: new THREE.Vector2(...(options.tiling || [1, 1])) },
        ndfmipSpecular: { value: new THREE.Vector3(...(options.specular || [1, 1, 1])) },
    };
    lobes.forEach((texture, j) => { uniforms[`ndfmipLobe${j}`] = { value: texture }; });
    material.userData.ndfmip = uniforms;
    material.defines = Object.assign(material.defines || {}, { USE_UV: '' });
    material.onBeforeCompile = shader => {
        Object.assign(shader.uniforms, uniforms);
        const replace = (text, chunk, by) => {
            if (!text.includes(chunk)) throw new Error(`ndfmip_vmf: three's shader has no ${chunk}`);
            return text.replace(chunk, by);
        };
        let fs = shader.fragmentShader;
        fs = replace(fs, '#include <lights_physical_pars_fragment>',
                     '#include <lights_physical_pars_fragment>\n' + declarations(lobes.length));
        fs = replace(fs, '#include <normal_fragment_maps>', '#include <normal_fragment_maps>\n' + setup(lobes.length));
        fs = replace(fs, '#include <lights_fragment_maps>', environment());
        shader.fragmentShader = fs;
    };
    material.customProgramCacheKey = () => `ndfmip-vmf-${lobes.length}`;
    material.needsUpdate = true;
    return material;
}
