// The bitmap texture plugin loading real files: PNG (sRGB → linear, or raw) and EXR (linear), and a
// missing file as an input error at the parameter's line.
#include <gtest/gtest.h>

#include <cmath>

#include "support/cli.h"
#include "volguide/render/image_io.h"
#include "volguide/render/srgb.h"
#include "volguide/render/texture.h"
#include "volguide/scene/factories.h"

using namespace volguide;
using namespace volguide::test;

namespace {

std::shared_ptr<Texture> bitmap(const std::string& file, bool raw = false) {
    Properties props("texture", "bitmap", {"scene.xml", 3});
    props.set("filename", "string", file, {"scene.xml", 4});
    props.set("filter_type", "string", std::string("nearest"), {"scene.xml", 5});
    if (raw) props.set("raw", "boolean", true, {"scene.xml", 6});
    auto tex = std::dynamic_pointer_cast<Texture>(create_texture(props));
    props.check_all_used();
    return tex;
}

Color3 at(const Texture& t, float u, float v) {
    SurfaceInteraction si;
    si.uv = Vec2f(u, v);
    return t.eval(si);
}


}  // namespace

TEST(BitmapFile, PngIsConvertedFromSrgbUnlessRaw) {
    TempDir dir("bitmap-png");
    Image img(2, 1);
    img.at(0, 0) = Color3(srgb_to_linear(128.f / 255.f), 0.f, 1.f);
    img.at(1, 0) = Color3(0.f, 1.f, 0.f);
    write_png(dir.file("t.png"), img);

    auto linear = bitmap(dir.file("t.png"));
    Color3 left = at(*linear, 0.25f, 0.5f), right = at(*linear, 0.75f, 0.5f);
    EXPECT_NEAR(left.r, srgb_to_linear(128.f / 255.f), 1e-3f);
    EXPECT_NEAR(left.b, 1.f, 1e-6f);
    EXPECT_NEAR(right.g, 1.f, 1e-6f);

    auto raw = bitmap(dir.file("t.png"), true);
    EXPECT_NEAR(at(*raw, 0.25f, 0.5f).r, 128.f / 255.f, 1e-6f);
}

TEST(BitmapFile, ExrIsLinear) {
    TempDir dir("bitmap-exr");
    Image img(1, 2);
    img.at(0, 0) = Color3(2.5f, 0.25f, 0.125f);  // top row: v near 0
    img.at(0, 1) = Color3(0.f, 7.f, 0.f);
    write_exr(dir.file("t.exr"), img);
    auto tex = bitmap(dir.file("t.exr"));
    EXPECT_EQ(at(*tex, 0.5f, 0.2f), Color3(2.5f, 0.25f, 0.125f));
    EXPECT_EQ(at(*tex, 0.5f, 0.8f), Color3(0.f, 7.f, 0.f));
}

TEST(BitmapFile, MissingFileIsAnInputErrorAtItsLine) {
    try {
        bitmap("/nonexistent/volguide/texture.png");
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(e.location().line, 4);
        EXPECT_NE(std::string(e.what()).find("texture.png"), std::string::npos);
    }
}
