#include "gpu/gl_context.h"

// Both through libepoxy: the Khronos EGL headers and epoxy's GL header clash on khrplatform types.
#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <cstdio>
#include <map>
#include <mutex>
#include <string_view>
#include <utility>
#include <vector>

namespace ndfmip {

namespace {

std::string eglErrorName(EGLint code) {
    static const std::pair<EGLint, const char*> names[] = {
        {EGL_SUCCESS, "EGL_SUCCESS"},
        {EGL_NOT_INITIALIZED, "EGL_NOT_INITIALIZED"},
        {EGL_BAD_ACCESS, "EGL_BAD_ACCESS"},
        {EGL_BAD_ALLOC, "EGL_BAD_ALLOC"},
        {EGL_BAD_ATTRIBUTE, "EGL_BAD_ATTRIBUTE"},
        {EGL_BAD_CONFIG, "EGL_BAD_CONFIG"},
        {EGL_BAD_CONTEXT, "EGL_BAD_CONTEXT"},
        {EGL_BAD_CURRENT_SURFACE, "EGL_BAD_CURRENT_SURFACE"},
        {EGL_BAD_DISPLAY, "EGL_BAD_DISPLAY"},
        {EGL_BAD_MATCH, "EGL_BAD_MATCH"},
        {EGL_BAD_NATIVE_PIXMAP, "EGL_BAD_NATIVE_PIXMAP"},
        {EGL_BAD_NATIVE_WINDOW, "EGL_BAD_NATIVE_WINDOW"},
        {EGL_BAD_PARAMETER, "EGL_BAD_PARAMETER"},
        {EGL_BAD_SURFACE, "EGL_BAD_SURFACE"},
        {EGL_CONTEXT_LOST, "EGL_CONTEXT_LOST"},
    };
    for (const auto& [value, name] : names)
        if (value == code) return name;
    char hex[32];
    std::snprintf(hex, sizeof hex, "EGL error 0x%04x", static_cast<unsigned>(code));
    return hex;
}

bool hasExtension(EGLDisplay display, std::string_view name) {
    const char* list = eglQueryString(display, EGL_EXTENSIONS);
    if (list == nullptr) return false;
    std::string_view all(list);
    for (size_t begin = 0; begin < all.size();) {
        size_t end = all.find(' ', begin);
        if (end == std::string_view::npos) end = all.size();
        if (all.substr(begin, end - begin) == name) return true;
        begin = end + 1;
    }
    return false;
}

// eglTerminate ends every context on a display, and a process has one display per platform, so
// two GlContexts on the same display must not terminate it under each other: count the users.
std::mutex displayMutex;
std::map<EGLDisplay, int> displayUsers;

void acquireDisplay(EGLDisplay display) {
    std::lock_guard lock(displayMutex);
    ++displayUsers[display];
}

void releaseDisplay(EGLDisplay display) {
    std::lock_guard lock(displayMutex);
    auto it = displayUsers.find(display);
    if (it == displayUsers.end() || --it->second > 0) return;
    displayUsers.erase(it);
    eglTerminate(display);
}

// Candidate displays in order of preference, each initialised; the first that initialises wins.
// Surfaceless Mesa needs neither X nor a DRM node (llvmpipe on a bare server); the device
// platform is what NVIDIA's driver offers headless; the default display is the last resort.
struct DisplayAttempt {
    EGLDisplay display = EGL_NO_DISPLAY;
    std::string failures; // "surfaceless: EGL_BAD_...; device: ..." for the error message
};

bool initialize(EGLDisplay display, const char* label, DisplayAttempt& attempt) {
    if (display == EGL_NO_DISPLAY) {
        attempt.failures += std::string(attempt.failures.empty() ? "" : "; ") + label + ": none";
        return false;
    }
    EGLint major = 0, minor = 0;
    if (eglInitialize(display, &major, &minor) != EGL_TRUE) {
        attempt.failures += std::string(attempt.failures.empty() ? "" : "; ") + label + ": " +
                            eglErrorName(eglGetError());
        return false;
    }
    attempt.display = display;
    return true;
}

DisplayAttempt openDisplay() {
    DisplayAttempt attempt;
    // Client extensions (EGL_NO_DISPLAY); epoxy aborts on a call nothing provides, so each
    // extension function is called only once its extension is listed.
    bool platforms = hasExtension(EGL_NO_DISPLAY, "EGL_EXT_platform_base");

    if (platforms && hasExtension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless")) {
        EGLDisplay display =
            eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        if (initialize(display, "surfaceless", attempt)) return attempt;
    }
    if (platforms && hasExtension(EGL_NO_DISPLAY, "EGL_EXT_platform_device") &&
        (hasExtension(EGL_NO_DISPLAY, "EGL_EXT_device_enumeration") ||
         hasExtension(EGL_NO_DISPLAY, "EGL_EXT_device_base"))) {
        EGLint count = 0;
        std::vector<EGLDeviceEXT> devices(16);
        if (eglQueryDevicesEXT(static_cast<EGLint>(devices.size()), devices.data(), &count) ==
            EGL_TRUE) {
            for (EGLint i = 0; i < count; ++i) {
                EGLDisplay display =
                    eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[size_t(i)], nullptr);
                if (initialize(display, "device", attempt)) return attempt;
            }
        }
    }
    initialize(eglGetDisplay(EGL_DEFAULT_DISPLAY), "default", attempt);
    return attempt;
}

// A config is only needed for surfaces; prefer a pbuffer-capable one (every driver has those),
// and fall back to no config where the driver allows it.
bool chooseConfig(EGLDisplay display, EGLConfig& config) {
    const EGLint attributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE,
                                 EGL_PBUFFER_BIT, EGL_NONE};
    EGLint count = 0;
    if (eglChooseConfig(display, attributes, &config, 1, &count) == EGL_TRUE && count > 0)
        return true;
    if (hasExtension(display, "EGL_KHR_no_config_context")) {
        config = EGL_NO_CONFIG_KHR;
        return true;
    }
    return false;
}

} // namespace

GlContext::GlContext(GlContext&& other) noexcept
    : display_(std::exchange(other.display_, nullptr)),
      context_(std::exchange(other.context_, nullptr)),
      description_(std::move(other.description_)) {}

GlContext& GlContext::operator=(GlContext&& other) noexcept {
    if (this != &other) {
        release();
        display_ = std::exchange(other.display_, nullptr);
        context_ = std::exchange(other.context_, nullptr);
        description_ = std::move(other.description_);
    }
    return *this;
}

GlContext::~GlContext() {
    release();
}

void GlContext::release() {
    if (context_ != nullptr) {
        if (eglGetCurrentContext() == context_)
            eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(display_, context_);
        context_ = nullptr;
    }
    if (display_ != nullptr) {
        releaseDisplay(display_);
        display_ = nullptr;
    }
}

Result<GlContext> createHeadlessGl() {
    DisplayAttempt attempt = openDisplay();
    if (attempt.display == EGL_NO_DISPLAY)
        return Error{"GPU: no EGL display (libEGL found no device; install libegl-mesa0 and "
                     "libgl1-mesa-dri) [" +
                     attempt.failures + "]"};
    EGLDisplay display = attempt.display;
    acquireDisplay(display);
    GlContext gl; // owns the display reference from here on: early returns release it
    gl.display_ = display;

    if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE)
        return Error{"GPU: the EGL display has no desktop OpenGL (" + eglErrorName(eglGetError()) +
                     ")"};
    EGLConfig config = nullptr;
    if (!chooseConfig(display, config))
        return Error{"GPU: no EGL config with OpenGL (" + eglErrorName(eglGetError()) + ")"};

    const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                 4,
                                 EGL_CONTEXT_MINOR_VERSION,
                                 5,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                 EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                 EGL_NONE};
    gl.context_ = eglCreateContext(display, config, EGL_NO_CONTEXT, attributes);
    if (gl.context_ == EGL_NO_CONTEXT) {
        gl.context_ = nullptr;
        return Error{"GPU: OpenGL 4.5 core context refused: " + eglErrorName(eglGetError())};
    }
    if (eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, gl.context_) != EGL_TRUE)
        return Error{"GPU: cannot make the context current without a surface (" +
                     eglErrorName(eglGetError()) + "; needs EGL_KHR_surfaceless_context)"};
    int version = glVersion();
    if (version < 45)
        return Error{"GPU: OpenGL 4.5 core context refused: the driver gave version " +
                     std::to_string(version / 10) + "." + std::to_string(version % 10)};

    auto text = [](GLenum name) {
        const GLubyte* s = glGetString(name);
        return s != nullptr ? std::string(reinterpret_cast<const char*>(s)) : std::string("?");
    };
    gl.description_ = text(GL_RENDERER) + ", " + text(GL_VERSION);
    return gl;
}

Status makeCurrent(const GlContext& gl) {
    if (!gl.valid()) return Status::failure("GPU: no OpenGL context");
    if (eglGetCurrentContext() == gl.eglContext()) return Status::success();
    if (eglMakeCurrent(gl.eglDisplay(), EGL_NO_SURFACE, EGL_NO_SURFACE, gl.eglContext()) !=
        EGL_TRUE)
        return Status::failure("GPU: cannot make the OpenGL context current on this thread (" +
                               eglErrorName(eglGetError()) + ")");
    return Status::success();
}

int glVersion() {
    if (eglGetCurrentContext() == EGL_NO_CONTEXT) return 0;
    GLint major = 0, minor = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    return major * 10 + minor;
}

} // namespace ndfmip
