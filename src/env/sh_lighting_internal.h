// What the SH lighting's preparation shares with the set of prepared views (src/env).
#pragma once

#include <cstdint>

#include "ndfmip/environment_sh_shading.h"

namespace ndfmip {

// A fresh ShLighting::id: never 0, never repeated in a process.
uint64_t nextShLightingId();

// prepareShLighting without L (`radiance` left empty): the reparameterised lighting alone, which
// is all that depends on the view. Preconditions: those of prepareShLighting.
ShLighting prepareReparameterisedSh(const Environment& env, int order, glm::dvec3 fixedView,
                                    SpecularCosine cosine);

} // namespace ndfmip
