// The prepared lighting cache of environment_cache.h. Each key has one entry whose data is made
// under its own once_flag, outside the cache's mutex, so a preparation (itself parallel) never
// blocks lookups of other keys.
#include "ndfmip/environment_cache.h"

#include <algorithm>

namespace ndfmip {

struct EnvironmentCache::Entry {
    // What the data was prepared for; fields a kind does not use keep their defaults.
    struct Key {
        enum class Kind { SplitSum, Sh, ShViews } kind = Kind::SplitSum;
        EnvironmentLod rule = EnvironmentLod::Filament;     // SplitSum
        bool blinnPhongLobe = false;                        // SplitSum
        bool dominantDirection = true;                      // SplitSum
        int order = 0;                                      // Sh, ShViews
        int frequency = 0;                                  // ShViews
        SpecularCosine cosine = SpecularCosine::MeanNormal; // Sh, ShViews
        glm::dvec3 view{0.};                                // Sh
        bool operator==(const Key&) const = default;
    } key;
    std::once_flag once;
    std::shared_ptr<const SplitSumLighting> splitSum;
    std::shared_ptr<const ShLighting> sh;
    std::shared_ptr<const ShViewSet> shViews;
};

namespace {

using Entry = EnvironmentCache::Entry;
using Kind = Entry::Key::Kind;

// The entry of `key`, or a new one (at the end: newest last). For SH, the oldest SH entries
// beyond kMaxCachedShViews are dropped; callers holding them keep their data.
std::shared_ptr<Entry> entryFor(EnvironmentCache& cache, const Entry::Key& key) {
    std::lock_guard<std::mutex> lock(cache.mutex);
    for (const std::shared_ptr<Entry>& e : cache.entries)
        if (e->key == key) return e;
    auto e = std::make_shared<Entry>();
    e->key = key;
    cache.entries.push_back(e);
    if (key.kind == Kind::Sh) {
        auto isSh = [](const std::shared_ptr<Entry>& x) { return x->key.kind == Kind::Sh; };
        while (std::count_if(cache.entries.begin(), cache.entries.end(), isSh) > kMaxCachedShViews)
            cache.entries.erase(std::find_if(cache.entries.begin(), cache.entries.end(), isSh));
    }
    return e;
}

} // namespace

std::shared_ptr<const SplitSumLighting> cachedSplitSum(const EnvironmentLighting& lighting,
                                                       EnvironmentLod rule, bool blinnPhongLobe,
                                                       bool dominantDirection) {
    std::shared_ptr<Entry> e = entryFor(lighting.cache, {.kind = Kind::SplitSum,
                                                         .rule = rule,
                                                         .blinnPhongLobe = blinnPhongLobe,
                                                         .dominantDirection = dominantDirection});
    std::call_once(e->once, [&] {
        SplitSumOptions options;
        options.rules = {rule};
        options.blinnPhongLobe = blinnPhongLobe;
        options.dominantDirection = dominantDirection;
        e->splitSum = std::make_shared<const SplitSumLighting>(
            prepareSplitSum(lighting.environment, options));
    });
    return e->splitSum;
}

std::shared_ptr<const ShLighting> cachedShLighting(const EnvironmentLighting& lighting, int order,
                                                   glm::dvec3 view, SpecularCosine cosine) {
    std::shared_ptr<Entry> e = entryFor(
        lighting.cache, {.kind = Kind::Sh, .order = order, .cosine = cosine, .view = view});
    std::call_once(e->once, [&] {
        e->sh = std::make_shared<const ShLighting>(
            prepareShLighting(lighting.environment, order, view, cosine));
    });
    return e->sh;
}

std::shared_ptr<const ShViewSet> cachedShViewSet(const EnvironmentLighting& lighting, int order,
                                                 int frequency, SpecularCosine cosine) {
    std::shared_ptr<Entry> e =
        entryFor(lighting.cache,
                 {.kind = Kind::ShViews, .order = order, .frequency = frequency, .cosine = cosine});
    std::call_once(e->once, [&] {
        e->shViews = std::make_shared<const ShViewSet>(
            prepareShViewSet(lighting.environment, order, frequency, cosine));
    });
    return e->shViews;
}

} // namespace ndfmip
