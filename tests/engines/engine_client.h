// What the real-client tests of tests/engines share: the programs and npm packages they need,
// a test page run in headless chromium through serve_page.mjs, the page's base64 bytes.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace ndfmip::test {

// The program in /usr/bin, /usr/local/bin or /bin, or "".
std::string findProgram(const char* name);

// Where npm's packages are: NDFMIP_NODE_MODULES, or the checkout's .npm/node_modules
// (scripts/setup).
std::string nodeModules();

// Why a three.js page cannot run here, or "" when it can: chromium, node, or one of `threeFiles`
// (paths inside npm's three) missing. Sets `chromium` and `node` to the programs.
std::string missingThreePage(const std::vector<std::string>& threeFiles, std::string* chromium,
                             std::string* node);

// missingThreePage for a page that loads a GLB of ndfmip gltf: three's GLTFLoader, KTX2Loader and
// Basis transcoder, and the Basis encoder that writes the GLB's KTX2.
std::string missingGltfPage(std::string* chromium, std::string* node);

// Runs the test script `script` (a module of tests/engines, e.g. "three_gltf_levels.mjs") in
// headless chromium through three_page.html with `query` ("glb=/asset/x.glb&..."), npm's three
// served at /three/, tests/engines at /engines/ and each (url prefix, folder) of `mounts`; the
// page's result goes to `result`, everything printed to `log`. Returns the exit status: 0 when
// the page posted its result (serve_page.mjs says the others).
int runThreePage(const std::string& node, const std::string& chromium, const std::string& script,
                 const std::string& query,
                 const std::vector<std::pair<std::string, std::string>>& mounts,
                 const std::string& result, const std::string& log);

std::vector<unsigned char> fromBase64(const std::string& text);

// `ndfmip gltf ARGS` for the engine tests: killed after 120 s (status 137) and then run once more.
// Under heavy load a UASTC encode was seen to hang once (not reproduced since; an open bug), which
// must not stall the suite for ctest's whole time limit. The last run's status.
int runGltfCli(const std::string& args, std::string* output);

} // namespace ndfmip::test
