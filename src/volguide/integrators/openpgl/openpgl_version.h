#pragma once
// What the linked Open PGL offers beyond 0.7.1 (cmake/openpgl.cmake's VOLGUIDE_OPENPGL_SOURCE picks
// 0.7.1 or the 0.8 devel snapshot). The version differences of the C++ API stay behind these few
// checks in integrators/openpgl/ only.
#include <cmath>
#include <limits>

#include <openpgl/cpp/OpenPGL.h>

#include "volguide/integrators/openpgl/openpgl_field.h"

namespace volguide {

// Open PGL's volume scattering probability (VSPG, Xu et al. 2024): 0.8 devel built with
// OPENPGL_EF_VSP_GUIDING, which its generated openpgl/defines.h announces as OPENPGL_VSP_GUIDING.
#ifdef OPENPGL_VSP_GUIDING
inline constexpr bool kOpenPglHasVsp = true;
#else
inline constexpr bool kOpenPglHasVsp = false;
#endif

// The linked version as CMake found it ("0.7.1", "0.8.0").
inline constexpr const char* kOpenPglVersion = VOLGUIDE_OPENPGL_VERSION;

// The guiding distribution's volume scattering probability in the world direction w (towards the
// light: the direction the path goes on in): the share of the radiance arriving from w that was
// scattered in a medium before the next surface. NaN without the 0.8 API, or where Open PGL returns
// no probability (NaN or outside [0, 1]; vspg-pbrt-v4 and Cycles fall back to free flight there too).
template <class Distribution>
float openpgl_volume_scatter_probability(const Distribution& distribution, const Vec3f& w) {
#ifdef OPENPGL_VSP_GUIDING
    pgl_vec3f direction = pgl_vec(w);
    const float vsp = distribution.VolumeScatterProbability(direction);
    if (vsp >= 0.f && vsp <= 1.f) return vsp;
#endif
    return std::numeric_limits<float>::quiet_NaN();
}

}  // namespace volguide
