#pragma once
// A minimal Shape for emitter tests: the unit square [0,1]^2 at z = 0 with normal +z (or -z when
// flipped), uniformly sampled by area. It relies on Shape's default solid-angle conversion.
#include "volguide/geometry/shape.h"

namespace volguide::test {

class MockSquare final : public Shape {
public:
    explicit MockSquare(bool flipped = false) : n_(0.f, 0.f, flipped ? -1.f : 1.f) {}
    BBox3f bbox() const override { return BBox3f({0.f, 0.f, 0.f}, {1.f, 1.f, 0.f}); }
    float surface_area() const override { return 1.f; }
    SurfaceInteraction compute_surface_interaction(const Ray& ray, float t, uint32_t, Vec2f) const override {
        return hit(ray.o + ray.d * t, ray.d);
    }
    PositionSample sample_position(Point2f u) const override {
        PositionSample ps;
        ps.p = Point3f(u.x, u.y, 0.f);
        ps.n = n_;
        ps.uv = u;
        ps.pdf = 1.f;
        return ps;
    }
    // Where the ray from `o` along unit `d` meets the square, as an integrator would record it.
    bool intersect_square(const Point3f& o, const Vec3f& d, float& t) const {
        if (d.z == 0.f) return false;
        t = -o.z / d.z;
        const Point3f p = o + d * t;
        return t > 0.f && p.x >= 0.f && p.x <= 1.f && p.y >= 0.f && p.y <= 1.f;
    }
    SurfaceInteraction hit(const Point3f& p, const Vec3f& d) const {
        SurfaceInteraction si;
        si.p = p;
        si.n = n_;
        si.t = 1.f;
        si.uv = Vec2f(p.x, p.y);
        si.sh_frame = Frame(n_);
        si.wi = si.to_local(-d);
        si.shape = this;
        return si;
    }
    void attach(std::shared_ptr<Emitter> e) {
        emitter_ = std::move(e);
        emitter_->set_shape(this);
    }

private:
    Normal3f n_;
};

}  // namespace volguide::test
