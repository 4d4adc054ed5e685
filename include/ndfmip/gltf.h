// glTF assets filtered as a whole: every material's normal texture and metallic-roughness
// texture get ndfmip's mip chains (Toksvig's variance added to the material's own roughness,
// level by level), carried as DDS images by MSFT_texture_dds beside the untouched originals,
// in one GLB. docs/ENGINES.md ("glTF") has the rules and which loaders read what.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "ndfmip/result.h"

namespace ndfmip {

// What happened to one material.
struct GltfMaterialReport {
    std::string name; // the material's name, or "material N"
    int width = 0, height = 0, levels = 0;
    bool madeRoughnessMap = false; // it had no usable metallicRoughnessTexture: one was made
    size_t clampedTexels = 0;      // texels whose roughness went above roughnessFactor (G = 1)
    double milliseconds = 0.0;
};

struct GltfFiltered {
    std::string glb; // the whole output file
    std::vector<GltfMaterialReport> materials;
    std::vector<std::string> warnings; // one line each, e.g. normals facing into the surface
    int decodedImages = 0;             // images decoded: each distinct image once
    int bakes = 0; // the method's bakes: one per distinct normal image, material map and options
    int replacedImages = 0; // images of an earlier ndfmip gltf pass found and replaced
};

// How the levels reach the textures: UASTC KTX2 through KHR_texture_basisu (three.js,
// Babylon.js and most web engines read it), DDS through MSFT_texture_dds (BC5 normal, RGBA8
// material map), or both extensions on each texture.
enum class GltfTextureFormat { Basisu, Dds, Both };

// How a material's roughness takes the normals' spread (--method): toksvig, one isotropic
// roughness per texel (Toksvig's variance added to alpha^2), or sggx, one anisotropic GGX lobe
// per texel from the slope moments (alpha^2 I + 2 Sigma, as the sggx shader), written as
// KHR_materials_anisotropy: metallicRoughness G = sqrt(alpha_b), an anisotropyTexture of its
// own (RG the direction of alpha_t in the tangent frame as (d + 1)/2, B the strength s with
// alpha_t = mix(alpha_b, 1, s^2)), every level ndfmip's.
// ggx-fit: the roughness fitted to each texel's filtered NDF (bake --method ggx-fit
// --roughness-map), the material's alpha_0 per texel the lobes it widens.
// ggx-aniso: the anisotropic GGX lobe fitted to each texel's filtered NDF (bake --method
// ggx-aniso --roughness-map), written as KHR_materials_anisotropy as sggx's is.
enum class GltfMethod { Toksvig, Sggx, GgxFit, GgxAniso };

struct GltfOptions {
    GltfMethod method = GltfMethod::Toksvig;
    // --texture-format; Basisu needs the Basis Universal encoder (basisuEncoder in
    // texture_container.h), a one-line error without it.
    GltfTextureFormat textureFormat = GltfTextureFormat::Basisu;
    // Buffer and image uris may name files outside the asset's folder (absolute paths, file:,
    // '..'); by default they are refused.
    bool allowOutside = false;
};

// Reads `path` (.gltf with its files, or .glb) and filters every material that has a
// normalTexture. Per material, with n the decoded normal image (glTF's convention: (n + 1)/2,
// +Y up) and its metallicRoughnessTexture M of the same size (G roughness, B metallic):
//  - the normal texture gets the pyramid's mean normals, every level: (n + 1)/2 as UASTC RGB
//    and/or BC5 (x, y) DDS, as textureFormat says;
//  - M's texture gets UASTC (RGB) and/or RGBA8 DDS levels: G = sqrt(alpha_k) / roughnessFactor (at
//  most
//    1), alpha_k the Toksvig bake's GGX alpha with alpha_0 = (G roughnessFactor)^2 per texel;
//    R, B and A averaged over each texel's footprint;
//  - without M (or with roughnessFactor 0, which no texture can raise) a new
//    metallicRoughnessTexture is made: G = sqrt(alpha_k), R = B = A = 1 (B so metallicFactor
//    still governs), its core image a PNG of level 0, and roughnessFactor becomes 1.
// A texture shared with a use that needs other levels is copied for this use. Errors (one
// line starting with `path`): unreadable asset, no material with a normalTexture, a normal
// image that is missing, undecodable or no normal map (1 or 2 channels, or more than half its
// texels more than 10% off unit length or facing into the surface), a metallic-roughness image
// of another size, texture coordinates or transforms that differ between the two textures.
// Materials that read the same images with the same options share one bake and its images.
// An asset that ndfmip gltf wrote (its images and textures marked in their extras "ndfmip")
// is first put back as it was, so a second pass replaces the first's images. A texture to be
// given KHR_texture_basisu that already has one of the asset's own is refused.
Result<GltfFiltered> filterGltf(const std::string& path, const GltfOptions& options);
Result<GltfFiltered> filterGltf(const std::string& path);

} // namespace ndfmip
