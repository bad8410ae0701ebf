// Mitsuba 3 conformance (oracles.md §7) for the 12 scenes of Mitsuba's participating-media test
// suite, rendered through the CLI with `volpath` (and `volpathmis` for the *_volpathmis scenes, as
// those scenes declare; same references), compared per pixel with Mitsuba's reference mean and
// per-sample variance (tests/support/ztest.h: XYZ, α = 0.01 Šidák-corrected, 99.75 % of
// pixel-channels must pass).
// Budget: spp = 2e6 / pixel count (868 spp at 48 x 48), as Mitsuba's test_renders.py; about 2·10^6
// camera paths of depth ≤ 6 (16 for the dielectric scene) per scene, together well under two minutes
// on two cores.
// Needs ../shared/mitsuba-data (third-party data, never copied into the repository): skipped, visibly,
// when that folder is absent. On failure the render and the error mask are written next to the build
// (conformance-<scene>-render.exr / -errors.exr).
#include <gtest/gtest.h>

#include <filesystem>

#include "support/cli.h"
#include "support/test_support.h"
#include "support/ztest.h"
#include "volguide/render/image_io.h"

using namespace volguide;
using namespace volguide::test;

namespace {

const std::string kMediaSuite = shared_dir() + "/mitsuba-data/tests/scenes/participating_media";

// Replaces every occurrence of `from` in `text` (which must contain it) by `to`.
std::string media_replace_all(std::string text, const std::string& from, const std::string& to) {
    EXPECT_NE(text.find(from), std::string::npos) << from;
    for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
        text.replace(at, from.size(), to);
    return text;
}

// The suite scene `scene` with `params` (XML elements) added to the nested integrator, written into
// `dir` (the suite is read-only): a copy of the scene whose <path> points into the suite, beside
// copies of the include files that declare the integrator (found first, from the scene's folder).
std::string media_scene_with_params(const TempDir& dir, const std::string& scene, const std::string& params) {
    const std::string suite_root = kMediaSuite + "/../../..";
    std::string xml = read_file(kMediaSuite + "/" + scene + ".xml");
    xml = media_replace_all(xml, R"(<path value="../../../common"/>)",
                            "<path value=\"" + suite_root + "/common\"/><path value=\"" + kMediaSuite + "\"/>");
    std::filesystem::create_directories(dir.path() / "include");
    for (const char* base : {"include/test-scene-base.xml", "include/test-scene-base-no-bg.xml"})
        dir.write(base, media_replace_all(read_file(kMediaSuite + "/" + base), R"(<integrator type="$integrator">)",
                                          R"(<integrator type="$integrator">)" + params));
    return dir.write(scene + ".xml", xml);
}

// `scene` = XML file stem; its reference is the stem without the integrator suffix. `params`: XML
// elements added to the integrator (empty: the scene as it is).
void run_media_conformance(const std::string& scene, const std::string& integrator, const std::string& params = "") {
    if (!std::filesystem::exists(kMediaSuite)) GTEST_SKIP() << "SKIPPED: " << kMediaSuite << " is absent";
    const std::string suffix = "_" + scene.substr(scene.rfind('_') + 1);
    const std::string ref_name = scene.substr(0, scene.size() - suffix.size());
    const std::string xml = kMediaSuite + "/" + scene + ".xml";
    Image ref_img = read_image(kMediaSuite + "/refs/" + ref_name + "_ref_rgb.exr");
    Image ref_var_img = read_image(kMediaSuite + "/refs/" + ref_name + "_ref_rgb_var.exr");
    const int spp = int(2e6 / (double(ref_img.width) * ref_img.height) + 0.5);

    TempDir dir("conformance-media-" + scene + "-" + integrator);
    const std::string scene_file = params.empty() ? xml : media_scene_with_params(dir, scene, params);
    // Mitsuba's reference variance is volpath's: an estimator with another variance (guided_volpath)
    // is tested with its own per-sample variance (support/ztest.h's own_variance_ztest: its 3x3
    // average, since per pixel it is not trustworthy where the weights are heavy-tailed —
    // guided_volpath with every decision off, the volpath estimator, failed HomoAreaLight with
    // per-pixel variances at seeds 1-5, 32-54 of 6912 pixel-channels).
    const bool own_variance = integrator == "guided_volpath";
    std::vector<std::string> cmd = {"render", scene_file,
                                    "-o",     dir.file("out.exr"),
                                    "-D",     "integrator=" + integrator,
                                    "--spp",  std::to_string(spp),
                                    "--seed", "1",
                                    "--quiet"};
    if (own_variance) cmd.push_back("--variance");
    CliResult r = run_cli(cmd);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    Image mean = read_image(dir.file("out.exr"));
    Image mask;
    bool rejects_dark = true;
    ZTestResult z = own_variance ? own_variance_ztest(mean, spp, ref_img, read_image(dir.file("out_var.exr")),
                                                      &rejects_dark, &mask)
                                 : pixel_ztest(mean, spp, ref_img, ref_var_img, ZTestOptions{}, &mask);
    EXPECT_TRUE(rejects_dark) << scene << ": the test has no power (the image 25 % too dark passes)";
    if (!z.passed) {
        const std::string stem =
            std::filesystem::current_path().string() + "/conformance-" + scene + "-" + integrator;
        write_exr(stem + "-render.exr", mean);
        write_exr(stem + "-errors.exr", mask);
    }
    EXPECT_TRUE(z.passed) << scene << " (" << integrator << ") at " << spp << " spp: " << z.summary();
}

}  // namespace

#define VOLPATH_SCENE(test_name, scene)        \
    TEST(MitsubaConformanceMedia, test_name) { \
        run_media_conformance(scene, "volpath");     \
    }
#define VOLPATHMIS_SCENE(test_name, scene)     \
    TEST(MitsubaConformanceMedia, test_name) { \
        run_media_conformance(scene, "volpathmis");  \
    }

VOLPATH_SCENE(HeteroSigmatAlbedo, "test_hetero_sigmat_albedo_volpath")
VOLPATH_SCENE(HeteroSigmat, "test_hetero_sigmat_volpath")
VOLPATH_SCENE(HeteroSpectralSigmatNoScattering, "test_hetero_spectral_sigmat_no_scattering_volpath")
VOLPATHMIS_SCENE(HeteroSpectralSigmatMis, "test_hetero_spectral_sigmat_volpathmis")
VOLPATH_SCENE(HomoAreaLight, "test_homo_area_light_volpath")
VOLPATH_SCENE(HomoDielectricEnvmap, "test_homo_dielectric_envmap_volpath")
VOLPATH_SCENE(HomoEmitterInsideMedium, "test_homo_emitter_inside_medium_volpath")
VOLPATH_SCENE(HomoNullEnvmap, "test_homo_null_envmap_volpath")
VOLPATH_SCENE(HomoObjInsideMedium, "test_homo_obj_inside_medium_volpath")
VOLPATH_SCENE(HomoRoughDielectricSpot, "test_homo_roughdielectric_spot_volpath")
VOLPATHMIS_SCENE(HomoSpectralSigmatMis, "test_homo_spectral_sigmat_volpathmis")
VOLPATH_SCENE(SurfAreaLight, "test_surf_area_light_volpath")

// The same scenes with guided_volpath's defaults (issue 7: distance=incremental direction=product,
// photon training; rrs falls back to throughput RR): guiding changes the variance, never the mean.
// Tested against the estimator's own per-sample variance, averaged over 3x3 pixels (per pixel it is
// not trustworthy where the weights are heavy-tailed: see support/ztest.h's own_variance_ztest).
// HeteroSigmat and HeteroSigmatAlbedo failed with the proxy-based bins (H1: 54 and 67 of 6912 pixel-channels at
// 868 spp, per-pixel variances); with guided null-collision tracking (H2, the default in
// heterogeneous media) they pass.
#define GUIDED_SCENE(test_name, scene)               \
    TEST(MitsubaConformanceMediaGuided, test_name) { \
        run_media_conformance(scene, "guided_volpath");    \
    }

GUIDED_SCENE(HeteroSigmatAlbedo, "test_hetero_sigmat_albedo_volpath")
GUIDED_SCENE(HeteroSigmat, "test_hetero_sigmat_volpath")
GUIDED_SCENE(HeteroSpectralSigmatNoScattering, "test_hetero_spectral_sigmat_no_scattering_volpath")
GUIDED_SCENE(HeteroSpectralSigmatMis, "test_hetero_spectral_sigmat_volpathmis")
GUIDED_SCENE(HomoAreaLight, "test_homo_area_light_volpath")
GUIDED_SCENE(HomoDielectricEnvmap, "test_homo_dielectric_envmap_volpath")
GUIDED_SCENE(HomoEmitterInsideMedium, "test_homo_emitter_inside_medium_volpath")
GUIDED_SCENE(HomoNullEnvmap, "test_homo_null_envmap_volpath")
GUIDED_SCENE(HomoObjInsideMedium, "test_homo_obj_inside_medium_volpath")
GUIDED_SCENE(HomoRoughDielectricSpot, "test_homo_roughdielectric_spot_volpath")
GUIDED_SCENE(HomoSpectralSigmatMis, "test_homo_spectral_sigmat_volpathmis")
GUIDED_SCENE(SurfAreaLight, "test_surf_area_light_volpath")

// distance="vsp" (issue 37, docs/theory.md §7.10) in the full system on the same scenes, the same
// test: the closed-form segment decision (with its equiangular share, §7.10.1) in the homogeneous
// scenes, the resampled one in the heterogeneous (chromatic: the spectral ones) scenes.
#define GUIDED_VSP_SCENE(test_name, scene)                                                  \
    TEST(MitsubaConformanceMediaGuidedVsp, test_name) {                                     \
        run_media_conformance(scene, "guided_volpath", R"(<string name="distance" value="vsp"/>)"); \
    }

GUIDED_VSP_SCENE(HeteroSigmatAlbedo, "test_hetero_sigmat_albedo_volpath")
GUIDED_VSP_SCENE(HeteroSigmat, "test_hetero_sigmat_volpath")
GUIDED_VSP_SCENE(HeteroSpectralSigmatNoScattering, "test_hetero_spectral_sigmat_no_scattering_volpath")
GUIDED_VSP_SCENE(HeteroSpectralSigmatMis, "test_hetero_spectral_sigmat_volpathmis")
GUIDED_VSP_SCENE(HomoAreaLight, "test_homo_area_light_volpath")
GUIDED_VSP_SCENE(HomoDielectricEnvmap, "test_homo_dielectric_envmap_volpath")
GUIDED_VSP_SCENE(HomoEmitterInsideMedium, "test_homo_emitter_inside_medium_volpath")
GUIDED_VSP_SCENE(HomoNullEnvmap, "test_homo_null_envmap_volpath")
GUIDED_VSP_SCENE(HomoObjInsideMedium, "test_homo_obj_inside_medium_volpath")
GUIDED_VSP_SCENE(HomoRoughDielectricSpot, "test_homo_roughdielectric_spot_volpath")
GUIDED_VSP_SCENE(HomoSpectralSigmatMis, "test_homo_spectral_sigmat_volpathmis")
GUIDED_VSP_SCENE(SurfAreaLight, "test_surf_area_light_volpath")
