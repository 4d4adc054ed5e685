// Many maps baked at once (`ndfmip bake` with folders, globs, -o patterns, --jobs and shards;
// Python's bake_many): the inputs expanded, each map given its output folder by a pattern, the
// maps split into shards for a farm, and baked by workers that share the cores. One map's
// failure never stops the others.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "ndfmip/bake_file.h"
#include "ndfmip/result.h"

namespace ndfmip {

// Files as given, the image files directly inside folders (png, jpg, jpeg, tga, bmp, exr, any
// case; sorted) and globs expanded by glob(3) for callers whose shell did not (farm job specs,
// Python). `expanded` says whether a folder or a glob was among them: then the maps are many,
// whatever their number.
struct BakeInputs {
    std::vector<std::string> maps;
    bool expanded = false;
};
Result<BakeInputs> expandBakeInputs(const std::vector<std::string>& inputs);

// The output pattern with {stem} (the file name without its extension), {name} (with it) and
// {parent} (its folder's name) of `input`; an error where a field would name a folder ("." or
// "..").
Result<std::string> bakeOutputFor(const std::string& pattern, const std::string& input);

// The shard (0 .. shards - 1) a map belongs to: FNV-1a of its path as given, so the split is the
// same on every machine and a map's shard does not move when others are added.
int bakeShardOf(const std::string& input, int shards);

// One map of a batch and, once baked, what happened.
struct BakeBatchMap {
    std::string input, output;
    std::string status; // "baked", "skipped" (up to date), "failed"; empty until it ran
    std::string error;  // one line, for "failed"
    double seconds = 0.0;
};

// Every map's output from the pattern (which must hold {stem} or {name} when the maps are many,
// and must not give two maps one folder), and the maps of shard `shard` of `shards`, in order.
Result<std::vector<BakeBatchMap>>
planBakeBatch(const BakeInputs& inputs, const std::string& outputPattern, int shard, int shards);

// Bakes the maps with bakeFile and `options` (its callbacks unused), `jobs` at a time, each
// with its share of the cores (OMP_NUM_THREADS or the process's affinity mask), filling in
// their status. `finished` is called, one call at a time, as each map ends, with the maps ended
// and failed so far. Returns how many maps were baked at a time (jobs, at most the maps).
int runBakeBatch(
    std::vector<BakeBatchMap>& maps, const BakeFileOptions& options, int jobs,
    const std::function<void(const BakeBatchMap& map, size_t ended, size_t failed)>& finished = {});

} // namespace ndfmip
