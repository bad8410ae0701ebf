// Analytic whole-render oracles (issue 2 acceptance): scenes whose exact pixel value is known.
#include <gtest/gtest.h>

#include <cmath>

#include "support/cli.h"
#include "support/ztest.h"
#include "volguide/render/image_io.h"

using namespace volguide;
using namespace volguide::test;

namespace {

struct AnalyticImage {
    Image mean, var;
};

AnalyticImage render_analytic(const TempDir& dir, const std::string& xml, int spp) {
    std::string scene = dir.write("scene.xml", xml);
    CliResult r = run_cli({"render", scene, "-o", dir.file("out.exr"), "--spp", std::to_string(spp), "--seed", "3",
                           "--quiet"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return {read_image(dir.file("out.exr")), read_image(dir.file("out_var.exr"))};
}

// Every pixel has expectation `expected`. The image mean must be within 4 standard errors, and so
// must the mean of every 6x6 block of pixels (5 standard errors), with standard errors from the
// per-sample variances. Blocks rather than single pixels: one pixel's sample variance is unreliable
// for these heavy-tailed estimators, a block's sum of 36 variances is not.
void expect_constant_image(const AnalyticImage& img, int spp, double expected) {
    ImageMean m = image_mean(img.mean, img.var, spp);
    EXPECT_NEAR(m.mean, expected, 4 * m.stderr_ + 1e-6) << "image mean " << m.mean << " ± " << m.stderr_;
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
                const double n = block * block, mean = sum / n, se = std::sqrt(var / spp) / n;
                EXPECT_NEAR(mean, expected, 5 * se + 1e-5)
                    << "block at (" << bx << ", " << by << ") channel " << c << ": " << mean << " ± " << se;
            }
}

const char* kSensor = R"(
    <sensor type="perspective">
        <float name="fov" value="60"/>
        <transform name="to_world"><lookat origin="$origin" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="24"/>
            <rfilter type="box"/></film>
        <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
    </sensor>)";

}  // namespace

// Inside a closed sphere with diffuse albedo 0.5 emitting 0.5: L = 0.5 + 0.5 L, so L = 1 everywhere.
TEST(AnalyticScenes, InsideEmissiveDiffuseSphereIsOne) {
    TempDir dir("furnace-sphere");
    std::string xml = std::string(R"(<scene version="3.0.0">
    <default name="origin" value="0, 0, 0.3"/>
    <integrator type="moment"><integrator type="path"/></integrator>)") +
                      kSensor + R"(
    <shape type="sphere">
        <float name="radius" value="1"/>
        <boolean name="flip_normals" value="true"/>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf>
        <emitter type="area"><rgb name="radiance" value="0.5"/></emitter>
    </shape>
</scene>)";
    const int spp = 1024;
    expect_constant_image(render_analytic(dir, xml, spp), spp, 1.0);
}

// A smooth dielectric sphere in a uniform environment of radiance 1 is invisible on average.
TEST(AnalyticScenes, DielectricSphereInConstantEnvironmentIsOne) {
    TempDir dir("glass-sphere");
    std::string xml = std::string(R"(<scene version="3.0.0">
    <default name="origin" value="0, 0, 2.5"/>
    <integrator type="moment"><integrator type="path"/></integrator>)") +
                      kSensor + R"(
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
    <shape type="sphere">
        <float name="radius" value="0.8"/>
        <bsdf type="dielectric"><float name="int_ior" value="1.5"/></bsdf>
    </shape>
</scene>)";
    const int spp = 1024;
    expect_constant_image(render_analytic(dir, xml, spp), spp, 1.0);
}
