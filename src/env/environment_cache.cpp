// The prepared lighting cache of environment_cache.h. Each key has one entry whose data is made
// under its own once_flag, outside the cache's mutex, so a preparation (itself parallel) never
// blocks lookups of other keys.
#include "ndfmip/environment_cache.h"

#include <algorithm>

namespace ndfmip {

struct EnvironmentCache::Entry {
    enum class Kind { SplitSum, Sh, ShViews } kind = Kind::SplitSum;
    EnvironmentLod rule = EnvironmentLod::Filament; // SplitSum
    bool blinnPhongLobe = false;                    // SplitSum
    int order = 0;                                  // Sh, ShViews
    int frequency = 0;                              // ShViews
    SpecularCosine cosine = SpecularCosine::MeanNormal;
    glm::dvec3 view{0.};
    std::once_flag once;
    std::shared_ptr<const SplitSumLighting> splitSum;
    std::shared_ptr<const ShLighting> sh;
    std::shared_ptr<const ShViewSet> shViews;
};

namespace {

using Entry = EnvironmentCache::Entry;

// The entry matching `same`, or a new one made by `make` (at the end: newest last). For SH, the
// oldest SH entries beyond kMaxCachedShViews are dropped; callers holding them keep their data.
template <class Same, class Make>
std::shared_ptr<Entry> entryFor(EnvironmentCache& cache, Same same, Make make) {
    std::lock_guard<std::mutex> lock(cache.mutex);
    for (const std::shared_ptr<Entry>& e : cache.entries)
        if (same(*e)) return e;
    std::shared_ptr<Entry> e = make();
    cache.entries.push_back(e);
    if (e->kind == Entry::Kind::Sh) {
        auto isSh = [](const std::shared_ptr<Entry>& x) { return x->kind == Entry::Kind::Sh; };
        while (std::count_if(cache.entries.begin(), cache.entries.end(), isSh) > kMaxCachedShViews)
            cache.entries.erase(std::find_if(cache.entries.begin(), cache.entries.end(), isSh));
    }
    return e;
}

} // namespace

std::shared_ptr<const SplitSumLighting> cachedSplitSum(const EnvironmentLighting& lighting,
                                                       EnvironmentLod rule, bool blinnPhongLobe) {
    std::shared_ptr<Entry> e = entryFor(
        lighting.cache,
        [&](const Entry& x) {
            return x.kind == Entry::Kind::SplitSum && x.rule == rule && x.blinnPhongLobe == blinnPhongLobe;
        },
        [&] {
            auto made = std::make_shared<Entry>();
            made->kind = Entry::Kind::SplitSum;
            made->rule = rule;
            made->blinnPhongLobe = blinnPhongLobe;
            return made;
        });
    std::call_once(e->once, [&] {
        SplitSumOptions options;
        options.rules = {rule};
        options.blinnPhongLobe = blinnPhongLobe;
        e->splitSum = std::make_shared<const SplitSumLighting>(
            prepareSplitSum(lighting.environment, options));
    });
    return e->splitSum;
}

std::shared_ptr<const ShLighting> cachedShLighting(const EnvironmentLighting& lighting, int order,
                                                   glm::dvec3 view, SpecularCosine cosine) {
    std::shared_ptr<Entry> e = entryFor(
        lighting.cache,
        [&](const Entry& x) {
            return x.kind == Entry::Kind::Sh && x.order == order && x.cosine == cosine &&
                   x.view == view;
        },
        [&] {
            auto made = std::make_shared<Entry>();
            made->kind = Entry::Kind::Sh;
            made->order = order;
            made->cosine = cosine;
            made->view = view;
            return made;
        });
    std::call_once(e->once, [&] {
        e->sh = std::make_shared<const ShLighting>(
            prepareShLighting(lighting.environment, order, view, cosine));
    });
    return e->sh;
}

std::shared_ptr<const ShViewSet> cachedShViewSet(const EnvironmentLighting& lighting, int order, int frequency,
                                                 SpecularCosine cosine) {
    std::shared_ptr<Entry> e = entryFor(
        lighting.cache,
        [&](const Entry& x) {
            return x.kind == Entry::Kind::ShViews && x.order == order && x.frequency == frequency &&
                   x.cosine == cosine;
        },
        [&] {
            auto made = std::make_shared<Entry>();
            made->kind = Entry::Kind::ShViews;
            made->order = order;
            made->frequency = frequency;
            made->cosine = cosine;
            return made;
        });
    std::call_once(e->once, [&] {
        e->shViews = std::make_shared<const ShViewSet>(
            prepareShViewSet(lighting.environment, order, frequency, cosine));
    });
    return e->shViews;
}

} // namespace ndfmip
