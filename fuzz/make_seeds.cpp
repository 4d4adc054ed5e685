// Writes the fuzzers' seed corpora: fuzz_seeds OUT REPO [SHARED_DATA]. Small images in every
// format ndfmip reads, cut from the bundled map and from SHARED_DATA's normal and environment
// maps when that folder exists; the example scenes and BRDF tables; the manifests of one small
// bake per method. Seeds stay small so that the fuzzers spend their time mutating, not decoding.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>

#include <nlohmann/json.hpp>

#include "fuzz_bakes.h"
#include "ndfmip/environment.h"
#include "ndfmip/io.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

using ndfmip::Image;

void writeBytes(const fs::path& path, const std::string& bytes) {
    std::FILE* file = std::fopen(path.c_str(), "wb");
    if (!file) return;
    std::fwrite(bytes.data(), 1, bytes.size(), file);
    std::fclose(file);
}

// The top-left w x h texels of `image` (fewer where it is smaller).
Image crop(const Image& image, int w, int h) {
    w = std::min(w, image.width), h = std::min(h, image.height);
    Image out(w, h, image.channels);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < image.channels; ++c) out.at(x, y)[c] = image.at(x, y)[c];
    return out;
}

std::vector<unsigned char> bytes8(const Image& image) {
    std::vector<unsigned char> out(image.pixels.size());
    for (size_t i = 0; i < out.size(); ++i)
        out[i] = static_cast<unsigned char>(std::clamp(image.pixels[i], 0.f, 1.f) * 255.f + 0.5f);
    return out;
}

// `image` in every format, as DIR/STEM.<format>.
void writeAllFormats(const fs::path& dir, const std::string& stem, const Image& image) {
    const std::string base = (dir / stem).string();
    ndfmip::savePng(base + ".8.png", image, 8);
    ndfmip::savePng(base + ".16.png", image, 16);
    ndfmip::saveExr(base + ".float.exr", image);
    ndfmip::saveExr(base + ".half.exr", image, {}, true);
    const std::vector<unsigned char> b = bytes8(image);
    const int w = image.width, h = image.height, c = image.channels;
    stbi_write_tga_with_rle = 0;
    stbi_write_tga((base + ".raw.tga").c_str(), w, h, c, b.data());
    stbi_write_tga_with_rle = 1;
    stbi_write_tga((base + ".rle.tga").c_str(), w, h, c, b.data());
    stbi_write_bmp((base + ".bmp").c_str(), w, h, c, b.data());
    stbi_write_jpg((base + ".jpg").c_str(), w, h, c, b.data(), 90);
    if (c == 3) stbi_write_hdr((base + ".hdr").c_str(), w, h, c, image.pixels.data());
}

void imageSeeds(const fs::path& out, const fs::path& repo, const fs::path& shared) {
    const fs::path dir = out / "image";
    fs::create_directories(dir);
    Image gradient(3, 2, 3);
    for (size_t i = 0; i < gradient.pixels.size(); ++i) gradient.pixels[i] = float(i) / 17.f;
    writeAllFormats(dir, "gradient", gradient);
    Image grey(9, 4, 1);
    for (size_t i = 0; i < grey.pixels.size(); ++i) grey.pixels[i] = float(i % 7) / 6.f;
    writeAllFormats(dir, "grey", grey);
    std::vector<fs::path> sources = {repo / "data" / "normalmaps" / "pyramidwall_256.png"};
    for (const char* sub : {"normalmaps", "envmaps"}) {
        if (shared.empty() || !fs::is_directory(shared / sub)) continue;
        for (const auto& entry : fs::directory_iterator(shared / sub))
            if (entry.path().extension() != ".md") sources.push_back(entry.path());
    }
    int n = 0;
    for (const fs::path& source : sources) {
        ndfmip::Result<ndfmip::SourceImage> image = ndfmip::loadImage(source.string());
        if (!image) continue;
        Image rgb = crop(image->image, 24, 16);
        if (image->format == "hdr") {
            // Radiance files: run-length scanlines (width 24) from real data.
            stbi_write_hdr((dir / ("env" + std::to_string(n++) + ".hdr")).c_str(), rgb.width,
                           rgb.height, 3, rgb.pixels.data());
            continue;
        }
        writeAllFormats(dir, "map" + std::to_string(n++), rgb);
    }
}

void sceneSeeds(const fs::path& out, const fs::path& repo) {
    const fs::path dir = out / "scene";
    fs::create_directories(dir);
    for (const auto& entry : fs::directory_iterator(repo / "scenes"))
        fs::copy_file(entry.path(), dir / entry.path().filename(),
                      fs::copy_options::overwrite_existing);
    const json camera = {
        {"type", "orthographic"}, {"eye", {0, 0, 2}}, {"target", {0, 0, 0}}, {"up", {0, 1, 0}},
        {"ortho_height", 2},      {"width", 8},       {"height", 8}};
    const json point = {
        {"type", "point"}, {"position", {1, 2, 3}}, {"color", 0.5}, {"intensity", 2}};
    json scene = {{"camera", camera},
                  {"object", {{"type", "sphere"}, {"radius", 1}, {"tiling", {2, 1}}}},
                  {"lights", {point}},
                  {"material", {{"brdf", "ggx"}, {"roughness", 0.3}, {"albedo", {0.2, 0.3, 0.4}}}},
                  {"normal_map",
                   {{"path", "map.png"},
                    {"green_down", true},
                    {"two_channel", false},
                    {"signed", false},
                    {"height_scale", 2},
                    {"address", "clamp"}}},
                  {"method", "vmf"},
                  {"bake", "bake"},
                  {"albedo_map", "albedo.png"},
                  {"background", 0.1}};
    writeBytes(dir / "every_key.json", scene.dump(1));
    scene["material"] = {{"brdf", "tabulated"}, {"table", "f.txt"}, {"g_table", "g.txt"}};
    writeBytes(dir / "tables.json", scene.dump());
}

void manifestSeeds(const fs::path& out) {
    const fs::path dir = out / "manifest", bakes = out / "bakes";
    fs::create_directories(dir);
    if (!ndfmip::writeFuzzBakes(bakes)) return;
    for (const char* method : {"naive", "toksvig", "sh", "vmf"})
        fs::copy_file(bakes / method / "manifest.json", dir / (std::string(method) + ".json"),
                      fs::copy_options::overwrite_existing);
    fs::remove_all(bakes);
}

void tableSeeds(const fs::path& out, const fs::path& repo) {
    const fs::path dir = out / "brdf_table";
    fs::create_directories(dir);
    for (const auto& entry : fs::directory_iterator(repo / "data" / "brdf"))
        fs::copy_file(entry.path(), dir / entry.path().filename(),
                      fs::copy_options::overwrite_existing);
    writeBytes(dir / "small.txt", "# two rows\ntheta_h_degrees f\n0 1\n+90 0.5e-1\n");
    writeBytes(dir / "crlf.txt", "theta_d_degrees g\r\n0 0.04\r\n45 0.2\r\n90 1\r\n");
}

std::string base64(const std::string& bytes) {
    static const char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        uint32_t n = uint32_t(uint8_t(bytes[i])) << 16;
        if (i + 1 < bytes.size()) n |= uint32_t(uint8_t(bytes[i + 1])) << 8;
        if (i + 2 < bytes.size()) n |= uint32_t(uint8_t(bytes[i + 2]));
        out += digits[(n >> 18) & 63];
        out += digits[(n >> 12) & 63];
        out += i + 1 < bytes.size() ? digits[(n >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? digits[n & 63] : '=';
    }
    return out;
}

// A .gltf with its images as data URIs: an 8x8 normal map (a bump) and a metallic-roughness map,
// two materials sharing them the ways the filter tells apart.
void gltfSeeds(const fs::path& out) {
    const fs::path dir = out / "gltf";
    fs::create_directories(dir);
    ndfmip::Image normals(8, 8, 3), material(8, 8, 3);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            const float nx = 0.3f * float(x - 4) / 4.f, ny = 0.3f * float(y - 4) / 4.f;
            const float nz = std::sqrt(1.f - nx * nx - ny * ny);
            float* n = normals.at(x, y);
            n[0] = 0.5f * (nx + 1.f), n[1] = 0.5f * (ny + 1.f), n[2] = 0.5f * (nz + 1.f);
            float* m = material.at(x, y);
            m[0] = 1.f, m[1] = 0.2f + 0.05f * float(x), m[2] = float(y % 2);
        }
    auto uri = [](const ndfmip::Image& image) {
        ndfmip::Result<std::string> png = ndfmip::encodePng(image, 8);
        return "data:image/png;base64," + (png ? base64(png.value()) : std::string());
    };
    nlohmann::ordered_json asset = {
        {"asset", {{"version", "2.0"}}},
        {"images", {{{"uri", uri(normals)}}, {{"uri", uri(material)}}}},
        {"textures", {{{"source", 0}}, {{"source", 1}}}},
        {"materials",
         {{{"name", "a"},
           {"normalTexture", {{"index", 0}}},
           {"occlusionTexture", {{"index", 1}}},
           {"pbrMetallicRoughness",
            {{"metallicRoughnessTexture", {{"index", 1}}}, {"roughnessFactor", 0.8}}}},
          {{"name", "b"}, {"normalTexture", {{"index", 0}, {"scale", 0.5}}}}}}};
    writeBytes(dir / "two_materials.gltf", asset.dump());
}

// Environment maps for fuzz_envmap: small equirectangular maps (2:1) as Radiance HDR and
// OpenEXR, resampled from SHARED_DATA's environment maps, and a sky with a sun made here.
void envmapSeeds(const fs::path& out, const fs::path& shared) {
    const fs::path dir = out / "envmap";
    fs::create_directories(dir);
    Image sky(16, 8, 3);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x) {
            float* v = sky.at(x, y);
            v[0] = 0.2f + 0.1f * float(y), v[1] = 0.3f + 0.05f * float(y), v[2] = 1.f;
        }
    sky.at(5, 2)[0] = sky.at(5, 2)[1] = sky.at(5, 2)[2] = 5e4f; // a sun
    stbi_write_hdr((dir / "sky.hdr").c_str(), sky.width, sky.height, 3, sky.pixels.data());
    ndfmip::saveExr((dir / "sky.exr").string(), sky);
    ndfmip::saveExr((dir / "sky.half.exr").string(), sky, {}, true);
    if (shared.empty() || !fs::is_directory(shared / "envmaps")) return;
    int n = 0;
    for (const auto& entry : fs::directory_iterator(shared / "envmaps")) {
        ndfmip::Result<ndfmip::SourceImage> image = ndfmip::loadImage(entry.path().string());
        if (!image || image->image.width != 2 * image->image.height || image->image.channels < 3)
            continue;
        Image rgb(image->image.width, image->image.height, 3);
        for (size_t i = 0; i < rgb.texelCount(); ++i)
            for (int c = 0; c < 3; ++c)
                rgb.pixels[3 * i + size_t(c)] =
                    image->image.pixels[i * size_t(image->image.channels) + size_t(c)];
        const Image small = ndfmip::resampleEquirect(rgb, 32);
        const std::string stem = (dir / ("env" + std::to_string(n++))).string();
        stbi_write_hdr((stem + ".hdr").c_str(), small.width, small.height, 3, small.pixels.data());
        ndfmip::saveExr(stem + ".exr", small);
    }
}

// .gltf texts for fuzz_gltf_bake, whose "@NORMAL_PNG@" strings the target replaces with a
// data uri of a valid normal map: materials sharing it the ways the filter tells apart.
void gltfBakeSeeds(const fs::path& out) {
    const fs::path dir = out / "gltf_bake";
    fs::create_directories(dir);
    nlohmann::ordered_json asset = {
        {"asset", {{"version", "2.0"}}},
        {"images", {{{"uri", "@NORMAL_PNG@"}}, {{"uri", "@NORMAL_PNG@"}}}},
        {"samplers", {{{"wrapS", 33071}, {"wrapT", 10497}}}},
        {"textures", {{{"source", 0}}, {{"source", 1}, {"sampler", 0}}}},
        {"materials",
         {{{"name", "a"}, {"normalTexture", {{"index", 0}}}},
          {{"name", "b"}, {"normalTexture", {{"index", 0}, {"scale", 0.5}}}},
          {{"name", "c"},
           {"normalTexture", {{"index", 1}}},
           {"pbrMetallicRoughness",
            {{"metallicRoughnessTexture", {{"index", 0}}}, {"roughnessFactor", 0.4}}}}}}};
    writeBytes(dir / "three_materials.gltf", asset.dump());
    nlohmann::ordered_json one = {{"asset", {{"version", "2.0"}}},
                                  {"images", {{{"uri", "@NORMAL_PNG@"}}}},
                                  {"textures", {{{"source", 0}}}},
                                  {"materials", {{{"normalTexture", {{"index", 0}}}}}}};
    writeBytes(dir / "one_material.gltf", one.dump());
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: fuzz_seeds OUT REPO [SHARED_DATA]\n");
        return 2;
    }
    const fs::path out = argv[1], repo = argv[2];
    const fs::path shared = argc > 3 && fs::is_directory(argv[3]) ? fs::path(argv[3]) : fs::path();
    imageSeeds(out, repo, shared);
    sceneSeeds(out, repo);
    manifestSeeds(out);
    tableSeeds(out, repo);
    gltfSeeds(out);
    envmapSeeds(out, shared);
    gltfBakeSeeds(out);
    std::printf("fuzz_seeds: %s%s\n", out.c_str(),
                shared.empty() ? " (no shared data: bundled files only)" : "");
    return 0;
}
