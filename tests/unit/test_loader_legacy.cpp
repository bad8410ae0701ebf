// Mitsuba 0.x scene files (issue 50, scene/legacy_upgrade.h): every mapping of the table read as its
// hand-written Mitsuba 3 form (the same records, value for value), errors and warnings at their lines,
// and what only 0.x files get (unused parameters are warnings there, errors in 3.x files).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <variant>
#include <vector>

#include "support/vol_writer.h"
#include "test_loader_util.h"
#include "volguide/core/log.h"
#include "volguide/render/bsdfs/ior.h"
#include "volguide/render/image_io.h"
#include "volguide/scene/cie1931.h"
#include "volguide/scene/legacy_table.h"
#include "volguide/scene/legacy_upgrade.h"
#include "volguide/scene/legacy_values.h"
#include "volguide/scene/xml_reader.h"

using namespace volguide;
using namespace volguide::test;

namespace {

std::string legacy_scene(const std::string& body, const std::string& version = "0.6.0") {
    return "<scene version=\"" + version + "\">\n" + body + "</scene>\n";
}

// Warnings raised while alive, as "line: message".
class LegacyWarnings {
  public:
    LegacyWarnings() {
        previous_ = set_warning_handler([this](const SourceLocation& loc, const std::string& m) {
            list.push_back(std::to_string(loc.line) + ": " + m);
        });
    }
    ~LegacyWarnings() { set_warning_handler(previous_); }
    bool has(int line, const std::string& needle) const {
        for (const std::string& w : list)
            if (w.rfind(std::to_string(line) + ": ", 0) == 0 && w.find(needle) != std::string::npos) return true;
        return false;
    }
    std::vector<std::string> list;

  private:
    WarningHandler previous_;
};

std::string legacy_describe(const Properties::Value& v);

// Two records are the same when their entries are, named ones by name, unnamed ones in order.
void expect_same_records(const Properties& a, const Properties& b, const std::string& where) {
    EXPECT_EQ(a.category(), b.category()) << where;
    EXPECT_EQ(a.type(), b.type()) << where;
    auto sorted = [](const Properties& p) {
        std::vector<const Properties::Entry*> e;
        for (const auto& x : p.entries()) e.push_back(&x);
        std::stable_sort(e.begin(), e.end(), [](auto* l, auto* r) { return l->name < r->name; });
        return e;
    };
    const auto ea = sorted(a), eb = sorted(b);
    ASSERT_EQ(ea.size(), eb.size()) << where << ": " << a.type() << " has " << ea.size() << " entries, expected "
                                    << eb.size();
    for (size_t i = 0; i < ea.size(); ++i) {
        const std::string at = where + "/" + a.type() + "." + ea[i]->name;
        EXPECT_EQ(ea[i]->name, eb[i]->name) << at;
        EXPECT_EQ(ea[i]->category, eb[i]->category) << at;
        ASSERT_EQ(ea[i]->value.index(), eb[i]->value.index()) << at;
        if (auto* oa = std::get_if<ObjectPtr>(&ea[i]->value)) {
            auto fa = std::dynamic_pointer_cast<FakeObject>(*oa);
            auto fb = std::dynamic_pointer_cast<FakeObject>(std::get<ObjectPtr>(eb[i]->value));
            ASSERT_TRUE(fa && fb) << at;
            expect_same_records(fa->props, fb->props, at);
        } else {
            EXPECT_EQ(legacy_describe(ea[i]->value), legacy_describe(eb[i]->value)) << at;
        }
    }
}

std::string legacy_describe(const Properties::Value& v) {
    if (auto* x = std::get_if<bool>(&v)) return *x ? "true" : "false";
    if (auto* x = std::get_if<int64_t>(&v)) return std::to_string(*x);
    if (auto* x = std::get_if<double>(&v)) return fmt::format("{}", *x);
    if (auto* x = std::get_if<std::string>(&v)) return *x;
    if (auto* x = std::get_if<Color3>(&v)) return fmt::format("({} {} {})", x->r, x->g, x->b);
    if (auto* x = std::get_if<Vec3f>(&v)) return fmt::format("({} {} {})", x->x, x->y, x->z);
    if (auto* x = std::get_if<Transform>(&v)) {
        std::string s;
        for (const auto& row : x->matrix().m)
            for (double e : row) s += fmt::format("{} ", e);
        return s;
    }
    return "?";
}

// A 0.6 body and its hand-written Mitsuba 3 form read into the same records.
void expect_same_scene(const ScratchDir& dir, const std::string& body06, const std::string& body3,
                       const std::string& version = "0.6.0") {
    const Properties a = load_fake(dir.write("legacy.xml", legacy_scene(body06, version)));
    const Properties b = load_fake(dir.write("modern.xml", scene(body3)));
    expect_same_records(a, b, "scene");
}

}  // namespace

TEST(LegacySnakeCase, IsMitsuba3sRule) {
    EXPECT_EQ(snake_case("sigmaA"), "sigma_a");
    EXPECT_EQ(snake_case("intIOR"), "int_ior");
    EXPECT_EQ(snake_case("toWorld"), "to_world");
    EXPECT_EQ(snake_case("cropOffsetX"), "crop_offset_x");
    EXPECT_EQ(snake_case("maxDepth"), "max_depth");
    EXPECT_EQ(snake_case("B"), "B");
    EXPECT_EQ(snake_case("p0"), "p0");
    // Mitsuba 3's loop skips the character after a run of capitals, so "aBcD" keeps its last capital.
    EXPECT_EQ(snake_case("aBcD"), "a_bcD");
}

TEST(LegacyVersions, ZeroFourToZeroSixAreRead) {
    ScratchDir dir;
    for (const char* v : {"0.4.0", "0.5.0", "0.6.0", "0.6.2"}) {
        Properties p = load_fake(dir.write("v.xml", legacy_scene("<integrator type=\"path\"/>\n", v)));
        auto integrator = child(p, "integrator");
        ASSERT_TRUE(integrator) << v;
        EXPECT_EQ(integrator->props.type(), "path") << v;
    }
}

TEST(LegacyVersions, OthersNameWhatIsRead) {
    ScratchDir dir;
    std::string f = dir.write("old.xml", legacy_scene("", "0.3.0"));
    expect_input_error([&] { load_fake(f); }, f, 1, "predates Mitsuba 0.4");
    f = dir.write("one.xml", legacy_scene("", "1.0.0"));
    expect_input_error([&] { load_fake(f); }, f, 1, "0.4.0 to 0.6.x");
    f = dir.write("seven.xml", legacy_scene("", "0.7.0"));
    expect_input_error([&] { load_fake(f); }, f, 1, "not a Mitsuba release");
}

TEST(LegacyIntegrators, RenamesAndDefaults) {
    ScratchDir dir;
    expect_same_scene(dir,
                      "<integrator type=\"volpath\"><integer name=\"maxDepth\" value=\"7\"/>"
                      "<integer name=\"rrDepth\" value=\"3\"/><boolean name=\"hideEmitters\" value=\"true\"/>"
                      "<boolean name=\"strictNormals\" value=\"false\"/></integrator>\n",
                      "<integrator type=\"volpath\"><integer name=\"max_depth\" value=\"7\"/>"
                      "<integer name=\"rr_depth\" value=\"3\"/><boolean name=\"hide_emitters\" value=\"true\"/>"
                      "</integrator>\n");
    expect_same_scene(dir,
                      "<integrator type=\"direct\"><integer name=\"emitterSamples\" value=\"2\"/>"
                      "<integer name=\"bsdfSamples\" value=\"3\"/></integrator>\n",
                      "<integrator type=\"direct\"><integer name=\"emitter_samples\" value=\"2\"/>"
                      "<integer name=\"bsdf_samples\" value=\"3\"/></integrator>\n");
    // 0.6 renders a scene without an integrator with `direct` (Mitsuba 3 with `path`).
    expect_same_scene(dir, "<emitter type=\"constant\"/>\n",
                      "<integrator type=\"direct\"/><emitter type=\"constant\"/>\n");
    LegacyWarnings w;
    expect_same_scene(dir, "<integrator type=\"volpath_simple\"/>\n", "<integrator type=\"volpath\"/>\n");
    EXPECT_TRUE(w.has(2, "'volpath_simple' is read as 'volpath'"));
}

TEST(LegacyIntegrators, StrictNormalsMatterOnlyForSmoothMeshes) {
    ScratchDir dir;
    dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn 0 1 1\nvn 1 0 1\nf 1//1 2//2 3//3\n");
    LegacyWarnings w;
    const std::string strict = "<integrator type=\"path\">\n<boolean name=\"strictNormals\" value=\"true\"/></integrator>\n";
    // Analytic shapes and face normals: every shading normal is geometric, strict or not (0.6's image).
    load_fake(dir.write("flat.xml", legacy_scene(strict + "<shape type=\"sphere\"/><shape type=\"cube\"/>\n"
                                                          "<shape type=\"obj\"><string name=\"filename\" value=\"tri.obj\"/>"
                                                          "<boolean name=\"faceNormals\" value=\"true\"/></shape>\n")));
    EXPECT_TRUE(w.list.empty()) << w.list.front();
    // A smooth mesh: paths 0.6 drops at grazing angles are kept, which is said at the parameter's line.
    const std::string f = dir.write("smooth.xml", legacy_scene(strict + "<shape type=\"obj\"><string name=\"filename\" "
                                                                        "value=\"tri.obj\"/></shape>\n"));
    Properties p = load_fake(f);
    EXPECT_TRUE(w.has(3, "strictNormals=true is read as false")) << (w.list.empty() ? "" : w.list.front());
    EXPECT_TRUE(w.has(3, "its obj mesh at line 4"));
    EXPECT_TRUE(child(p, "integrator")->props.entries().empty());
}

TEST(LegacySensors, CameraFilmSampler) {
    ScratchDir dir;
    LegacyWarnings w;
    expect_same_scene(dir,
                      "<sensor type=\"perspective\">\n"
                      "  <float name=\"fov\" value=\"30\"/><string name=\"fovAxis\" value=\"Y\"/>\n"
                      "  <float name=\"nearClip\" value=\"0.1\"/><float name=\"farClip\" value=\"100\"/>\n"
                      "  <transform name=\"toWorld\"><scale x=\"-1\"/><lookAt origin=\"0,0,5\" target=\"0,0,0\" "
                      "up=\"0,1,0\"/></transform>\n"
                      "  <film type=\"hdrfilm\"><integer name=\"width\" value=\"40\"/><integer name=\"height\" value=\"30\"/>"
                      "<boolean name=\"highQualityEdges\" value=\"true\"/><string name=\"pixelFormat\" value=\"RGB\"/>"
                      "<boolean name=\"banner\" value=\"false\"/><rfilter type=\"gaussian\"><float name=\"stddev\" "
                      "value=\"0.3\"/></rfilter></film>\n"
                      "  <sampler type=\"ldsampler\"><integer name=\"sampleCount\" value=\"16\"/>"
                      "<integer name=\"dimension\" value=\"8\"/></sampler>\n"
                      "</sensor>\n",
                      "<integrator type=\"direct\"/><sensor type=\"perspective\">\n"
                      "  <float name=\"fov\" value=\"30\"/><string name=\"fov_axis\" value=\"y\"/>\n"
                      "  <float name=\"near_clip\" value=\"0.1\"/><float name=\"far_clip\" value=\"100\"/>\n"
                      "  <transform name=\"to_world\"><scale x=\"-1\"/><lookat origin=\"0,0,5\" target=\"0,0,0\" "
                      "up=\"0,1,0\"/></transform>\n"
                      "  <film type=\"hdrfilm\"><integer name=\"width\" value=\"40\"/><integer name=\"height\" value=\"30\"/>"
                      "<boolean name=\"sample_border\" value=\"true\"/><string name=\"pixel_format\" value=\"rgb\"/>"
                      "<rfilter type=\"gaussian\"><float name=\"stddev\" value=\"0.3\"/></rfilter></film>\n"
                      "  <sampler type=\"ldsampler\"><integer name=\"sample_count\" value=\"16\"/></sampler>\n"
                      "</sensor>\n");
    EXPECT_TRUE(w.has(7, "'dimension'"));
    // 0.6's films read annotations, which volguide does not write: a warning each.
    load_fake(dir.write("labels.xml", legacy_scene("<sensor type=\"perspective\"><film type=\"ldrfilm\">\n"
                                                   "<string name=\"label[10, 10]\" value=\"$scene['renderTime']\"/>\n"
                                                   "<string name=\"metadata['k']\" value=\"v\"/></film></sensor>\n")));
    EXPECT_TRUE(w.has(3, "annotations"));
    EXPECT_TRUE(w.has(4, "annotations"));
    // The low-discrepancy samplers Mitsuba 3 lacks are independent ones, said on stderr.
    expect_same_scene(dir, "<sensor type=\"perspective\"><sampler type=\"sobol\"><integer name=\"sampleCount\" "
                           "value=\"32\"/></sampler></sensor>\n",
                      "<integrator type=\"direct\"/><sensor type=\"perspective\"><sampler type=\"independent\">"
                      "<integer name=\"sample_count\" "
                      "value=\"32\"/></sampler></sensor>\n");
    EXPECT_TRUE(w.has(2, "sampler 'sobol' is read as 'independent' (32 samples per pixel)"));
}

TEST(LegacySensors, MediumOfSensorAndEmitter) {
    ScratchDir dir;
    expect_same_scene(dir,
                      "<medium type=\"homogeneous\" id=\"fog\"><spectrum name=\"sigmaT\" value=\"0.1\"/>"
                      "<spectrum name=\"albedo\" value=\"0.5\"/></medium>\n"
                      "<sensor type=\"perspective\"><ref id=\"fog\"/></sensor>\n"
                      "<emitter type=\"point\"><point name=\"position\" x=\"0\" y=\"1\" z=\"0\"/><ref id=\"fog\"/></emitter>\n",
                      "<integrator type=\"direct\"/><medium type=\"homogeneous\" id=\"fog\">"
                      "<spectrum name=\"sigma_t\" value=\"0.1\"/><spectrum name=\"albedo\" value=\"0.5\"/></medium>\n"
                      "<sensor type=\"perspective\"><ref id=\"fog\" name=\"medium\"/></sensor>\n"
                      "<emitter type=\"point\"><point name=\"position\" x=\"0\" y=\"1\" z=\"0\"/>"
                      "<ref id=\"fog\" name=\"medium\"/></emitter>\n");
}

TEST(LegacyValues, ColoursAndSpectra) {
    ScratchDir dir;
    const float s = std::pow((128 / 255.0f + 0.055f) * (1.0f / 1.055f), 2.4f);
    const legacy::Rgb bb = legacy::blackbody_rgb(4000);
    const double wl[] = {400, 500, 600, 700}, val[] = {0.2, 0.4, 0.6, 0.8};
    const Color3 pairs = spectrum_to_linear_srgb(wl, val, {true, false}).rgb;
    expect_same_scene(
        dir,
        "<bsdf type=\"diffuse\" id=\"a\"><rgb name=\"reflectance\" value=\"#ff8000\" intent=\"reflectance\"/></bsdf>\n"
        "<bsdf type=\"diffuse\" id=\"b\"><srgb name=\"reflectance\" value=\"#808080\"/></bsdf>\n"
        "<bsdf type=\"diffuse\" id=\"c\"><spectrum name=\"reflectance\" value=\"0.1, 0.2, 0.3\"/></bsdf>\n"
        "<bsdf type=\"diffuse\" id=\"d\"><spectrum name=\"reflectance\" value=\"400:0.2, 500:0.4, 600:0.6, 700:0.8\"/></bsdf>\n"
        "<emitter type=\"constant\"><blackbody name=\"radiance\" temperature=\"4000K\" scale=\"2\"/></emitter>\n",
        fmt::format("<integrator type=\"direct\"/>\n"
                    "<bsdf type=\"diffuse\" id=\"a\"><rgb name=\"reflectance\" value=\"1 {} 0\"/></bsdf>\n"
                    "<bsdf type=\"diffuse\" id=\"b\"><rgb name=\"reflectance\" value=\"{} {} {}\"/></bsdf>\n"
                    "<bsdf type=\"diffuse\" id=\"c\"><rgb name=\"reflectance\" value=\"0.1 0.2 0.3\"/></bsdf>\n"
                    "<bsdf type=\"diffuse\" id=\"d\"><rgb name=\"reflectance\" value=\"{} {} {}\"/></bsdf>\n"
                    "<emitter type=\"constant\"><rgb name=\"radiance\" value=\"{} {} {}\"/></emitter>\n",
                    128 / 255.0f, s, s, s, pairs.r, pairs.g, pairs.b, float(2 * bb[0]), float(2 * bb[1]),
                    float(2 * bb[2])));
    // A black body at 6504 K is near sRGB's white (D65 lies just off the Planckian locus); one at 3000 K
    // is reddish; the luminance grows steeply with the temperature (Planck's law).
    const legacy::Rgb warm = legacy::blackbody_rgb(3000), white = legacy::blackbody_rgb(6504);
    EXPECT_GT(warm[0], 2 * warm[2]);
    EXPECT_NEAR(white[0] / white[1], 1.0, 0.1);
    EXPECT_NEAR(white[2] / white[1], 1.0, 0.1);
    EXPECT_GT(legacy::blackbody_rgb(8000)[1], 5 * bb[1]);
}

TEST(LegacyMedia, HomogeneousCoefficients) {
    ScratchDir dir;
    // sigmaA + sigmaS: sigma_t = a + s, albedo = s / (a + s).
    expect_same_scene(dir,
                      "<medium type=\"homogeneous\" id=\"m\"><spectrum name=\"sigmaA\" value=\"0.25\"/>"
                      "<rgb name=\"sigmaS\" value=\"0.75, 1.75, 0\"/><float name=\"scale\" value=\"4\"/>"
                      "<phase type=\"hg\"><float name=\"g\" value=\"0.7\"/></phase></medium>\n",
                      "<integrator type=\"direct\"/><medium type=\"homogeneous\" id=\"m\">"
                      "<rgb name=\"sigma_t\" value=\"1 2 0.25\"/><rgb name=\"albedo\" value=\"0.75 0.875 0\"/>"
                      "<float name=\"scale\" value=\"4\"/><phase type=\"hg\"><float name=\"g\" value=\"0.7\"/></phase>"
                      "</medium>\n");
    // sigmaT + albedo are Mitsuba 3's own; a medium's own g reduces sigmaS to (1 - g) sigmaS.
    expect_same_scene(dir,
                      "<medium type=\"homogeneous\" id=\"m\"><spectrum name=\"sigmaT\" value=\"2\"/>"
                      "<spectrum name=\"albedo\" value=\"0.5\"/></medium>\n"
                      "<medium type=\"homogeneous\" id=\"n\"><spectrum name=\"sigmaT\" value=\"2\"/>"
                      "<spectrum name=\"albedo\" value=\"0.5\"/><float name=\"g\" value=\"0.5\"/></medium>\n",
                      "<integrator type=\"direct\"/><medium type=\"homogeneous\" id=\"m\">"
                      "<spectrum name=\"sigma_t\" value=\"2\"/><spectrum name=\"albedo\" value=\"0.5\"/></medium>\n"
                      "<medium type=\"homogeneous\" id=\"n\"><rgb name=\"sigma_t\" value=\"1.5\"/>"
                      "<rgb name=\"albedo\" value=\"0.33333334\"/></medium>\n");
}

TEST(LegacyMedia, HeterogeneousGridVolumes) {
    ScratchDir dir;
    // A 5 x 3 x 3 grid over the box [-1, 3] x [0, 2] x [0, 2]: 0.6's voxels at the corners of unit
    // cells. The unit cube maps onto the box grown by half a voxel.
    VolGrid g = make_vol_grid(5, 3, 3, 1, [](float, float, float, int) { return 0.f; });
    g.values[size_t((1 * 3 + 1) * 5 + 2)] = 1.f;  // the one inner voxel
    const float box[6] = {-1, 0, 0, 3, 2, 2};
    std::copy(box, box + 6, g.bbox);
    write_vol_file(dir.path("density.vol"), g);
    LegacyWarnings w;
    expect_same_scene(
        dir,
        "<medium type=\"heterogeneous\" id=\"smoke\">\n"
        "  <string name=\"method\" value=\"woodcock\"/>\n"
        "  <volume name=\"density\" type=\"gridvolume\"><string name=\"filename\" value=\"density.vol\"/>\n"
        "    <transform name=\"toWorld\"><translate x=\"10\"/></transform></volume>\n"
        "  <volume name=\"albedo\" type=\"constvolume\"><spectrum name=\"value\" value=\"0.9\"/></volume>\n"
        "  <float name=\"scale\" value=\"100\"/>\n"
        "</medium>\n",
        "<integrator type=\"direct\"/><medium type=\"heterogeneous\" id=\"smoke\">\n"
        "  <volume name=\"sigma_t\" type=\"gridvolume\"><string name=\"filename\" value=\"density.vol\"/>\n"
        "    <transform name=\"to_world\"><scale x=\"5\" y=\"3\" z=\"3\"/><translate x=\"-1.5\" y=\"-0.5\" "
        "z=\"-0.5\"/><translate x=\"10\"/></transform></volume>\n"
        "  <volume name=\"albedo\" type=\"constvolume\"><spectrum name=\"value\" value=\"0.9\"/></volume>\n"
        "  <float name=\"scale\" value=\"100\"/>\n"
        "</medium>\n");
    EXPECT_TRUE(w.list.empty()) << w.list.front();
    // min/max replace the file's box; Simpson quadrature is read as unbiased tracking (a warning).
    expect_same_scene(
        dir,
        "<medium type=\"heterogeneous\" id=\"smoke\">\n"
        "  <string name=\"method\" value=\"simpson\"/>\n"
        "  <volume name=\"density\" type=\"gridvolume\"><string name=\"filename\" value=\"density.vol\"/>\n"
        "    <point name=\"min\" x=\"0\" y=\"0\" z=\"0\"/><point name=\"max\" x=\"8\" y=\"4\" z=\"4\"/></volume>\n"
        "  <volume name=\"albedo\" type=\"constvolume\"><spectrum name=\"value\" value=\"0.9\"/></volume>\n"
        "</medium>\n",
        "<integrator type=\"direct\"/><medium type=\"heterogeneous\" id=\"smoke\">\n"
        "  <volume name=\"sigma_t\" type=\"gridvolume\"><string name=\"filename\" value=\"density.vol\"/>\n"
        "    <transform name=\"to_world\"><scale x=\"10\" y=\"6\" z=\"6\"/><translate x=\"-1\" y=\"-1\" "
        "z=\"-1\"/></transform></volume>\n"
        "  <volume name=\"albedo\" type=\"constvolume\"><spectrum name=\"value\" value=\"0.9\"/></volume>\n"
        "</medium>\n");
    EXPECT_TRUE(w.has(3, "method 'simpson'"));
    // Non-zero outermost voxels: the medium ends differently (half a voxel), which is said.
    g.values[0] = 1.f;
    write_vol_file(dir.path("edge.vol"), g);
    load_fake(dir.write("edge.xml", legacy_scene("<volume type=\"gridvolume\" id=\"v\"><string name=\"filename\" "
                                                 "value=\"edge.vol\"/></volume>\n")));
    EXPECT_TRUE(w.has(2, "outermost voxels are not all zero"));
}

TEST(LegacyBsdfs, RenamesDefaultsAndConductors) {
    ScratchDir dir;
    const ComplexIor cu = *conductor_preset("Cu");
    const float air = 1.000277f;
    expect_same_scene(
        dir,
        "<bsdf type=\"diffuse\" id=\"a\"><spectrum name=\"diffuseReflectance\" value=\"0.3\"/></bsdf>\n"
        "<bsdf type=\"roughdielectric\" id=\"b\"><string name=\"distribution\" value=\"GGX\"/><float name=\"alphaU\" "
        "value=\"0.1\"/><float name=\"alphaV\" value=\"0.2\"/><string name=\"intIOR\" value=\"water\"/>"
        "<float name=\"extIOR\" value=\"1.1\"/><boolean name=\"sampleVisible\" value=\"false\"/></bsdf>\n"
        "<bsdf type=\"conductor\" id=\"c\"/>\n"
        "<bsdf type=\"roughconductor\" id=\"d\"><string name=\"material\" value=\"none\"/><float name=\"extEta\" "
        "value=\"2\"/></bsdf>\n"
        "<bsdf type=\"plastic\" id=\"e\"><spectrum name=\"diffuseReflectance\" value=\"0.5\"/>"
        "<boolean name=\"nonlinear\" value=\"true\"/></bsdf>\n"
        "<bsdf type=\"blendbsdf\" id=\"f\"><bsdf type=\"diffuse\"/><bsdf type=\"null\"/></bsdf>\n"
        "<bsdf type=\"mixturebsdf\" id=\"g\"><string name=\"weights\" value=\"0.25, 0.75\"/><bsdf type=\"diffuse\"/>"
        "<bsdf type=\"null\"/></bsdf>\n"
        "<bsdf type=\"twosided\" id=\"h\"><bsdf type=\"diffuse\"><spectrum name=\"reflectance\" value=\"2\"/></bsdf>"
        "</bsdf>\n",
        fmt::format(
            "<integrator type=\"direct\"/>\n"
            "<bsdf type=\"diffuse\" id=\"a\"><spectrum name=\"reflectance\" value=\"0.3\"/></bsdf>\n"
            "<bsdf type=\"roughdielectric\" id=\"b\"><string name=\"distribution\" value=\"ggx\"/><float "
            "name=\"alpha_u\" value=\"0.1\"/><float name=\"alpha_v\" value=\"0.2\"/><string name=\"int_ior\" "
            "value=\"water\"/><float name=\"ext_ior\" value=\"1.1\"/><boolean name=\"sample_visible\" "
            "value=\"false\"/></bsdf>\n"
            "<bsdf type=\"conductor\" id=\"c\"><rgb name=\"eta\" value=\"{} {} {}\"/><rgb name=\"k\" value=\"{} {} "
            "{}\"/></bsdf>\n"
            "<bsdf type=\"roughconductor\" id=\"d\"><rgb name=\"eta\" value=\"0\"/><rgb name=\"k\" value=\"0.5\"/></bsdf>\n"
            "<bsdf type=\"plastic\" id=\"e\"><spectrum name=\"diffuse_reflectance\" value=\"0.5\"/>"
            "<boolean name=\"nonlinear\" value=\"true\"/></bsdf>\n"
            "<bsdf type=\"blendbsdf\" id=\"f\"><bsdf type=\"diffuse\"/><bsdf type=\"null\"/><float name=\"weight\" "
            "value=\"0.5\"/></bsdf>\n"
            "<bsdf type=\"blendbsdf\" id=\"g\"><float name=\"weight\" value=\"0.75\"/><bsdf type=\"diffuse\"/>"
            "<bsdf type=\"null\"/></bsdf>\n"
            "<bsdf type=\"twosided\" id=\"h\"><bsdf type=\"diffuse\"><rgb name=\"reflectance\" value=\"{}\"/></bsdf>"
            "</bsdf>\n",
            cu.eta.r / air, cu.eta.g / air, cu.eta.b / air, cu.k.r / air, cu.k.g / air, cu.k.b / air,
            2.0f * (0.99f * (1.0f / 2.0f))));
}

TEST(LegacyBsdfs, EnergyConservationCanBeOff) {
    ScratchDir dir;
    LegacyWarnings w;
    expect_same_scene(dir,
                      "<bsdf type=\"diffuse\" id=\"a\"><boolean name=\"ensureEnergyConservation\" value=\"false\"/>"
                      "<spectrum name=\"reflectance\" value=\"2\"/></bsdf>\n",
                      "<integrator type=\"direct\"/><bsdf type=\"diffuse\" id=\"a\">"
                      "<spectrum name=\"reflectance\" value=\"2\"/></bsdf>\n");
    EXPECT_TRUE(w.list.empty());
    load_fake(dir.write("on.xml", legacy_scene("<bsdf type=\"diffuse\" id=\"a\">\n"
                                               "<spectrum name=\"reflectance\" value=\"2\"/></bsdf>\n")));
    EXPECT_TRUE(w.has(3, "scaled by 0.495"));
    // A floating-point texture above 1 would be scaled by 0.6: no equivalent, an error at its line.
    write_exr(dir.path("bright.exr"), Image(2, 2, Color3(2.f, 0.5f, 0.5f)));
    const std::string texture = "<texture type=\"bitmap\" name=\"reflectance\"><string name=\"filename\" "
                                "value=\"bright.exr\"/><string name=\"filterType\" value=\"bilinear\"/></texture>";
    const std::string f = dir.write("tex.xml", legacy_scene("<bsdf type=\"diffuse\" id=\"a\">\n" + texture + "</bsdf>\n"));
    expect_input_error([&] { load_fake(f); }, f, 3, "scales this texture by 0.495");
    EXPECT_NO_THROW(load_fake(dir.write("off.xml", legacy_scene("<bsdf type=\"diffuse\" id=\"a\"><boolean name=\""
                                                                 "ensureEnergyConservation\" value=\"false\"/>" +
                                                                 texture + "</bsdf>\n"))));
}

TEST(LegacyTextures, BitmapAndUvTransforms) {
    ScratchDir dir;
    write_png(dir.path("tex.png"), Image(2, 2, Color3(0.5f)));
    LegacyWarnings w;
    // 0.6 looks up uv * scale + offset: the scale first.
    expect_same_scene(
        dir,
        "<texture type=\"bitmap\" id=\"a\"><string name=\"filename\" value=\"tex.png\"/>"
        "<string name=\"filterType\" value=\"nearest\"/><string name=\"wrapMode\" value=\"clamp\"/>"
        "<float name=\"gamma\" value=\"1\"/><float name=\"uscale\" value=\"2\"/><float name=\"voffset\" value=\"0.5\"/>"
        "</texture>\n"
        "<texture type=\"checkerboard\" id=\"b\"><float name=\"uvscale\" value=\"4\"/></texture>\n",
        "<integrator type=\"direct\"/>\n"
        "<texture type=\"bitmap\" id=\"a\"><string name=\"filename\" value=\"tex.png\"/>"
        "<string name=\"filter_type\" value=\"nearest\"/><string name=\"wrap_mode\" value=\"clamp\"/>"
        "<boolean name=\"raw\" value=\"true\"/><string name=\"format\" value=\"fp16\"/>"
        "<transform name=\"to_uv\"><scale x=\"2\" y=\"1\"/><translate x=\"0\" y=\"0.5\"/></transform></texture>\n"
        "<texture type=\"checkerboard\" id=\"b\"><transform name=\"to_uv\"><scale x=\"4\" y=\"4\"/>"
        "<translate x=\"0\" y=\"0\"/></transform></texture>\n");
    EXPECT_TRUE(w.list.empty());
    // 0.6's default filter is EWA: read bilinearly, with a warning.
    load_fake(dir.write("ewa.xml", legacy_scene("<texture type=\"bitmap\" id=\"a\"><string name=\"filename\" "
                                                "value=\"tex.png\"/></texture>\n")));
    EXPECT_TRUE(w.has(2, "EWA over each ray's footprint (its default)"));
}

TEST(LegacyShapes, DefaultBsdfsAndMeshes) {
    ScratchDir dir;
    dir.write("mesh.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    expect_same_scene(
        dir,
        "<medium type=\"homogeneous\" id=\"fog\"><spectrum name=\"sigmaT\" value=\"1\"/>"
        "<spectrum name=\"albedo\" value=\"0.5\"/></medium>\n"
        "<shape type=\"sphere\"><point name=\"center\" x=\"1\" y=\"2\" z=\"3\"/><emitter type=\"area\">"
        "<spectrum name=\"radiance\" value=\"5\"/></emitter></shape>\n"
        "<shape type=\"cube\"><ref name=\"interior\" id=\"fog\"/><boolean name=\"flipNormals\" value=\"true\"/></shape>\n"
        "<shape type=\"rectangle\"/>\n"
        "<shape type=\"obj\"><string name=\"filename\" value=\"mesh.obj\"/><boolean name=\"faceNormals\" value=\"true\"/>"
        "<boolean name=\"flipTexCoords\" value=\"false\"/><integer name=\"shapeIndex\" value=\"-1\"/>"
        "<bsdf type=\"diffuse\"/></shape>\n",
        "<integrator type=\"direct\"/>\n"
        "<medium type=\"homogeneous\" id=\"fog\"><spectrum name=\"sigma_t\" value=\"1\"/>"
        "<spectrum name=\"albedo\" value=\"0.5\"/></medium>\n"
        "<shape type=\"sphere\"><point name=\"center\" x=\"1\" y=\"2\" z=\"3\"/><emitter type=\"area\">"
        "<rgb name=\"radiance\" value=\"5\"/></emitter><bsdf type=\"diffuse\"><rgb name=\"reflectance\" "
        "value=\"0\"/></bsdf></shape>\n"
        "<shape type=\"cube\"><ref name=\"interior\" id=\"fog\"/><boolean name=\"flip_normals\" value=\"true\"/>"
        "<bsdf type=\"null\"/></shape>\n"
        "<shape type=\"rectangle\"/>\n"
        "<shape type=\"obj\"><string name=\"filename\" value=\"mesh.obj\"/><boolean name=\"face_normals\" "
        "value=\"true\"/><boolean name=\"flip_tex_coords\" value=\"false\"/><bsdf type=\"diffuse\"/></shape>\n");
}

TEST(LegacyShapes, ObjMaterialsAreRefused) {
    ScratchDir dir;
    dir.write("m.mtl", "newmtl red\nKd 1 0 0\n");
    dir.write("mat.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n");
    std::string f = dir.write("obj.xml", legacy_scene("<shape type=\"obj\">\n<string name=\"filename\" value=\"mat.obj\"/>"
                                                      "</shape>\n"));
    expect_input_error([&] { load_fake(f); }, f, 2, "reads no .mtl");
    // loadMaterials=false gives 0.6's default diffuse, as does an explicit BSDF.
    f = dir.write("obj2.xml", legacy_scene("<shape type=\"obj\"><string name=\"filename\" value=\"mat.obj\"/>"
                                           "<boolean name=\"loadMaterials\" value=\"false\"/></shape>\n"));
    EXPECT_NO_THROW(load_fake(f));
    // A BSDF named after the only material is the shape's; one named after no material is ignored; one
    // of several materials would give faces different BSDFs.
    f = dir.write("obj3.xml", legacy_scene("<shape type=\"obj\"><string name=\"filename\" value=\"mat.obj\"/>\n"
                                           "<bsdf type=\"diffuse\" name=\"red\"/></shape>\n"));
    EXPECT_EQ(child(load_fake(f), "shape")->props.children("bsdf").size(), 1u);
    LegacyWarnings w;
    f = dir.write("obj4.xml", legacy_scene("<shape type=\"obj\"><string name=\"filename\" value=\"mat.obj\"/>\n"
                                           "<bsdf type=\"diffuse\"/><bsdf type=\"null\" name=\"blue\"/></shape>\n"));
    EXPECT_EQ(child(load_fake(f), "shape")->props.children("bsdf").size(), 1u);
    EXPECT_TRUE(w.has(3, "uses no material 'blue'"));
    dir.write("two.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\nusemtl green\nf 1 3 2\n");
    f = dir.write("obj5.xml", legacy_scene("<shape type=\"obj\"><string name=\"filename\" value=\"two.obj\"/>\n"
                                           "<bsdf type=\"diffuse\" name=\"red\"/></shape>\n"));
    expect_input_error([&] { load_fake(f); }, f, 3, "one of the OBJ's materials ('red')");
}

TEST(LegacyFilms, LdrfilmKeepsItsTonemap) {
    ScratchDir dir;
    LegacyWarnings w;
    expect_same_scene(dir,
                      "<sensor type=\"perspective\"><film type=\"ldrfilm\"><string name=\"tonemapMethod\" "
                      "value=\"reinhard\"/><float name=\"key\" value=\"0.3\"/><float name=\"burn\" value=\"0.1\"/>"
                      "<float name=\"gamma\" value=\"2.2\"/><string name=\"fileFormat\" value=\"png\"/>"
                      "<string name=\"pixelFormat\" value=\"rgb\"/></film></sensor>\n",
                      "<integrator type=\"direct\"/><sensor type=\"perspective\"><film type=\"ldrfilm\">"
                      "<string name=\"tonemap_method\" value=\"reinhard\"/><float name=\"key\" value=\"0.3\"/>"
                      "<float name=\"burn\" value=\"0.1\"/><float name=\"gamma\" value=\"2.2\"/></film></sensor>\n");
    EXPECT_TRUE(w.list.empty());
}

TEST(LegacyIds, ReservedIdsAreRenamed) {
    ScratchDir dir;
    LegacyWarnings w;
    expect_same_scene(dir, "<bsdf type=\"diffuse\" id=\"_white\"/>\n<shape type=\"sphere\"><ref id=\"_white\"/></shape>\n",
                      "<integrator type=\"direct\"/><bsdf type=\"diffuse\" id=\"ID_white__UPGR\"/>\n"
                      "<shape type=\"sphere\"><ref id=\"ID_white__UPGR\"/></shape>\n");
    EXPECT_TRUE(w.has(2, "renamed \"ID_white__UPGR\""));
}

TEST(LegacyWarningsAndErrors, UnknownParametersWarnOnlyInZeroX) {
    ScratchDir dir;
    LegacyWarnings w;
    // A parameter 0.6's plugin does not read (a fork's, or a Mitsuba 3 name): a warning, then dropped.
    std::string f = dir.write("fork.xml", legacy_scene("<integrator type=\"volpath\">\n"
                                                       "  <boolean name=\"useGuiding\" value=\"true\"/>\n"
                                                       "  <integer name=\"max_depth\" value=\"3\"/>\n"
                                                       "</integrator>\n"));
    Properties p = load_fake(f);
    EXPECT_TRUE(w.has(3, "does not read a parameter 'useGuiding'"));
    EXPECT_TRUE(w.has(4, "does not read a parameter 'max_depth'"));
    EXPECT_TRUE(child(p, "integrator")->props.entries().empty());
    // The same parameter in a 3.x file stays an error of the plugin that does not read it.
    f = dir.write("modern.xml", scene("<integrator type=\"strict\">\n<boolean name=\"use_guiding\" value=\"true\"/>"
                                      "</integrator>\n"));
    expect_input_error([&] { load_fake(f); }, f, 3, "has no parameter 'use_guiding'");
}

TEST(LegacyWarningsAndErrors, NoEquivalentIsAnErrorAtItsLine) {
    ScratchDir dir;
    struct Case {
        std::string body;
        int line;
        std::string needle;
    };
    const Case cases[] = {
        {"<integrator type=\"guided\"/>\n", 2, "Mitsuba 0.6 has no integrator plugin 'guided'"},
        {"<integrator type=\"bdpt\"/>\n", 2, "render with 'volpath'"},
        {"<shape type=\"ply\">\n<float name=\"maxSmoothAngle\" value=\"30\"/></shape>\n", 3, "'maxSmoothAngle'"},
        {"<medium type=\"homogeneous\" id=\"m\">\n<string name=\"material\" value=\"Ketchup\"/></medium>\n", 3,
         "named medium presets"},
        {"<medium type=\"homogeneous\" id=\"m\">\n<spectrum name=\"sigmaA\" value=\"1\"/></medium>\n", 3,
         "'skin1' preset"},
        {"<medium type=\"heterogeneous\" id=\"m\">\n</medium>\n", 2, "needs a 'density' volume"},
        {"<sensor type=\"perspective\">\n<animation name=\"toWorld\"></animation></sensor>\n", 3, "<animation>"},
        {"<bsdf type=\"roughconductor\" id=\"b\">\n<string name=\"distribution\" value=\"phong\"/></bsdf>\n", 3,
         "Phong microfacet distribution"},
        {"<bsdf type=\"conductor\" id=\"b\">\n<string name=\"material\" value=\"Unobtainium\"/></bsdf>\n", 3,
         "unknown conductor material 'Unobtainium'"},
        {"<bsdf type=\"bumpmap\" id=\"b\"/>\n", 2, "bump mapping"},
        {"<shape type=\"sphere\">\n<subsurface type=\"dipole\"/></shape>\n", 3, "homogeneous' medium inside"},
        {"<bsdf type=\"mixturebsdf\" id=\"b\">\n<string name=\"weights\" value=\"0.5, 0.2\"/><bsdf type=\"diffuse\"/>"
         "<bsdf type=\"null\"/></bsdf>\n",
         2, "weights sum to 1"},
        {"<texture type=\"bitmap\" id=\"t\">\n<float name=\"gamma\" value=\"2.2\"/><string name=\"filename\" "
         "value=\"x.png\"/></texture>\n",
         3, "gamma 2.2 has no equivalent"},
        {"<texture type=\"bitmap\" id=\"t\">\n<string name=\"wrapModeU\" value=\"clamp\"/></texture>\n", 2,
         "different wrap modes"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.body);
        const std::string f = dir.write("bad.xml", legacy_scene(c.body));
        expect_input_error([&] { load_fake(f); }, f, c.line, c.needle);
    }
}

TEST(LegacyWarningsAndErrors, ErrorsOfRewrittenElementsKeepTheirLines) {
    ScratchDir dir;
    // <lookAt> is renamed <lookat>: its own error is still at its line.
    std::string f = dir.write("look.xml", legacy_scene("<sensor type=\"perspective\"><transform name=\"toWorld\">\n"
                                                       "<lookAt origin=\"1,1,1\" target=\"1,1,1\"/></transform></sensor>\n"));
    expect_input_error([&] { load_fake(f); }, f, 3, "origin and target coincide");
    // The computed albedo of a medium with a negative sigmaA is out of range: at sigmaA's line, where
    // the plugin's check sees the rewritten value.
    f = dir.write("albedo.xml", legacy_scene("<medium type=\"homogeneous\" id=\"m\">\n"
                                             "<spectrum name=\"sigmaA\" value=\"-0.5\"/>\n"
                                             "<spectrum name=\"sigmaS\" value=\"1\"/></medium>\n"));
    expect_input_error([&] { load_scene_properties(f); }, f, 3, "albedo must lie in [0, 1]");
}

TEST(LegacyUpgrade, WrittenFileReadsAsTheInput) {
    ScratchDir dir;
    write_png(dir.path("tex.png"), Image(2, 2, Color3(0.25f)));
    VolGrid g = make_vol_grid(3, 3, 3, 1, [](float, float, float, int) { return 0.f; });
    g.values[13] = 2.f;
    write_vol_file(dir.path("d.vol"), g);
    const std::string in = dir.write(
        "in.xml",
        "<?xml version=\"1.0\"?>\n<!-- kept -->\n" +
            legacy_scene(
                "<integrator type=\"volpath\"><integer name=\"maxDepth\" value=\"5\"/></integrator>\n"
                "<sensor type=\"perspective\"><float name=\"fov\" value=\"50\"/>\n"
                "  <transform name=\"toWorld\"><lookAt origin=\"0,0,4\" target=\"0,0,0\" up=\"0,1,0\"/></transform>\n"
                "  <sampler type=\"halton\"><integer name=\"sampleCount\" value=\"12\"/></sampler>\n"
                "  <film type=\"hdrfilm\"><integer name=\"width\" value=\"8\"/><integer name=\"height\" value=\"6\"/>"
                "</film><ref id=\"fog\"/></sensor>\n"
                "<medium type=\"homogeneous\" id=\"fog\"><spectrum name=\"sigmaA\" value=\"0.1\"/>"
                "<srgb name=\"sigmaS\" value=\"0.5, 0.25, 1\"/></medium>\n"
                "<medium type=\"heterogeneous\" id=\"smoke\"><volume name=\"density\" type=\"gridvolume\">"
                "<string name=\"filename\" value=\"d.vol\"/></volume><volume name=\"albedo\" type=\"constvolume\">"
                "<rgb name=\"value\" value=\"#c0c0ff\"/></volume></medium>\n"
                "<shape type=\"cube\"><ref name=\"interior\" id=\"smoke\"/></shape>\n"
                "<shape type=\"rectangle\"><bsdf type=\"roughconductor\"><string name=\"material\" value=\"Au\"/>"
                "<float name=\"alpha\" value=\"0.3\"/></bsdf></shape>\n"
                "<shape type=\"sphere\"><bsdf type=\"diffuse\"><texture type=\"bitmap\" name=\"reflectance\">"
                "<string name=\"filename\" value=\"tex.png\"/><float name=\"uoffset\" value=\"0.5\"/></texture></bsdf>"
                "<emitter type=\"area\"><spectrum name=\"radiance\" value=\"400:1, 700:2\"/></emitter></shape>\n"));
    const std::string text = upgrade_scene_file(in, {});
    const std::string out = dir.write("out.xml", text);
    expect_same_records(load_fake(in), load_fake(out), "scene");
    EXPECT_EQ(text.rfind("<?xml version=\"1.0\"?>\n<!-- kept -->\n<scene version=\"3.0.0\">", 0), 0u) << text;
    for (const char* name06 : {"maxDepth", "toWorld", "lookAt", "sigmaA", "srgb", "halton", "density", "uoffset"})
        EXPECT_EQ(text.find(name06), std::string::npos) << name06 << " in\n" << text;
    // A file that is not 0.x is refused.
    expect_input_error([&] { upgrade_scene_file(out, {}); }, out, 3, "not a Mitsuba 0.x file");
}

TEST(LegacyUpgrade, LdrfilmBecomesHdrfilm) {
    ScratchDir dir;
    LegacyWarnings w;
    // With 0.6's default tonemap (the sRGB curve) nothing is lost: no warning.
    const std::string plain = dir.write("plain.xml", legacy_scene("<sensor type=\"perspective\"><film type=\"ldrfilm\">"
                                                                  "<float name=\"gamma\" value=\"-1\"/></film></sensor>\n"));
    EXPECT_NE(upgrade_scene_file(plain, {}).find("<film type=\"hdrfilm\"/>"), std::string::npos);
    EXPECT_TRUE(w.list.empty()) << w.list.front();
    const std::string tonemapped = dir.write("reinhard.xml", legacy_scene("<sensor type=\"perspective\">\n"
                                                                          "<film type=\"ldrfilm\"><string name=\""
                                                                          "tonemapMethod\" value=\"reinhard\"/>"
                                                                          "</film></sensor>\n"));
    upgrade_scene_file(tonemapped, {});
    EXPECT_TRUE(w.has(3, "loses the PNG tonemap (tonemap_method=reinhard)"));
}

TEST(LegacyTable, DocsListEveryPluginAndParameter) {
    // docs/scene-format.md, "Mitsuba 0.6 scenes", is the table's user-facing form: every 0.6 plugin and
    // parameter the table knows is named there (in backticks), so none is wired without being documented.
    std::ifstream in(std::string(VOLGUIDE_SOURCE_DIR) + "/docs/scene-format.md");
    std::string doc((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const size_t begin = doc.find("## Mitsuba 0.6 scenes");
    ASSERT_NE(begin, std::string::npos);
    const std::string section = doc.substr(begin, doc.find("\n## ", begin + 1) - begin);
    for (const legacy::PluginRule& p : legacy::plugin_table()) {
        EXPECT_NE(section.find("`" + std::string(p.type) + "`"), std::string::npos) << p.category << " " << p.type;
        for (auto rules : {p.params, p.family})
            for (const legacy::ParamRule& r : rules)
                EXPECT_NE(section.find("`" + std::string(r.name) + "`"), std::string::npos)
                    << p.type << " parameter " << r.name;
    }
}

TEST(LegacyUpgrade, ComputedValuesFixTheirParameters) {
    ScratchDir dir;
    LegacyWarnings w;
    const std::string f = dir.write("p.xml", legacy_scene("<default name=\"a\" value=\"0.25\"/>\n"
                                                          "<medium type=\"homogeneous\" id=\"m\"><spectrum name=\"sigmaA\" "
                                                          "value=\"$a\"/>\n<spectrum name=\"sigmaS\" value=\"0.75\"/>"
                                                          "</medium>\n"));
    LoadOptions options;
    options.defines["a"] = "0.5";
    const std::string text = upgrade_scene_file(f, options);
    EXPECT_NE(text.find("<rgb name=\"sigma_t\" value=\"1.25 1.25 1.25\"/>"), std::string::npos) << text;
    EXPECT_TRUE(w.has(3, "'sigmaA' is \"$a\" (\"0.5\" here) and enters a computed value"));
    // Loading (not writing) the file says nothing: the value is the parameter's.
    w.list.clear();
    load_fake(f);
    EXPECT_TRUE(w.list.empty()) << w.list.front();
}

TEST(LegacyIncludes, EachFileIsReadByItsOwnVersion) {
    ScratchDir dir;
    // A 0.6 file included by a 3.0 one is upgraded; the 3.0 one is not, and gets Mitsuba 3's defaults.
    dir.write("part06.xml", legacy_scene("<bsdf type=\"diffuse\" id=\"white\"><spectrum name=\"diffuseReflectance\" "
                                         "value=\"0.8\"/></bsdf>\n<shape type=\"sphere\"><ref id=\"white\"/>"
                                         "<transform name=\"toWorld\"><translate x=\"1\"/></transform></shape>\n"));
    dir.write("part3.xml", scene("<integrator type=\"path\"><integer name=\"max_depth\" value=\"3\"/></integrator>\n"));
    const std::string main3 = dir.write("main3.xml", scene("<include filename=\"part06.xml\"/>\n"));
    const std::string expected3 = dir.write("expected3.xml", scene(
        "<bsdf type=\"diffuse\" id=\"white\"><spectrum name=\"reflectance\" value=\"0.8\"/></bsdf>\n<shape "
        "type=\"sphere\"><ref id=\"white\"/><transform name=\"to_world\"><translate x=\"1\"/></transform></shape>\n"));
    expect_same_records(load_fake(main3), load_fake(expected3), "scene");
    // A 0.6 main file gets 0.6's default integrator only when none of its files declares one.
    const std::string main06 = dir.write("main06.xml", legacy_scene("<include filename=\"part06.xml\"/>\n"));
    EXPECT_EQ(child(load_fake(main06), "integrator")->props.type(), "direct");
    const std::string with_integrator =
        dir.write("main06b.xml", legacy_scene("<include filename=\"part06.xml\"/>\n<include filename=\"part3.xml\"/>\n"));
    const Properties p = load_fake(with_integrator);
    ASSERT_EQ(p.children("integrator").size(), 1u);
    EXPECT_EQ(child(p, "integrator")->props.type(), "path");
}
