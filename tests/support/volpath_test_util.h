#pragma once
// Rendering helpers for the volumetric integrator tests: render an XML scene in-process (optionally
// with the test media of support/test_media.h), and compare images statistically.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "support/cli.h"
#include "support/test_media.h"
#include "volguide/core/image.h"
#include "volguide/integrators/render_loop.h"
#include "volguide/render/scene.h"
#include "volguide/scene/loader.h"

namespace volguide::test {

struct Rendered {
    Image mean, var;  // var: per-sample variance (the scene must wrap its integrator in `moment`)
    int spp = 0;
};

// Renders `xml` with the given spp and seed; `test_media` swaps in support/test_media.h's media.
inline Rendered render_scene_xml(const std::string& xml, int spp, uint64_t seed, bool test_media = true,
                                 const LoadOptions& options = {}) {
    TempDir dir("volpath-test");
    const std::string path = dir.write("scene.xml", xml);
    std::unique_ptr<Scene> scene = test_media ? load_scene_with_test_media(path, options) : load_scene(path, options);
    RenderOptions ro;
    ro.spp = spp;
    ro.seed = seed;
    RenderResult r = render(*scene, ro);
    return {r.mean, r.variance, r.spp};
}

// Mean over the pixels of one channel (c = 0..2) or all (c = -1), with its standard error.
struct ChannelMean {
    double mean = 0, se = 0;
};
inline ChannelMean channel_mean(const Rendered& r, int c = -1) {
    double sum = 0, var = 0;
    long n = 0;
    for (size_t i = 0; i < r.mean.pixels.size(); ++i)
        for (int k = 0; k < 3; ++k) {
            if (c >= 0 && k != c) continue;
            sum += r.mean.pixels[i][k];
            var += r.var.pixels[i][k];
            ++n;
        }
    return {sum / n, std::sqrt(var / r.spp) / n};
}

// Two-sample z-test of the per-channel image means of two independent renders of one scene.
inline void expect_same_means(const Rendered& a, const Rendered& b, double z_max = 4.0) {
    for (int c = 0; c < 3; ++c) {
        ChannelMean ma = channel_mean(a, c), mb = channel_mean(b, c);
        const double se = std::sqrt(ma.se * ma.se + mb.se * mb.se) + 1e-9;
        EXPECT_LT(std::abs(ma.mean - mb.mean) / se, z_max)
            << "channel " << c << ": " << ma.mean << " ± " << ma.se << " vs " << mb.mean << " ± " << mb.se;
    }
}

// Every pixel has expectation `expected`: the image mean within 4 standard errors, every 6x6 block
// within 5 (block sums of variances are reliable where single-pixel variances are not).
inline void expect_constant_image(const Rendered& img, double expected) {
    ChannelMean m = channel_mean(img);
    EXPECT_NEAR(m.mean, expected, 4 * m.se + 1e-6) << "image mean " << m.mean << " ± " << m.se;
    const int block = 6;
    for (int by = 0; by + block <= img.mean.height; by += block)
        for (int bx = 0; bx + block <= img.mean.width; bx += block)
            for (int c = 0; c < 3; ++c) {
                double sum = 0, var = 0;
                for (int y = by; y < by + block; ++y)
                    for (int x = bx; x < bx + block; ++x) {
                        sum += img.mean.at(x, y)[c];
                        var += img.var.at(x, y)[c];
                    }
                const double n = block * block, mean = sum / n, se = std::sqrt(var / img.spp) / n;
                EXPECT_NEAR(mean, expected, 5 * se + 1e-5)
                    << "block at (" << bx << ", " << by << ") channel " << c << ": " << mean << " ± " << se;
            }
}

}  // namespace volguide::test
