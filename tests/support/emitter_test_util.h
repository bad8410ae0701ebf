#pragma once
// Helpers for the emitter tests: building emitters from parameters, as the XML loader would.
#include <memory>
#include <string>

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
