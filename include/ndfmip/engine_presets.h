// What engines expect of a normal map and a packed material map: the normal's green
// convention, which channel holds roughness (perceptual) or smoothness, metallic and ambient
// occlusion, and the file names. docs/ENGINES.md lists the sources and how to load the files.
#pragma once

#include <string>
#include <vector>

namespace ndfmip {

enum class MaterialChannel { Zero, One, Roughness, Smoothness, Metallic, Occlusion };

// How an engine takes one anisotropic GGX lobe per texel: the files a lean bake writes for it,
// besides the mean slope's normal and the packed map's roughness (docs/ENGINES.md has the
// sources and how to wire each).
enum class AnisotropyInput {
    // KHR_materials_anisotropy: NAME_anisotropy RG the direction (d + 1)/2, B the strength;
    // roughness sqrt(alpha_b).
    Khr,
    // Unreal (Kulla): NAME_anisotropy RG the direction (d + 1)/2 in the normal map's frame (its
    // green down), B the Anisotropy input k; roughness sqrt((alpha_t + alpha_b) / 2).
    Unreal,
    // Unity HDRP (Kulla): NAME_tangent, a tangent map (RG the direction (d + 1)/2, B 0.5: import
    // it as a normal map), and NAME_anisotropy (R = G = B the Anisotropy k); smoothness
    // 1 - sqrt((alpha_t + alpha_b) / 2).
    UnityHdrp,
    // Godot 4 (Burley): NAME_anisotropy, its anisotropy flowmap (RG the direction (d + 1)/2, A
    // the anisotropy k, B 0); roughness (alpha_t alpha_b)^(1/4).
    Godot,
};

struct EnginePreset {
    const char* name;           // --engine NAME
    bool greenDown;             // normal map Y points down the texture (DirectX convention)
    const char* normalFile;     // file stem of the BC5 normal map
    const char* packedFile;     // file stem of the packed material map (RGBA8)
    MaterialChannel packed[4];  // R, G, B, A of the packed map
    AnisotropyInput anisotropy; // the files a lean bake writes for one anisotropic lobe
};

const std::vector<EnginePreset>& enginePresets();
const EnginePreset* findEnginePreset(const std::string& name); // null if unknown
std::string enginePresetNames();                               // "gltf, unreal, ..."

} // namespace ndfmip
