#pragma once
// Helpers for the emitter tests: building emitters from parameters, as the XML loader would.
#include <memory>
#include <string>

#include "volguide/core/image.h"
#include "volguide/core/properties.h"
#include "volguide/render/emitter.h"
#include "volguide/scene/factories.h"

namespace volguide::test {

class EmitterBuilder {
  public:
    explicit EmitterBuilder(const std::string& type)
        : props_("emitter", type, SourceLocation{"test.xml", 1}) {}
    EmitterBuilder& set(const std::string& name, Properties::Value value,
                        const std::string& category = "param") {
        props_.set(name, category, std::move(value), SourceLocation{"test.xml", ++line_});
        return *this;
    }
    // Creates the emitter and checks that every parameter was consumed, as the loader does.
    std::shared_ptr<Emitter> build() const {
        auto emitter = std::dynamic_pointer_cast<Emitter>(create_emitter(props_));
        props_.check_all_used();
        return emitter;
    }
    const Properties& props() const { return props_; }

  private:
    Properties props_;
    int line_ = 1;
};

inline Interaction reference_point(const Point3f& p) {
    Interaction it;
    it.p = p;
    it.t = 0.f;
    return it;
}

// The record an integrator builds when a ray leaves the scene in direction d.
inline SurfaceInteraction escaped_ray(const Vec3f& d) {
    SurfaceInteraction si;
    si.wi = -d;
    return si;
}

}  // namespace volguide::test

#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include "volguide/core/image.h"
#include "volguide/render/image_io.h"

namespace volguide::test {

inline std::filesystem::path emitter_scratch_dir() {
    return std::filesystem::temp_directory_path() / ("volguide_emitter_" + std::to_string(::getpid()));
}

// Writes `image` as an EXR into a per-process scratch folder (removed at exit) and returns its path.
inline std::string write_temp_exr(const std::string& name, const Image& image) {
    const auto dir = emitter_scratch_dir();
    if (!std::filesystem::exists(dir)) {
        std::filesystem::create_directories(dir);
        std::atexit([] {
            std::error_code ec;
            std::filesystem::remove_all(emitter_scratch_dir(), ec);
        });
    }
    const std::string path = (dir / name).string();
    write_exr(path, image);
    return path;
}

// Direction of Mitsuba's latitude-longitude parameterisation (emitter frame).
inline Vec3f envmap_direction(float u, float v) {
    const float theta = v * Pi, phi = u * 2.f * Pi;
    return {std::sin(phi) * std::sin(theta), std::cos(theta), -std::cos(phi) * std::sin(theta)};
}

// A strongly non-uniform synthetic sky for envmap tests: bright sun, black band, smooth gradient.
inline Image synthetic_sky() {
    Image image(24, 12);
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 24; ++x) image.at(x, y) = Color3(0.2f + 0.1f * x, 0.05f * y, y < 6 ? 1.f : 0.1f);
    for (int x = 0; x < 24; ++x) image.at(x, 8) = Color3(0.f);
    image.at(5, 3) = Color3(200.f, 150.f, 100.f);
    image.at(6, 3) = Color3(80.f, 60.f, 40.f);
    return image;
}

}  // namespace volguide::test
