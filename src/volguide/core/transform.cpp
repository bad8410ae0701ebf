#include "volguide/core/transform.h"

#include <cmath>
#include <stdexcept>

namespace volguide {

Matrix4 Matrix4::identity() {
    Matrix4 r;
    for (int i = 0; i < 4; ++i) r.m[i][i] = 1.0;
    return r;
}

Matrix4 Matrix4::operator*(const Matrix4& o) const {
    Matrix4 r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            double s = 0;
            for (int k = 0; k < 4; ++k) s += m[i][k] * o.m[k][j];
            r.m[i][j] = s;
        }
    return r;
}

Matrix4 Matrix4::transposed() const {
    Matrix4 r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) r.m[i][j] = m[j][i];
    return r;
}

Matrix4 Matrix4::inverse() const {
    // Gauss-Jordan elimination with partial pivoting, in double.
    Matrix4 a = *this, inv = identity();
    for (int c = 0; c < 4; ++c) {
        int pivot = c;
        for (int r = c + 1; r < 4; ++r)
            if (std::abs(a.m[r][c]) > std::abs(a.m[pivot][c])) pivot = r;
        if (std::abs(a.m[pivot][c]) < 1e-300) throw std::domain_error("singular transform matrix");
        std::swap(a.m[c], a.m[pivot]);
        std::swap(inv.m[c], inv.m[pivot]);
        double d = 1.0 / a.m[c][c];
        for (int j = 0; j < 4; ++j) {
            a.m[c][j] *= d;
            inv.m[c][j] *= d;
        }
        for (int r = 0; r < 4; ++r) {
            if (r == c) continue;
            double f = a.m[r][c];
            if (f == 0.0) continue;
            for (int j = 0; j < 4; ++j) {
                a.m[r][j] -= f * a.m[c][j];
                inv.m[r][j] -= f * inv.m[c][j];
            }
        }
    }
    return inv;
}

Transform::Transform(const Matrix4& m) : m_(m), inv_(m.inverse()) {}

Transform Transform::translate(const Vec3f& v) {
    Matrix4 m = Matrix4::identity(), inv = Matrix4::identity();
    for (int i = 0; i < 3; ++i) {
        m.m[i][3] = v[i];
        inv.m[i][3] = -v[i];
    }
    return {m, inv};
}

Transform Transform::scale(const Vec3f& v) {
    Matrix4 m = Matrix4::identity(), inv = Matrix4::identity();
    for (int i = 0; i < 3; ++i) {
        m.m[i][i] = v[i];
        inv.m[i][i] = 1.0 / v[i];
    }
    return {m, inv};
}

Transform Transform::rotate(const Vec3f& axis_in, float angle_deg) {
    Vec3d a = normalize(Vec3d(axis_in));
    double th = angle_deg * 3.14159265358979323846 / 180.0;
    double s = std::sin(th), c = std::cos(th), t = 1.0 - c;
    Matrix4 m = Matrix4::identity();
    m.m[0][0] = a.x * a.x * t + c;
    m.m[0][1] = a.x * a.y * t - a.z * s;
    m.m[0][2] = a.x * a.z * t + a.y * s;
    m.m[1][0] = a.x * a.y * t + a.z * s;
    m.m[1][1] = a.y * a.y * t + c;
    m.m[1][2] = a.y * a.z * t - a.x * s;
    m.m[2][0] = a.x * a.z * t - a.y * s;
    m.m[2][1] = a.y * a.z * t + a.x * s;
    m.m[2][2] = a.z * a.z * t + c;
    return {m, m.transposed()};
}

Transform Transform::look_at(const Vec3f& origin, const Vec3f& target, const Vec3f& up) {
    Vec3d o(origin), dir = normalize(Vec3d(target) - Vec3d(origin));
    Vec3d left = cross(Vec3d(up), dir);
    if (norm(left) < 1e-12) throw std::domain_error("lookat: 'up' is parallel to the view direction");
    left = normalize(left);
    Vec3d new_up = cross(dir, left);
    Matrix4 m = Matrix4::identity();
    for (int i = 0; i < 3; ++i) {
        m.m[i][0] = left[i];
        m.m[i][1] = new_up[i];
        m.m[i][2] = dir[i];
        m.m[i][3] = o[i];
    }
    return Transform(m);
}

Transform Transform::perspective(float fov_deg, float near_clip, float far_clip) {
    double recip = 1.0 / (double(far_clip) - near_clip);
    double cot = 1.0 / std::tan(double(fov_deg) * 3.14159265358979323846 / 360.0);
    Matrix4 m;
    m.m[0][0] = cot;
    m.m[1][1] = cot;
    m.m[2][2] = far_clip * recip;
    m.m[2][3] = -double(near_clip) * far_clip * recip;
    m.m[3][2] = 1.0;
    return Transform(m);
}

Point3f Transform::apply_point(const Point3f& p) const {
    const auto& a = m_.m;
    double x = a[0][0] * p.x + a[0][1] * p.y + a[0][2] * p.z + a[0][3];
    double y = a[1][0] * p.x + a[1][1] * p.y + a[1][2] * p.z + a[1][3];
    double z = a[2][0] * p.x + a[2][1] * p.y + a[2][2] * p.z + a[2][3];
    double w = a[3][0] * p.x + a[3][1] * p.y + a[3][2] * p.z + a[3][3];
    return w == 1.0 ? Point3f(float(x), float(y), float(z)) : Point3f(float(x / w), float(y / w), float(z / w));
}

Vec3f Transform::apply_vector(const Vec3f& v) const {
    const auto& a = m_.m;
    return {float(a[0][0] * v.x + a[0][1] * v.y + a[0][2] * v.z),
            float(a[1][0] * v.x + a[1][1] * v.y + a[1][2] * v.z),
            float(a[2][0] * v.x + a[2][1] * v.y + a[2][2] * v.z)};
}

Normal3f Transform::apply_normal(const Normal3f& n) const {
    const auto& a = inv_.m;  // transpose of the inverse
    return {float(a[0][0] * n.x + a[1][0] * n.y + a[2][0] * n.z),
            float(a[0][1] * n.x + a[1][1] * n.y + a[2][1] * n.z),
            float(a[0][2] * n.x + a[1][2] * n.y + a[2][2] * n.z)};
}

}  // namespace volguide
