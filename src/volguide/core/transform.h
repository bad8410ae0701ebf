#pragma once
// Affine/projective 4x4 transforms with a cached inverse. Composition follows Mitsuba's XML:
// each operation listed later is applied after (left-multiplied onto) the earlier ones.
#include <array>

#include "volguide/core/vec.h"

namespace volguide {

struct Matrix4 {
    std::array<std::array<double, 4>, 4> m{};  // row-major: m[row][col]
    static Matrix4 identity();
    Matrix4 operator*(const Matrix4& o) const;
    Matrix4 transposed() const;
    // Throws std::domain_error when singular.
    Matrix4 inverse() const;
    bool operator==(const Matrix4&) const = default;
};

class Transform {
public:
    Transform() : m_(Matrix4::identity()), inv_(Matrix4::identity()) {}
    explicit Transform(const Matrix4& m);
    Transform(const Matrix4& m, const Matrix4& inv) : m_(m), inv_(inv) {}

    static Transform translate(const Vec3f& v);
    static Transform scale(const Vec3f& v);
    // Rotation by angle_deg degrees about axis (right-handed, as Mitsuba's <rotate>).
    static Transform rotate(const Vec3f& axis, float angle_deg);
    // Mitsuba's <lookat>: camera space +z looks at target, +y is up, +x is "left".
    static Transform look_at(const Vec3f& origin, const Vec3f& target, const Vec3f& up);
    static Transform perspective(float fov_deg, float near_clip, float far_clip);

    Transform operator*(const Transform& o) const { return {m_ * o.m_, o.inv_ * inv_}; }
    Transform inverse() const { return {inv_, m_}; }
    const Matrix4& matrix() const { return m_; }
    const Matrix4& inverse_matrix() const { return inv_; }
    bool is_identity() const { return m_ == Matrix4::identity(); }

    Point3f apply_point(const Point3f& p) const;  // with homogeneous divide
    Vec3f apply_vector(const Vec3f& v) const;
    Normal3f apply_normal(const Normal3f& n) const;  // inverse transpose; not normalized
    bool operator==(const Transform& o) const { return m_ == o.m_; }

private:
    Matrix4 m_, inv_;
};

}  // namespace volguide
