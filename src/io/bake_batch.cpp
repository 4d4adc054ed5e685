// Many maps baked at once (bake_batch.h).
#include "ndfmip/bake_batch.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <map>
#include <mutex>
#include <new>
#include <thread>

#include <glob.h>
#include <omp.h>

#include "ndfmip/clock.h"
#include "ndfmip/limits.h"

namespace ndfmip {
namespace {

bool isImageFile(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    for (const char* known : {".png", ".jpg", ".jpeg", ".tga", ".bmp", ".exr"})
        if (ext == known) return true;
    return false;
}

} // namespace

Result<BakeInputs> expandBakeInputs(const std::vector<std::string>& inputs) {
    BakeInputs out;
    for (const std::string& input : inputs) {
        std::error_code ec;
        if (std::filesystem::is_directory(input, ec)) {
            out.expanded = true;
            std::vector<std::string> inside;
            for (const auto& entry : std::filesystem::directory_iterator(input, ec))
                if (entry.is_regular_file(ec) && isImageFile(entry.path()))
                    inside.push_back(entry.path().string());
            if (ec) return Error{input + ": cannot list the folder (" + ec.message() + ")"};
            if (inside.empty())
                return Error{input + ": the folder holds no image files (png, jpg, tga, bmp, exr)"};
            std::sort(inside.begin(), inside.end());
            out.maps.insert(out.maps.end(), inside.begin(), inside.end());
        } else if (input.find_first_of("*?[") != std::string::npos &&
                   !std::filesystem::exists(input, ec)) {
            out.expanded = true;
            glob_t found{};
            const int rc = ::glob(input.c_str(), 0, nullptr, &found);
            for (size_t i = 0; rc == 0 && i < found.gl_pathc; ++i)
                out.maps.emplace_back(found.gl_pathv[i]);
            ::globfree(&found);
            if (rc != 0) return Error{quote(input) + ": no file matches"};
        } else {
            out.maps.push_back(input);
        }
    }
    return out;
}

Result<std::string> bakeOutputFor(const std::string& pattern, const std::string& input) {
    const std::filesystem::path path(input);
    const std::pair<std::string, std::string> fields[] = {
        {"{stem}", path.stem().string()},
        {"{name}", path.filename().string()},
        {"{parent}", path.parent_path().filename().string()}};
    std::string out = pattern;
    for (const auto& [field, value] : fields) {
        // "..png" has the stem "." and "...png" the stem "..": out/{stem} would be out/ itself or
        // the folder above it.
        if ((value == "." || value == "..") && out.find(field) != std::string::npos)
            return Error{quote(input) + ": its " + field + " is " + quote(value) +
                         ", which names a folder, not a bake; "
                         "rename the map or use another field in -o"};
        for (size_t at = out.find(field); at != std::string::npos;
             at = out.find(field, at + value.size()))
            out.replace(at, field.size(), value);
    }
    return out;
}

int bakeShardOf(const std::string& input, int shards) {
    uint64_t h = 1469598103934665603ull;
    for (unsigned char c : input) h = (h ^ c) * 1099511628211ull;
    return int(h % uint64_t(std::max(shards, 1)));
}

Result<std::vector<BakeBatchMap>>
planBakeBatch(const BakeInputs& inputs, const std::string& outputPattern, int shard, int shards) {
    if (shards < 1 || shard < 0 || shard >= shards)
        return Error{"shard " + std::to_string(shard) + " of " + std::to_string(shards) +
                     ": expected 0 <= shard < shards"};
    if ((inputs.maps.size() > 1 || inputs.expanded) &&
        outputPattern.find("{stem}") == std::string::npos &&
        outputPattern.find("{name}") == std::string::npos)
        return Error{"-o " + quote(outputPattern) + ": with " + std::to_string(inputs.maps.size()) +
                     " map(s) from " + (inputs.expanded ? "a folder or glob" : "several inputs") +
                     ", -o needs {stem} or {name}, e.g. -o 'out/{stem}.bake'"};
    std::vector<BakeBatchMap> maps;
    std::map<std::string, std::string> outputs; // output -> the map writing it
    for (const std::string& input : inputs.maps) {
        Result<std::string> output = bakeOutputFor(outputPattern, input);
        if (!output) return output.error();
        const std::string normal =
            std::filesystem::path(output.value()).lexically_normal().string();
        if (auto [it, fresh] = outputs.emplace(normal, input); !fresh)
            return Error{quote(it->second) + " and " + quote(input) + " would both be baked to " +
                         quote(output.value()) + "; use {parent} or {name} in -o"};
        if (bakeShardOf(input, shards) == shard)
            maps.push_back({input, output.value(), "", "", 0.0});
    }
    return maps;
}

int runBakeBatch(
    std::vector<BakeBatchMap>& maps, const BakeFileOptions& options, int jobs,
    const std::function<void(const BakeBatchMap& map, size_t ended, size_t failed)>& finished) {
    BakeFileOptions quiet = options;
    quiet.progress = nullptr;
    quiet.decoded = nullptr;
    std::mutex lock;
    std::atomic<size_t> next{0};
    size_t ended = 0, failed = 0;
    const int workers = std::max(1, std::min(jobs, int(maps.size())));
    // The cores this process may use: OMP_NUM_THREADS, else the CPUs of its affinity mask (a
    // Slurm or container cpuset), not every core of the machine.
    const int cores = std::max(1, omp_get_max_threads());
    auto work = [&] {
        omp_set_num_threads(std::max(1, cores / workers)); // the maps share the cores
        for (size_t i; (i = next++) < maps.size();) {
            BakeBatchMap& m = maps[i];
            const long long start = nowNanoseconds();
            try {
                Result<BakeFileReport> baked = bakeFile(m.input, m.output, quiet);
                if (baked) {
                    m.status = baked->skipped ? "skipped" : "baked";
                } else {
                    m.status = "failed";
                    m.error = baked.error().message;
                }
            } catch (const std::bad_alloc&) {
                m.status = "failed";
                m.error = outOfMemoryMessage(m.input);
            } catch (const std::exception& e) { // one map's failure never stops the others
                m.status = "failed";
                m.error = e.what();
            }
            m.seconds = millisecondsSince(start) / 1000.0;
            std::lock_guard<std::mutex> guard(lock);
            ++ended;
            failed += m.status == "failed";
            if (finished) finished(m, ended, failed);
        }
    };
    std::vector<std::thread> threads;
    for (int t = 1; t < workers; ++t) threads.emplace_back(work);
    work();
    for (std::thread& t : threads) t.join();
    return workers;
}

} // namespace ndfmip
