#include "volguide/vmm/vmf_sum.h"

#include <cstring>

#include "volguide/vmm/simd4.h"

namespace volguide {

using namespace simd4;

float vmf_exp(float x) { return exp4(splat(x))[0]; }

float vmf_sum(const float* mu_x, const float* mu_y, const float* mu_z, const float* kappa,
                     const float* weight, const float* norm, int count, const Vec3f& w) {
    const F4 wx = splat(w.x), wy = splat(w.y), wz = splat(w.z);
    F4 acc = splat(0.f);
    auto terms = [&](F4 mx, F4 my, F4 mz, F4 k, F4 scale) {
        const F4 dx = wx - mx, dy = wy - my, dz = wz - mz;
        F4 omc = splat(0.5f) * (dx * dx + dy * dy + dz * dz);
        omc = omc < splat(2.f) ? omc : splat(2.f);
        return scale * exp4(-k * omc);
    };
    int i = 0;
    for (; i + 4 <= count; i += 4) {
        const F4 scale = weight ? load(weight + i) * load(norm + i) : load(norm + i);
        acc += terms(load(mu_x + i), load(mu_y + i), load(mu_z + i), load(kappa + i), scale);
    }
    if (i < count) {  // the last 1-3 lobes in zero-padded lanes (scale 0 adds exactly 0)
        float t[5][4] = {};
        for (int j = 0; i + j < count; ++j) {
            t[0][j] = mu_x[i + j], t[1][j] = mu_y[i + j], t[2][j] = mu_z[i + j], t[3][j] = kappa[i + j];
            t[4][j] = weight ? weight[i + j] * norm[i + j] : norm[i + j];
        }
        acc += terms(load(t[0]), load(t[1]), load(t[2]), load(t[3]), load(t[4]));
    }
    return (acc[0] + acc[1]) + (acc[2] + acc[3]);
}

}  // namespace volguide
