// Image reading/writing: exact EXR round trip, PNG within one 8-bit step, real EXR input, errors.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <gtest/gtest.h>
#include <stb/stb_image_write.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "support/test_support.h"
#include "volguide/core/error.h"
#include "volguide/render/image_io.h"
#include "volguide/render/srgb.h"

using namespace volguide;
namespace fs = std::filesystem;

namespace {

// A fresh scratch directory per test, removed afterwards.
class ImageIo : public ::testing::Test {
  protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("volguide_image_io_" + std::to_string(::getpid()) + "_" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    bool only_file_is(const std::string& name) const {
        int count = 0;
        for (const auto& entry : fs::directory_iterator(dir_)) {
            ++count;
            if (entry.path().filename() != name) return false;
        }
        return count == 1;
    }
    fs::path dir_;
};

Image test_pattern(int w, int h) {
    Image image(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            image.at(x, y) = Color3(x / float(w), y / float(h), 0.1234567f * (x + 3 * y) + 1e-5f);
    return image;
}

}  // namespace

TEST_F(ImageIo, ExrRoundTripIsExact) {
    Image image = test_pattern(17, 9);
    image.at(3, 4) = Color3(1e6f, -2.5f, 0.f);  // HDR and negative values survive float32
    write_exr(path("a.exr"), image);
    EXPECT_TRUE(only_file_is("a.exr"));  // the temporary file was renamed
    Image back = read_image(path("a.exr"));
    ASSERT_EQ(back.width, 17);
    ASSERT_EQ(back.height, 9);
    for (size_t i = 0; i < image.pixels.size(); ++i) EXPECT_EQ(back.pixels[i], image.pixels[i]) << i;
}

// A half-float, single-channel (Y) EXR whose data window does not start at the origin.
TEST_F(ImageIo, ExrHalfGrayWithOffsetDataWindow) {
    const int w = 5, h = 3;
    const Imath::Box2i display(Imath::V2i(0, 0), Imath::V2i(19, 19));
    const Imath::Box2i data(Imath::V2i(7, 11), Imath::V2i(7 + w - 1, 11 + h - 1));
    std::vector<half> values(w * h);
    for (int i = 0; i < w * h; ++i) values[i] = half(0.25f * i);  // exactly representable
    {
        Imf::Header header(display, data);
        header.channels().insert("Y", Imf::Channel(Imf::HALF));
        Imf::OutputFile file(path("y.exr").c_str(), header);
        Imf::FrameBuffer fb;
        fb.insert("Y", Imf::Slice::Make(Imf::HALF, values.data(), data, sizeof(half), sizeof(half) * w));
        file.setFrameBuffer(fb);
        file.writePixels(h);
    }
    const Image image = read_image(path("y.exr"));
    ASSERT_EQ(image.width, w);
    ASSERT_EQ(image.height, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) EXPECT_EQ(image.at(x, y), Color3(0.25f * (y * w + x))) << x << "," << y;
}

TEST_F(ImageIo, PngRoundTripWithinOneStep) {
    Image image(16, 8);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x) image.at(x, y) = Color3(x / 15.f, y / 7.f, (x * y) / 105.f);
    write_image(path("a.png"), image);
    EXPECT_TRUE(only_file_is("a.png"));
    Image back = read_image(path("a.png"));
    ASSERT_EQ(back.width, 16);
    ASSERT_EQ(back.height, 8);
    // The error bound is one 8-bit step in the sRGB encoding, measured back in linear space.
    for (size_t i = 0; i < image.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const float v = image.pixels[i][c];
            const float enc = v <= 0.0031308f ? v * 12.92f : 1.055f * std::pow(v, 1.f / 2.4f) - 0.055f;
            const float lo = srgb_to_linear(std::max(enc - 1.f / 255.f, 0.f));
            const float hi = srgb_to_linear(std::min(enc + 1.f / 255.f, 1.f));
            EXPECT_GE(back.pixels[i][c], lo) << i << " " << c;
            EXPECT_LE(back.pixels[i][c], hi) << i << " " << c;
        }
}

TEST_F(ImageIo, PngRawSkipsSrgbDecoding) {
    Image image(2, 1);
    image.at(0, 0) = Color3(0.f);
    image.at(1, 0) = Color3(srgb_to_linear(128.f / 255.f));  // encodes to byte 128
    write_png(path("r.png"), image);
    const Image raw = read_image(path("r.png"), /*raw=*/true);
    const Image lin = read_image(path("r.png"));
    EXPECT_NEAR(raw.at(1, 0).g, 128.f / 255.f, 1e-6f);
    EXPECT_NEAR(lin.at(1, 0).g, srgb_to_linear(128.f / 255.f), 1e-6f);
    EXPECT_EQ(raw.at(0, 0), Color3(0.f));
}

TEST_F(ImageIo, PngClampsOutOfRange) {
    Image image(3, 1);
    image.at(0, 0) = Color3(-1.f);
    image.at(1, 0) = Color3(5.f);
    image.at(2, 0) = Color3(std::nanf(""));
    write_png(path("c.png"), image);
    const Image back = read_image(path("c.png"));
    EXPECT_EQ(back.at(0, 0), Color3(0.f));
    EXPECT_EQ(back.at(1, 0), Color3(1.f));
    EXPECT_EQ(back.at(2, 0), Color3(0.f));
}

TEST_F(ImageIo, ReadsJpeg) {
    // A flat mid-grey JPEG (written with stb) decodes to the linear value of its sRGB byte.
    std::vector<unsigned char> bytes(16 * 8 * 3, 128);
    ASSERT_TRUE(stbi_write_jpg(path("g.jpg").c_str(), 16, 8, 3, bytes.data(), 100));
    const Image image = read_image(path("g.jpg"));
    ASSERT_EQ(image.width, 16);
    ASSERT_EQ(image.height, 8);
    for (const Color3& c : image.pixels)
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], srgb_to_linear(128.f / 255.f), 0.01f);
}

TEST_F(ImageIo, ReadsMuseumExr) {
    const std::string file = test::shared_dir() + "/mitsuba-data/common/textures/museum.exr";
    if (!fs::exists(file)) GTEST_SKIP() << "missing test data " << file;
    const Image image = read_image(file);
    EXPECT_GT(image.width, 0);
    EXPECT_GT(image.height, 0);
    EXPECT_EQ(image.pixels.size(), size_t(image.width) * image.height);
    double sum = 0.0;
    for (const Color3& c : image.pixels) {
        ASSERT_TRUE(c.is_finite());
        sum += c.average();
    }
    EXPECT_GT(sum, 0.0);
}

TEST_F(ImageIo, MissingFileNamesThePath) {
    const std::string file = path("nope.exr");
    try {
        read_image(file);
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
    }
}

TEST_F(ImageIo, CorruptFilesAreErrors) {
    {
        std::ofstream(path("bad.png")) << "this is not an image";
        // A valid EXR magic number followed by garbage.
        std::ofstream exr(path("bad.exr"), std::ios::binary);
        exr << "\x76\x2f\x31\x01" << std::string(64, '\x5a');
    }
    EXPECT_THROW(read_image(path("bad.png")), InputError);
    EXPECT_THROW(read_image(path("bad.exr")), InputError);
    // A truncated but otherwise valid EXR.
    write_exr(path("t.exr"), test_pattern(64, 64));
    fs::resize_file(path("t.exr"), fs::file_size(path("t.exr")) / 2);
    EXPECT_THROW(read_image(path("t.exr")), InputError);
}

TEST_F(ImageIo, FailedWriteLeavesNoTemporaryAndNamesPath) {
    const std::string target = path("missing_dir/out.exr");
    try {
        write_exr(target, test_pattern(4, 4));
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(target), std::string::npos) << e.what();
    }
    // Rename onto an existing directory fails after the temp file was written: it must be removed.
    fs::create_directories(path("dir.png"));
    EXPECT_THROW(write_png(path("dir.png"), test_pattern(4, 4)), InputError);
    EXPECT_TRUE(only_file_is("dir.png"));
    EXPECT_THROW(write_image(path("x.tiff"), test_pattern(4, 4)), InputError);
}
