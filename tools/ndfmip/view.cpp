// ndfmip view SCENE.json: a window that draws the scene with the GPU renderer, interactively:
// switch method and lobe count, orbit and zoom, move the light, split screen of two methods,
// the mip level as false colour, the frame time in the title.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>

#include "cli.h"

#if defined(NDFMIP_HAS_GLFW)
#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "ndfmip/gpu_render.h"
#include "ndfmip/io.h"
#include "ndfmip/vmf.h"
#endif

namespace ndfmip::cli {
namespace {

struct ViewArgs {
    std::string scene, bake;
    MethodParameterArgs methodParameters; // --order, --lobes: the bakes made on start
    std::string method;                   // at start (default: the scene's)
    bool split = false, levels = false;
    int frames = 0; // quit after this many frames (0: when the window closes)
    FilteringArgs filtering;
};

#if defined(NDFMIP_HAS_GLFW)

const char* kHelp =
    "ndfmip view: Tab / Shift+Tab method, +/- vMF lobes, S split screen (left: the method, right: "
    "toksvig), F mip level as false colour, left drag orbit, right drag light, wheel zoom, R "
    "reset, "
    "Esc quit";

// What the window shows and how the camera and light sit, in spherical coordinates about the
// scene's target.
struct ViewState {
    std::vector<std::string> methods;
    size_t method = 0;
    int lobes = 4;
    bool split = false, levels = false;
    float azimuth = 0.f, elevation = 0.f, distance = 1.f;
    float lightAzimuth = 0.f, lightElevation = 0.f;
    double mouseX = 0.0, mouseY = 0.0;
    bool orbiting = false, lighting = false;
};

glm::vec3 fromSpherical(float azimuth, float elevation) {
    return {std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
            std::sin(elevation)};
}

struct Viewer {
    Scene scene;
    RenderTextures base; // normals (and albedo)
    Pyramid pyramid;
    ViewArgs args;
    RenderOptions options;
    ViewState state;
    std::map<std::string, Bake> bakes; // by bake key ("vmf:4", "sh", ...)
    GpuWindowDrawer drawer;            // a program per shader and bake key

    std::string bakeKey(const std::string& shader) const {
        const Method bake = shaderBake(shader).value();
        const std::string name = methodName(bake);
        if (bakeFitsMaterialRoughness(bake))
            return name + " a=" + std::to_string(scene.material.roughness);
        return bake == Method::Vmf ? name + ":" + std::to_string(state.lobes) : name;
    }

    const Bake& bakeFor(const std::string& shader) {
        const std::string key = bakeKey(shader);
        auto it = bakes.find(key);
        if (it != bakes.end()) return it->second;
        const Method method = shaderBake(shader).value();
        BakeOptions o;
        o.parameters = args.methodParameters.given();
        o.parameters["lobes"] = state.lobes;
        o.parameters = parametersOf(method, o.parameters);
        if (bakeFitsMaterialRoughness(method)) o.baseRoughness = scene.material.roughness;
        std::fprintf(stderr, "view: baking %s ...\n", key.c_str());
        return bakes[key] = bakeMethod(method, pyramid, o);
    }

    // Draws `shader` over the whole window (the scissor keeps it to its half when split).
    void draw(const std::string& shader, int width, int height) {
        Scene s = scene;
        s.camera.width = width;
        s.camera.height = height;
        s.camera.eye =
            scene.camera.target + state.distance * fromSpherical(state.azimuth, state.elevation);
        if (!s.lights.empty() && s.lights.front().type == LightType::Directional)
            s.lights.front().direction = fromSpherical(state.lightAzimuth, state.lightElevation);
        RenderTextures t = base;
        t.bake = bakeFor(shader);
        if (Status drawn = drawer.draw(s, t, shader, options, shader + "/" + bakeKey(shader),
                                       state.levels, 0, 0, width, height);
            !drawn)
            throw Failure(args.scene + ": " + drawn.error);
    }
};

Viewer* viewerOf(GLFWwindow* window) {
    return static_cast<Viewer*>(glfwGetWindowUserPointer(window));
}

void onKey(GLFWwindow* window, int key, int, int action, int mods) {
    if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
    ViewState& s = viewerOf(window)->state;
    const size_t n = s.methods.size();
    if (key == GLFW_KEY_ESCAPE) glfwSetWindowShouldClose(window, GLFW_TRUE);
    if (key == GLFW_KEY_TAB)
        s.method = (mods & GLFW_MOD_SHIFT) ? (s.method + n - 1) % n : (s.method + 1) % n;
    if (key == GLFW_KEY_EQUAL || key == GLFW_KEY_KP_ADD)
        s.lobes = std::min(s.lobes + 1, kMaxVmfBakeLobes);
    if (key == GLFW_KEY_MINUS || key == GLFW_KEY_KP_SUBTRACT) s.lobes = std::max(s.lobes - 1, 1);
    if (key == GLFW_KEY_S) s.split = !s.split;
    if (key == GLFW_KEY_F) s.levels = !s.levels;
    if (key == GLFW_KEY_R) {
        Viewer* v = viewerOf(window);
        const std::vector<std::string> methods = s.methods;
        s = ViewState{};
        s.methods = methods;
        const glm::vec3 offset = v->scene.camera.eye - v->scene.camera.target;
        s.distance = glm::length(offset);
        s.azimuth = std::atan2(offset.y, offset.x);
        s.elevation = std::asin(glm::clamp(offset.z / s.distance, -1.f, 1.f));
        s.lobes = int(v->args.methodParameters.value(Method::Vmf, "lobes"));
        if (!v->scene.lights.empty()) {
            const glm::vec3 d = glm::normalize(v->scene.lights.front().direction);
            s.lightAzimuth = std::atan2(d.y, d.x);
            s.lightElevation = std::asin(glm::clamp(d.z, -1.f, 1.f));
        }
    }
}

void onButton(GLFWwindow* window, int button, int action, int) {
    ViewState& s = viewerOf(window)->state;
    glfwGetCursorPos(window, &s.mouseX, &s.mouseY);
    if (button == GLFW_MOUSE_BUTTON_LEFT) s.orbiting = action == GLFW_PRESS;
    if (button == GLFW_MOUSE_BUTTON_RIGHT) s.lighting = action == GLFW_PRESS;
}

void onCursor(GLFWwindow* window, double x, double y) {
    ViewState& s = viewerOf(window)->state;
    const float dx = float(x - s.mouseX) * 0.005f, dy = float(y - s.mouseY) * 0.005f;
    s.mouseX = x, s.mouseY = y;
    if (s.orbiting) {
        s.azimuth -= dx;
        s.elevation = glm::clamp(s.elevation + dy, -1.5f, 1.5f);
    }
    if (s.lighting) {
        s.lightAzimuth -= dx;
        s.lightElevation = glm::clamp(s.lightElevation - dy, 0.02f, 1.57f);
    }
}

void onScroll(GLFWwindow* window, double, double y) {
    ViewState& s = viewerOf(window)->state;
    s.distance *= std::pow(0.9f, float(y));
}

void runView(const ViewArgs& a) {
    Result<Scene> scene = loadScene(a.scene);
    if (!scene) throw Failure(scene.error().message);
    if (!glfwInit()) {
        const char* description = nullptr;
        glfwGetError(&description);
        throw Failure(std::string("view: no display to open a window on (") +
                      (description ? description : "GLFW could not start") +
                      "); render --gpu draws images without one");
    }
    struct Terminate {
        ~Terminate() { glfwTerminate(); }
    } terminate;
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    GLFWwindow* window = glfwCreateWindow(scene->camera.width, scene->camera.height, "ndfmip view",
                                          nullptr, nullptr);
    if (!window) throw Failure("view: OpenGL 4.5 core window refused by the display's driver");
    glfwMakeContextCurrent(window);
    glfwSwapInterval(0);

    Viewer v;
    v.scene = scene.value();
    v.args = a;
    a.filtering.apply(v.options);
    v.base.normals = std::make_shared<const Image>(
        loadNormalsOrFail(scene->normalMap.path, scene->normalMap.decode, true));
    v.pyramid = buildPyramid(v.base.normals);
    if (!a.bake.empty()) {
        Result<Bake> bake = loadBake(a.bake);
        if (!bake) throw Failure(bake.error().message);
        v.bakes[methodName(bake->method) + (bake->method == Method::Vmf
                                                ? ":" + std::to_string(bakeVmfLobes(bake.value()))
                                                : "")] = bake.value();
    }
    for (const std::string& shader : shaderNames()) {
        if (shader == kRoughnessMips) continue; // needs an engine's roughness mips
        if (shader == kToksvigLut && scene->material.brdf != Brdf::BlinnPhong) continue;
        v.state.methods.push_back(shader);
    }
    glfwSetWindowUserPointer(window, &v);
    onKey(window, GLFW_KEY_R, 0, GLFW_PRESS, 0); // the scene's own camera and light
    const std::string first = a.method.empty() ? scene->method : a.method;
    bool known = false;
    for (size_t i = 0; i < v.state.methods.size(); ++i)
        if (v.state.methods[i] == first) v.state.method = i, known = true;
    if (!known && !a.method.empty())
        throw Failure("view: unknown method " + quote(a.method) +
                      " (the window shows the GPU renderer's methods)");
    v.state.split = a.split;
    v.state.levels = a.levels;
    glfwSetKeyCallback(window, onKey);
    glfwSetMouseButtonCallback(window, onButton);
    glfwSetCursorPosCallback(window, onCursor);
    glfwSetScrollCallback(window, onScroll);
    std::printf("%s\n", kHelp);

    std::vector<double> frameMs;
    while (!glfwWindowShouldClose(window) && (a.frames == 0 || int(frameMs.size()) < a.frames)) {
        int width = 0, height = 0;
        glfwGetFramebufferSize(window, &width, &height);
        if (width < 1 || height < 1) {
            glfwWaitEvents();
            continue;
        }
        const double start = glfwGetTime();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        const std::string method = v.state.methods[v.state.method];
        if (v.state.split) {
            glEnable(GL_SCISSOR_TEST);
            glScissor(0, 0, width / 2, height);
            v.draw(method, width, height);
            glScissor(width / 2, 0, width - width / 2, height);
            v.draw("toksvig", width, height);
            glDisable(GL_SCISSOR_TEST);
        } else {
            v.draw(method, width, height);
        }
        glFinish();
        const double ms = (glfwGetTime() - start) * 1e3;
        frameMs.push_back(ms);
        std::string title = "ndfmip view - " + method;
        if (shaderBake(method) == Method::Vmf) title += ":" + std::to_string(v.state.lobes);
        if (v.state.split) title += " | toksvig";
        if (v.state.levels) title += " (mip levels)";
        char timing[64];
        std::snprintf(timing, sizeof timing, " - %.1f ms", ms);
        glfwSetWindowTitle(window, (title + timing).c_str());
        glfwSwapBuffers(window);
        glfwPollEvents();
    }
    if (a.frames > 0 && !frameMs.empty()) {
        std::sort(frameMs.begin(), frameMs.end());
        std::printf("view: %d frames of %s on %s, median %.1f ms\n", int(frameMs.size()),
                    v.state.methods[v.state.method].c_str(),
                    reinterpret_cast<const char*>(glGetString(GL_RENDERER)),
                    frameMs[frameMs.size() / 2]);
    }
}

#else

void runView(const ViewArgs&) {
    throw Failure("view: this ndfmip was built without a window system (GLFW: libglfw3-dev, and "
                  "the OpenGL path)");
}

#endif

} // namespace

void addViewCommand(CLI::App& app) {
    auto a = std::make_shared<ViewArgs>();
    CLI::App* c =
        app.add_subcommand("view", "draw a scene in a window with the GPU renderer, interactively");
    c->add_option("scene", a->scene, "scene file (JSON)")->required();
    c->add_option("--bake", a->bake, "use this bake directory for its method");
    addMethodParameterOptions(c, kParameterView,
                              a->methodParameters); // vmf's lobes at start; +/- change them
    c->add_option("--method", a->method, "method at start (default: the scene's)");
    c->add_flag("--split", a->split, "start in split screen (right: toksvig)");
    c->add_flag("--mip-levels", a->levels, "start with the mip level as false colour");
    c->add_option("--frames", a->frames, "quit after N frames and print the median frame time")
        ->check(CLI::Range(0, 100000));
    addFilteringOptions(c, a->filtering);
    c->callback([a] { runView(*a); });
}

} // namespace ndfmip::cli
