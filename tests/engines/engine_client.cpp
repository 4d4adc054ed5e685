// The real-client tests' shared parts (engine_client.h).
#include "engines/engine_client.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "ndfmip/texture_container.h"
#include "test_support.h"

namespace ndfmip::test {

namespace fs = std::filesystem;

std::string findProgram(const char* name) {
    for (const char* dir : {"/usr/bin/", "/usr/local/bin/", "/bin/"}) {
        const std::string path = std::string(dir) + name;
        if (fs::exists(path)) return path;
    }
    return "";
}

std::string nodeModules() {
    const char* modules = std::getenv("NDFMIP_NODE_MODULES");
    return modules ? modules : std::string(NDFMIP_SOURCE_DIR) + "/.npm/node_modules";
}

std::string missingThreePage(const std::vector<std::string>& threeFiles, std::string* chromium,
                             std::string* node) {
    *chromium = findProgram("chromium");
    *node = findProgram("node");
    if (chromium->empty()) return "chromium not installed (scripts/setup installs it)";
    if (node->empty()) return "node not installed (scripts/setup installs nodejs)";
    const std::string three = nodeModules() + "/three";
    for (const std::string& file : threeFiles)
        if (!fs::exists(three + file))
            return "npm package three not installed (" + three + file +
                   " missing; scripts/setup installs three@0.187.0 into .npm/)";
    return "";
}

std::string missingGltfPage(std::string* chromium, std::string* node) {
    if (std::string missing =
            missingThreePage({"/build/three.module.js", "/examples/jsm/loaders/GLTFLoader.js",
                              "/examples/jsm/loaders/KTX2Loader.js",
                              "/examples/jsm/libs/basis/basis_transcoder.wasm"},
                             chromium, node);
        !missing.empty())
        return missing;
    if (Result<std::string> encoder = basisuEncoder(); !encoder) return encoder.error().message;
    return "";
}

int runThreePage(const std::string& node, const std::string& chromium, const std::string& script,
                 const std::string& query,
                 const std::vector<std::pair<std::string, std::string>>& mounts,
                 const std::string& result, const std::string& log) {
    const std::string pages = std::string(NDFMIP_SOURCE_DIR) + "/tests/engines";
    std::string command = "timeout 150 " + shellArg(node) + " " +
                          shellArg(pages + "/serve_page.mjs") + " --chromium " +
                          shellArg(chromium) + " --timeout 90 --out " + shellArg(result) +
                          " --mount " + shellArg("/three/=" + nodeModules() + "/three") +
                          " --mount " + shellArg("/engines/=" + pages);
    for (const auto& [prefix, folder] : mounts)
        command += " --mount " + shellArg(prefix + "=" + folder);
    command += " --page " + shellArg("/engines/three_page.html?script=" + script + "&" + query) +
               " > " + shellArg(log) + " 2>&1";
    return std::system(command.c_str());
}

std::vector<unsigned char> fromBase64(const std::string& text) {
    std::vector<unsigned char> out;
    uint32_t bits = 0;
    int count = 0;
    for (char c : text) {
        int v = c >= 'A' && c <= 'Z'   ? c - 'A'
                : c >= 'a' && c <= 'z' ? c - 'a' + 26
                : c >= '0' && c <= '9' ? c - '0' + 52
                : c == '+'             ? 62
                : c == '/'             ? 63
                                       : -1;
        if (v < 0) continue; // '=' padding
        bits = (bits << 6) | uint32_t(v);
        if ((count += 6) >= 8) {
            count -= 8;
            out.push_back(static_cast<unsigned char>((bits >> count) & 0xFF));
        }
    }
    return out;
}

int runGltfCli(const std::string& args, std::string* output) {
    int status = runCliWithin(120, "gltf " + args, output);
    if (status == 137) {
        std::fprintf(stderr, "ndfmip gltf did not finish in 120 s; running it once more\n");
        status = runCliWithin(120, "gltf " + args, output);
    }
    return status;
}

} // namespace ndfmip::test
