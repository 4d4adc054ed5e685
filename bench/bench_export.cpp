// Engine exports: a Toksvig bake written as BC5 normal + BC4 roughness KTX2 files (every level,
// no EXR planes), from the normals in memory (a real map, tiled) to the files on disk. The
// command-line job also decodes the PNG; scripts/bench-export times that beside Filament's
// roughness-prefilter.
#include <filesystem>
#include <string>

#include <unistd.h>

#include <benchmark/benchmark.h>

#include "bench_support.h"
#include "ndfmip/bake.h"
#include "ndfmip/pyramid.h"
#include "ndfmip/texture_container.h"

namespace {

void exportKtx2(benchmark::State& state, ndfmip::TextureFormat roughness, bool normal) {
    const ndfmip::SharedImage& map = ndfmip::bench::realMap(int(state.range(0)));
    const std::string dir = (std::filesystem::temp_directory_path() /
                             ("ndfmip_bench_export_" + std::to_string(getpid())))
                                .string();
    ndfmip::BakeWriteOptions write;
    write.exr = false;
    write.ktx2 = true;
    write.exportNormal = normal;
    write.exportPlanes = false;
    write.roughnessFormat = roughness;
    for (auto _ : state) {
        const ndfmip::Pyramid pyramid = ndfmip::buildPyramid(map);
        const ndfmip::Bake bake = ndfmip::bakeMethod(ndfmip::Method::Toksvig, pyramid, {});
        const ndfmip::Status status =
            ndfmip::writeBake(dir, bake, {"bench", "", map->width, map->height, {}, "", ""}, write);
        if (!status) state.SkipWithError(status.error.c_str());
    }
    std::filesystem::remove_all(dir);
}

void BM_ExportKtx2Bc5Bc4(benchmark::State& state) {
    exportKtx2(state, ndfmip::TextureFormat::Bc4Unorm, true);
}
void BM_ExportKtx2RoughnessBc4(benchmark::State& state) {
    exportKtx2(state, ndfmip::TextureFormat::Bc4Unorm, false);
}
void BM_ExportKtx2RoughnessR16F(benchmark::State& state) {
    exportKtx2(state, ndfmip::TextureFormat::R16F, false);
}

} // namespace

BENCHMARK(BM_ExportKtx2Bc5Bc4)->Arg(1024)->Arg(4096)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ExportKtx2RoughnessBc4)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ExportKtx2RoughnessR16F)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime();
