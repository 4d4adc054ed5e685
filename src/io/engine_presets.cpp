// Engine presets (see engine_presets.h; sources in docs/ENGINES.md).
#include "ndfmip/engine_presets.h"

namespace ndfmip {

const std::vector<EnginePreset>& enginePresets() {
    using C = MaterialChannel;
    using A = AnisotropyInput;
    static const std::vector<EnginePreset> presets = {
        // glTF 2.0: +Y up normals; metallicRoughness G roughness, B metallic; occlusion R
        // (packed into the same texture's R, the common ORM layout).
        {"gltf",
         false,
         "normal",
         "occlusion_roughness_metallic",
         {C::Occlusion, C::Roughness, C::Metallic, C::One},
         A::Khr},
        // Unreal: DirectX (-Y) normals; ORM packing R AO, G roughness, B metallic.
        {"unreal",
         true,
         "normal",
         "occlusion_roughness_metallic",
         {C::Occlusion, C::Roughness, C::Metallic, C::One},
         A::Unreal},
        // Unity HDRP mask map: R metallic, G AO, B detail mask, A smoothness; +Y normals.
        {"unity",
         false,
         "normal",
         "mask_map",
         {C::Metallic, C::Occlusion, C::One, C::Smoothness},
         A::UnityHdrp},
        // Godot 4 ORMMaterial3D: R AO, G roughness, B metallic; +Y (OpenGL) normals.
        {"godot",
         false,
         "normal",
         "orm",
         {C::Occlusion, C::Roughness, C::Metallic, C::One},
         A::Godot},
        // Filament (and its glTF loader): +Y normals, perceptual roughness; glTF packing.
        {"filament",
         false,
         "normal",
         "occlusion_roughness_metallic",
         {C::Occlusion, C::Roughness, C::Metallic, C::One},
         A::Khr},
        // Bevy: glTF's conventions (StandardMaterial metallic_roughness_texture, occlusion R).
        {"bevy",
         false,
         "normal",
         "occlusion_roughness_metallic",
         {C::Occlusion, C::Roughness, C::Metallic, C::One},
         A::Khr},
        // three.js: glTF's conventions (roughnessMap G, metalnessMap B, aoMap R).
        {"three",
         false,
         "normal",
         "occlusion_roughness_metallic",
         {C::Occlusion, C::Roughness, C::Metallic, C::One},
         A::Khr},
    };
    return presets;
}

const EnginePreset* findEnginePreset(const std::string& name) {
    for (const EnginePreset& p : enginePresets())
        if (name == p.name) return &p;
    return nullptr;
}

std::string enginePresetNames() {
    std::string names;
    for (const EnginePreset& p : enginePresets()) {
        if (!names.empty()) names += ", ";
        names += p.name;
    }
    return names;
}

} // namespace ndfmip
