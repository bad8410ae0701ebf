// `ptracer` (integrators/ptracer.h, light_tracing.h): its image is path's. A small room (diffuse floor
// and wall, a rough conductor block, a spherical area light seen by the camera, a spot light) rendered
// by path (per-sample variance from the render) and by ptracer (8 independent renders: the variance of
// their mean from their spread), compared per pixel-channel with a Bonferroni-corrected two-sample
// z-test and on the image mean. Plus: the same image for 1 and 2 threads, hide_emitters, and the
// loader's errors.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "support/bench_two_sample.h"
#include "support/cli.h"
#include "volguide/core/error.h"
#include "volguide/integrators/render_loop.h"
#include "volguide/render/scene.h"
#include "volguide/scene/loader.h"

using namespace volguide;
using namespace volguide::test;

namespace {

std::string ptracer_room_xml(const std::string& integrator) {
    return R"(<scene version="3.0.0">
  <integrator type=")" +
           integrator + R"(">
    <integer name="max_depth" value="4"/>
    <integer name="rr_depth" value="2"/>
  </integrator>
  <sensor type="perspective">
    <float name="fov" value="60"/>
    <transform name="to_world"><lookat origin="0, 1.5, -4.5" target="0, 0.6, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="16"/>
      <rfilter type="box"/></film>
  </sensor>
  <bsdf type="diffuse" id="white"><rgb name="reflectance" value="0.8, 0.7, 0.6"/></bsdf>
  <shape type="rectangle"><ref id="white"/>
    <transform name="to_world"><scale value="4"/><rotate x="1" angle="-90"/></transform></shape>
  <shape type="rectangle"><ref id="white"/>
    <transform name="to_world"><scale value="4"/><rotate y="1" angle="180"/><translate z="2"/></transform></shape>
  <shape type="cube">
    <bsdf type="roughconductor"><float name="alpha" value="0.3"/></bsdf>
    <transform name="to_world"><scale value="0.4"/><rotate y="1" angle="30"/><translate x="0.8" y="0.4"/></transform>
  </shape>
  <shape type="sphere"><point name="center" value="-0.8, 1.2, 0.5"/><float name="radius" value="0.25"/>
    <emitter type="area"><rgb name="radiance" value="6, 5, 4"/></emitter></shape>
  <emitter type="spot"><rgb name="intensity" value="8"/><float name="cutoff_angle" value="35"/>
    <transform name="to_world"><lookat origin="0.5, 2.5, -1" target="0.5, 0, 0.5" up="0, 0, 1"/></transform>
  </emitter>
</scene>)";
}

RenderResult ptracer_render(const std::string& path, int spp, uint64_t seed, int threads = 0,
                            bool variance = false) {
    auto scene = load_scene(path);
    RenderOptions options;
    options.spp = spp;
    options.seed = seed;
    options.threads = threads;
    options.variance = variance;
    return render(*scene, options);
}

// ptracer's mean and per-sample variance from `renders` independent renders of `spp` each.
BenchRender ptracer_mean_of_renders(const std::string& path, int spp, int renders) {
    BenchRender out{Image(), Image(), spp * renders};
    std::vector<Image> images;
    for (int k = 0; k < renders; ++k) images.push_back(ptracer_render(path, spp, 100 + k).mean);
    out.mean = Image(images[0].width, images[0].height);
    out.var = Image(images[0].width, images[0].height);
    for (size_t i = 0; i < out.mean.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            double sum = 0, sum2 = 0;
            for (const Image& img : images) {
                sum += img.pixels[i][c];
                sum2 += double(img.pixels[i][c]) * img.pixels[i][c];
            }
            const double m = sum / renders, v = std::max(0.0, (sum2 - renders * m * m) / (renders - 1));
            out.mean.pixels[i][c] = float(m);
            // The variance of one render's mean is v; expressed per sample (× spp) for the two-sample test.
            out.var.pixels[i][c] = float(v * spp);
        }
    return out;
}

}  // namespace

TEST(Ptracer, SameImageAsPath) {
    TempDir dir("ptracer-vs-path");
    const RenderResult p = ptracer_render(dir.write("path.xml", ptracer_room_xml("path")), 1024, 7, 0, true);
    const BenchRender path{p.mean, p.variance, p.spp};
    const BenchRender light =
        ptracer_mean_of_renders(dir.write("ptracer.xml", ptracer_room_xml("ptracer")), 128, 8);
    expect_same_expectation(path, light, "ptracer room", "path", "ptracer");
}

TEST(Ptracer, SameImageForOneAndTwoThreads) {
    TempDir dir("ptracer-threads");
    const std::string path = dir.write("ptracer.xml", ptracer_room_xml("ptracer"));
    const RenderResult one = ptracer_render(path, 6, 3, 1), two = ptracer_render(path, 6, 3, 2);
    ASSERT_EQ(one.mean.pixels.size(), two.mean.pixels.size());
    for (size_t i = 0; i < one.mean.pixels.size(); ++i)
        ASSERT_EQ(one.mean.pixels[i], two.mean.pixels[i]) << i;
    EXPECT_EQ(one.spp, 6);
}

TEST(Ptracer, HideEmittersRemovesOnlyTheVisibleEmitter) {
    TempDir dir("ptracer-hide");
    std::string xml = ptracer_room_xml("ptracer");
    xml.replace(xml.find("<integer name=\"rr_depth\""), 0,
                "<boolean name=\"hide_emitters\" value=\"true\"/>");
    const Image shown = ptracer_render(dir.write("a.xml", ptracer_room_xml("ptracer")), 16, 5).mean;
    const Image hidden = ptracer_render(dir.write("b.xml", xml), 16, 5).mean;
    double sum_shown = 0, sum_hidden = 0;
    for (size_t i = 0; i < shown.pixels.size(); ++i) {
        sum_shown += shown.pixels[i].r;
        sum_hidden += hidden.pixels[i].r;
    }
    EXPECT_LT(sum_hidden, sum_shown);
    EXPECT_GT(sum_hidden, 0.0);
}

TEST(Ptracer, ErrorsNameFileAndLine) {
    TempDir dir("ptracer-errors");
    std::string bad = ptracer_room_xml("ptracer");
    bad.replace(bad.find("<integer name=\"rr_depth\" value=\"2\"/>"), 0,
                "<integer name=\"samples_per_pass\" value=\"0\"/>");
    const std::string bad_path = dir.write("bad.xml", bad);
    try {
        load_scene(bad_path);
        ADD_FAILURE() << "samples_per_pass 0 accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(bad_path + ":4:"), std::string::npos) << e.what();
    }
    std::string lens = ptracer_room_xml("ptracer");
    const std::string from = "<sensor type=\"perspective\">";
    lens.replace(lens.find(from), from.size(),
                 "<sensor type=\"thinlens\"><float name=\"aperture_radius\" value=\"0.05\"/>");
    const std::string ortho = dir.write("lens.xml", lens);
    try {
        load_scene(ortho);
        ADD_FAILURE() << "thin lens accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(ortho + ":2: a light tracer"), std::string::npos) << e.what();
    }
}

// ptracer renders surfaces only: a medium anywhere (the sensor's, a shape's interior or exterior, a
// light's) is an error at the integrator's line naming the integrators that render media; the same
// scenes load with path (which, as Mitsuba's, ignores media).
TEST(Ptracer, RefusesParticipatingMediaAtItsLine) {
    TempDir dir("ptracer-media");
    const std::string fog =
        R"(<medium type="homogeneous" id="fog"><float name="sigma_t" value="0.1"/></medium>)";
    const std::string ref = R"(<ref name="medium" id="fog"/>)";
    struct Case {
        const char* name;
        std::string from, to;
    };
    const Case cases[] = {
        {"sensor", "<float name=\"fov\" value=\"60\"/>", "<float name=\"fov\" value=\"60\"/>" + ref},
        {"exterior", "<shape type=\"cube\">", "<shape type=\"cube\"><ref name=\"exterior\" id=\"fog\"/>"},
        {"spot", "<rgb name=\"intensity\" value=\"8\"/>", "<rgb name=\"intensity\" value=\"8\"/>" + ref},
    };
    for (const Case& c : cases) {
        for (const std::string integrator : {"ptracer", "path"}) {
            std::string xml = ptracer_room_xml(integrator);
            xml.replace(xml.find(c.from), c.from.size(), c.to);
            xml.replace(xml.find("<sensor"), 0, fog + "\n  ");
            const std::string path = dir.write(std::string(c.name) + "-" + integrator + ".xml", xml);
            if (integrator == "path") {
                EXPECT_NO_THROW(load_scene(path)) << c.name;
                continue;
            }
            try {
                load_scene(path);
                ADD_FAILURE() << c.name << ": ptracer accepted a medium";
            } catch (const InputError& e) {
                const std::string what = e.what();
                EXPECT_NE(what.find(path + ":2: ptracer renders surfaces only"), std::string::npos) << what;
                EXPECT_NE(what.find("volpath or guided_volpath"), std::string::npos) << what;
            }
        }
    }
}
