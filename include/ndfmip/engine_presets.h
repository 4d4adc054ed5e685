// What engines expect of a normal map and a packed material map: the normal's green
// convention, which channel holds roughness (perceptual) or smoothness, metallic and ambient
// occlusion, and the file names. docs/ENGINES.md lists the sources and how to load the files.
#pragma once

#include <string>
#include <vector>

namespace ndfmip {

enum class MaterialChannel { Zero, One, Roughness, Smoothness, Metallic, Occlusion };

struct EnginePreset {
    const char* name;          // --engine NAME
    bool greenDown;            // normal map Y points down the texture (DirectX convention)
    const char* normalFile;    // file stem of the BC5 normal map
    const char* packedFile;    // file stem of the packed material map (RGBA8)
    MaterialChannel packed[4]; // R, G, B, A of the packed map
    // Reads glTF's KHR_materials_anisotropy (an anisotropyTexture: RG direction, B strength;
    // roughness alpha_b): what a lean bake's engine files are written for.
    bool anisotropy = false;
};

const std::vector<EnginePreset>& enginePresets();
const EnginePreset* findEnginePreset(const std::string& name); // null if unknown
std::string enginePresetNames();                               // "gltf, unreal, ..."

} // namespace ndfmip
