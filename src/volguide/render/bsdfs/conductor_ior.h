#pragma once
// Complex IOR parameters of the conductor plugins: `material` preset (default "none": a perfect
// mirror) or explicit `eta` / `k` (textures), as Mitsuba 3.
#include <memory>

#include "volguide/core/properties.h"
#include "volguide/render/texture.h"

namespace volguide {

struct ConductorIor {
    std::shared_ptr<Texture> eta, k;
    static ConductorIor parse(const Properties& props);
};

}  // namespace volguide
