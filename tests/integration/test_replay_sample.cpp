// Replaying a camera sample reproduces it bit for bit (camera_sample.h): a 1-spp render through the
// render loop (box filter: a pixel is its one sample's value) against samples recomputed through
// the shared entry point, and against tools/replay_sample, for volpath and guided_volpath with its
// defaults (guided RR/splitting against the pixel estimate at the sample's film position).
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "support/cli.h"
#include "volguide/core/image.h"
#include "volguide/integrators/camera_sample.h"
#include "volguide/integrators/render_loop.h"
#include "volguide/render/scene.h"
#include "volguide/scene/loader.h"

using namespace volguide;
using volguide::test::TempDir;

namespace {

constexpr int kWidth = 12, kHeight = 9;
constexpr uint64_t kSeed = 11;
const std::string kReplayScene = std::string(VOLGUIDE_SOURCE_DIR) + "/bench/scenes/fogbox.xml";

// The scene defines of a tiny fogbox rendered by `integrator_xml` (empty: volpath).
std::vector<std::pair<std::string, std::string>> scene_defines(const std::string& integrator_xml) {
    std::vector<std::pair<std::string, std::string>> d = {
        {"width", std::to_string(kWidth)}, {"height", std::to_string(kHeight)}, {"spp", "1"}, {"max_depth", "16"}};
    if (!integrator_xml.empty()) d.push_back({"integrator_xml", integrator_xml});
    return d;
}

std::unique_ptr<Scene> load_replay_scene(const std::string& integrator_xml) {
    LoadOptions options;
    for (const auto& [name, value] : scene_defines(integrator_xml)) options.defines[name] = value;
    return load_scene(kReplayScene, options);
}

// guided_volpath with its defaults (distance, direction, grrs), a small training pass.
std::string guided_xml(const TempDir& dir) {
    return dir.write("guided.xml", R"(<?xml version="1.0" encoding="utf-8"?>
<scene version="3.0.0">
    <integrator type="guided_volpath">
        <integer name="max_depth" value="$max_depth"/>
        <integer name="photons" value="20000"/>
    </integrator>
</scene>
)");
}

// The pixels replayed: corners, centre and a few in between.
std::vector<std::pair<int, int>> replayed_pixels() {
    return {{0, 0}, {kWidth - 1, 0}, {0, kHeight - 1}, {kWidth - 1, kHeight - 1}, {kWidth / 2, kHeight / 2},
            {3, 2},  {7, 5},          {10, 1},           {2, 7}};
}

bool same_bits(const Color3& a, const Color3& b) { return a.r == b.r && a.g == b.g && a.b == b.b; }

// Renders 1 spp through the render loop, then recomputes samples through the shared entry point
// with an integrator preprocessed the same way on a second copy of the scene (guided_volpath learns
// at the end of every pass, so the rendered integrator's state is no longer the first pass's). With `position_matters`, the same samples with the film
// position of another pixel (the ray kept) must differ somewhere: guided RR/splitting reads the
// pixel estimate there, so the comparison would catch a replay that loses the film position.
void expect_replays_match_render(const std::string& integrator_xml, bool position_matters = false) {
    auto scene = load_replay_scene(integrator_xml);
    RenderOptions options;
    options.seed = kSeed;
    options.threads = 2;
    const RenderResult render_result = render(*scene, options);
    ASSERT_EQ(render_result.spp, 1);
    scene = load_replay_scene(integrator_xml);
    PreprocessContext context;
    context.seed = kSeed;
    const_cast<Integrator&>(scene->integrator()).preprocess(*scene, context);
    const Film& film = scene->sensor().film();
    ASSERT_EQ(film.sample_border(), false);
    const FilmGrid grid{film.width(), film.height(), 0};
    int nonzero = 0, moved_differs = 0;
    for (const auto& [x, y] : replayed_pixels()) {
        FilmSample sample = film_sample(grid, kSeed, x, y, 0);
        FilmSample moved = sample;
        const Color3 L = camera_sample_value(*scene, scene->integrator(), sample.film_uv, sample.sampler);
        const Color3 L_moved = camera_sample_value(scene->sensor(), moved.film_uv, [&](const CameraRay& camera) {
            const CameraRay elsewhere{camera.ray, Point2f(1.f - camera.film_uv.x, 1.f - camera.film_uv.y)};
            return scene->integrator().Li(*scene, moved.sampler, elsewhere);
        });
        moved_differs += !same_bits(L, L_moved);
        const Color3 pixel = render_result.mean.at(x, y);
        EXPECT_TRUE(same_bits(L, pixel)) << "pixel (" << x << ", " << y << "): replayed (" << L.r << ", " << L.g
                                         << ", " << L.b << "), rendered (" << pixel.r << ", " << pixel.g << ", "
                                         << pixel.b << ")";
        nonzero += L.max_value() > 0.f;
    }
    EXPECT_GT(nonzero, 3);  // the comparison sees light, not only black pixels
    if (position_matters) {
        EXPECT_GT(moved_differs, 0);
    }
}

// tools/replay_sample's printed value of sample 0 of pixel (x, y).
Color3 run_replay_tool(int x, int y, const std::string& integrator_xml) {
    std::string command = fmt::format("'{}' '{}' {} {} 0 {}", VOLGUIDE_REPLAY_SAMPLE, kReplayScene, x, y, kSeed);
    for (const auto& [name, value] : scene_defines(integrator_xml)) command += fmt::format(" '{}={}'", name, value);
    command += " 2>/dev/null";
    std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
    if (!pipe) return Color3(-1.f);
    std::string out;
    char buffer[512];
    while (fgets(buffer, sizeof buffer, pipe.get())) out += buffer;
    // "pixel (x, y) sample s seed n: L = (r, g, b)"; fmt prints the shortest representation that
    // reads back to the same float.
    const size_t at = out.find("L = (");
    if (at == std::string::npos) return Color3(-1.f);
    Color3 L(-1.f);
    if (std::sscanf(out.c_str() + at, "L = (%f, %f, %f)", &L.r, &L.g, &L.b) != 3) return Color3(-1.f);
    return L;
}

void expect_tool_matches_render(const std::string& integrator_xml) {
    auto scene = load_replay_scene(integrator_xml);
    RenderOptions options;
    options.seed = kSeed;
    options.threads = 1;
    const Image image = render(*scene, options).mean;
    for (const auto& [x, y] : {std::pair{kWidth / 2, kHeight / 2}, std::pair{3, 2}}) {
        const Color3 L = run_replay_tool(x, y, integrator_xml);
        const Color3 pixel = image.at(x, y);
        EXPECT_TRUE(same_bits(L, pixel)) << "pixel (" << x << ", " << y << "): replay_sample printed (" << L.r
                                         << ", " << L.g << ", " << L.b << "), rendered (" << pixel.r << ", "
                                         << pixel.g << ", " << pixel.b << ")";
    }
}

}  // namespace

TEST(ReplaySample, VolpathSamplesReplayBitForBit) { expect_replays_match_render(""); }

TEST(ReplaySample, GuidedVolpathSamplesReplayBitForBit) {
    TempDir dir("replay_guided");
    expect_replays_match_render(guided_xml(dir), /*position_matters=*/true);
}

TEST(ReplaySample, ToolReproducesVolpathAndGuidedVolpathSamples) {
    expect_tool_matches_render("");
    TempDir dir("replay_tool_guided");
    expect_tool_matches_render(guided_xml(dir));
}
