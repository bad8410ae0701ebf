#pragma once
// Small fixed-size vectors. Points, vectors and normals share one type; names say which is meant.
#include <cmath>
#include <ostream>

#include "volguide/core/math.h"

namespace volguide {

template <typename T>
struct Vec2 {
    T x{}, y{};
    constexpr Vec2() = default;
    constexpr Vec2(T x_, T y_) : x(x_), y(y_) {}
    constexpr T operator[](int i) const { return i == 0 ? x : y; }
    constexpr T& operator[](int i) { return i == 0 ? x : y; }
    constexpr Vec2 operator+(Vec2 o) const { return {x + o.x, y + o.y}; }
    constexpr Vec2 operator-(Vec2 o) const { return {x - o.x, y - o.y}; }
    constexpr Vec2 operator*(T s) const { return {x * s, y * s}; }
    constexpr Vec2 operator*(Vec2 o) const { return {x * o.x, y * o.y}; }
    constexpr Vec2 operator/(T s) const { return {x / s, y / s}; }
    constexpr bool operator==(const Vec2&) const = default;
};

template <typename T>
struct Vec3 {
    T x{}, y{}, z{};
    constexpr Vec3() = default;
    constexpr Vec3(T x_, T y_, T z_) : x(x_), y(y_), z(z_) {}
    constexpr explicit Vec3(T s) : x(s), y(s), z(s) {}
    template <typename U>
    constexpr explicit Vec3(const Vec3<U>& o) : x(T(o.x)), y(T(o.y)), z(T(o.z)) {}
    constexpr T operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr T& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr Vec3 operator-() const { return {-x, -y, -z}; }
    constexpr Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
    constexpr Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
    constexpr Vec3 operator*(const Vec3& o) const { return {x * o.x, y * o.y, z * o.z}; }
    constexpr Vec3 operator/(const Vec3& o) const { return {x / o.x, y / o.y, z / o.z}; }
    constexpr Vec3 operator*(T s) const { return {x * s, y * s, z * s}; }
    constexpr Vec3 operator/(T s) const { return {x / s, y / s, z / s}; }
    constexpr Vec3& operator+=(const Vec3& o) { x += o.x; y += o.y; z += o.z; return *this; }
    constexpr Vec3& operator-=(const Vec3& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
    constexpr Vec3& operator*=(T s) { x *= s; y *= s; z *= s; return *this; }
    constexpr bool operator==(const Vec3&) const = default;
};

template <typename T>
constexpr Vec3<T> operator*(T s, const Vec3<T>& v) { return v * s; }
template <typename T>
constexpr Vec2<T> operator*(T s, const Vec2<T>& v) { return v * s; }

using Vec2f = Vec2<float>;
using Vec2i = Vec2<int>;
using Vec3f = Vec3<float>;
using Vec3d = Vec3<double>;
using Point2f = Vec2f;
using Point3f = Vec3f;
using Normal3f = Vec3f;

template <typename T>
constexpr T dot(const Vec3<T>& a, const Vec3<T>& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <typename T>
constexpr T absdot(const Vec3<T>& a, const Vec3<T>& b) { return std::abs(dot(a, b)); }
template <typename T>
constexpr Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <typename T>
inline T squared_norm(const Vec3<T>& v) { return dot(v, v); }
template <typename T>
inline T norm(const Vec3<T>& v) { return std::sqrt(dot(v, v)); }
template <typename T>
inline Vec3<T> normalize(const Vec3<T>& v) { return v / norm(v); }
template <typename T>
inline Vec3<T> abs(const Vec3<T>& v) { return {std::abs(v.x), std::abs(v.y), std::abs(v.z)}; }
template <typename T>
inline Vec3<T> min(const Vec3<T>& a, const Vec3<T>& b) {
    return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
template <typename T>
inline Vec3<T> max(const Vec3<T>& a, const Vec3<T>& b) {
    return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}
template <typename T>
inline T max_component(const Vec3<T>& v) { return std::max(v.x, std::max(v.y, v.z)); }
template <typename T>
inline T min_component(const Vec3<T>& v) { return std::min(v.x, std::min(v.y, v.z)); }
template <typename T>
inline bool all_finite(const Vec3<T>& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
// Reflect w about n (both pointing away from the surface).
inline Vec3f reflect(const Vec3f& w, const Vec3f& n) { return 2.f * dot(w, n) * n - w; }
// Direction from spherical coordinates about +z.
inline Vec3f spherical_direction(float sin_theta, float cos_theta, float phi) {
    return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}

template <typename T>
std::ostream& operator<<(std::ostream& os, const Vec3<T>& v) {
    return os << "[" << v.x << ", " << v.y << ", " << v.z << "]";
}
template <typename T>
std::ostream& operator<<(std::ostream& os, const Vec2<T>& v) {
    return os << "[" << v.x << ", " << v.y << "]";
}

}  // namespace volguide
