// The methods' prepared lighting under an environment, made once per loaded map and shared: the
// split-sum lighting of one LOD rule (environment_splitsum.h) and the SH lighting of one order and
// view (environment_sh_shading.h) or of a set of views (environment_sh_views.h), kept in
// EnvironmentLighting::cache (environment_lighting.h).
// Thread-safe: concurrent callers asking for the same data wait for one preparation; different
// data is prepared concurrently.
#pragma once

#include <memory>

#include <glm/glm.hpp>

#include "ndfmip/environment_lighting.h"
#include "ndfmip/environment_sh_shading.h"
#include "ndfmip/environment_sh_views.h"
#include "ndfmip/environment_splitsum.h"

namespace ndfmip {

// prepareSplitSum(lighting.environment, options) with options.rules = {rule},
// options.blinnPhongLobe = blinnPhongLobe and options.dominantDirection = dominantDirection, the
// other options at their defaults; the same object for every call with the same three.
std::shared_ptr<const SplitSumLighting> cachedSplitSum(const EnvironmentLighting& lighting,
                                                       EnvironmentLod rule,
                                                       bool blinnPhongLobe = false,
                                                       bool dominantDirection = true);

// prepareShLighting(lighting.environment, order, view, cosine); the same object for every call with
// the same order, cosine and view (compared exactly: an eval's renders share their camera). Only
// the kMaxCachedShViews most recent views are kept, so a moving camera does not grow the cache.
constexpr int kMaxCachedShViews = 16;
std::shared_ptr<const ShLighting>
cachedShLighting(const EnvironmentLighting& lighting, int order, glm::dvec3 view,
                 SpecularCosine cosine = SpecularCosine::MeanNormal);

// prepareShViewSet(lighting.environment, order, frequency, cosine); the same object for every call
// with the same order, frequency and cosine (the set does not depend on the camera).
std::shared_ptr<const ShViewSet>
cachedShViewSet(const EnvironmentLighting& lighting, int order, int frequency,
                SpecularCosine cosine = SpecularCosine::MeanNormal);

} // namespace ndfmip
