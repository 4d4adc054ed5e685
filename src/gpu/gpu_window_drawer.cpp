// GpuWindowDrawer (gpu_render.h): the renderer's programs drawn into a caller's window, one
// compiled GpuMethod per program key.
#include <map>

#include "gpu/gpu_method.h"
#include "ndfmip/gpu_render.h"

namespace ndfmip {

struct GpuWindowDrawer::Programs {
    std::map<std::string, GpuMethod> byKey;
};

GpuWindowDrawer::GpuWindowDrawer() : programs_(std::make_unique<Programs>()) {}
GpuWindowDrawer::GpuWindowDrawer(GpuWindowDrawer&&) noexcept = default;
GpuWindowDrawer& GpuWindowDrawer::operator=(GpuWindowDrawer&&) noexcept = default;
GpuWindowDrawer::~GpuWindowDrawer() = default;

Status GpuWindowDrawer::draw(const Scene& scene, const RenderTextures& textures,
                             const std::string& shader, const RenderOptions& options,
                             const std::string& programKey, bool showLevel, int x, int y, int width,
                             int height) {
    Result<RenderProgram> program = renderProgram(scene, textures, shader, options);
    if (!program) return Status::failure(program.error().message);
    program->uniforms.push_back({"ndfmipShowLevel", true, {showLevel ? 1.f : 0.f}});
    auto it = programs_->byKey.find(programKey);
    if (it == programs_->byKey.end()) {
        Result<GpuMethod> created = GpuMethod::create(program.value());
        if (!created) return Status::failure(created.error().message);
        it = programs_->byKey.emplace(programKey, std::move(created.value())).first;
    }
    it->second.draw(program->uniforms, x, y, width, height);
    return Status::success();
}

} // namespace ndfmip
