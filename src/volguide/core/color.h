#pragma once
// Linear RGB radiometric quantity (Mitsuba 3's `rgb` variants). Used for radiance, throughput,
// albedo and chromatic medium coefficients alike.
#include <algorithm>
#include <cmath>
#include <ostream>

namespace volguide {

struct Color3 {
    float r = 0.f, g = 0.f, b = 0.f;
    constexpr Color3() = default;
    constexpr Color3(float r_, float g_, float b_) : r(r_), g(g_), b(b_) {}
    constexpr explicit Color3(float s) : r(s), g(s), b(s) {}
    constexpr float operator[](int i) const { return i == 0 ? r : (i == 1 ? g : b); }
    constexpr float& operator[](int i) { return i == 0 ? r : (i == 1 ? g : b); }
    constexpr Color3 operator+(const Color3& o) const { return {r + o.r, g + o.g, b + o.b}; }
    constexpr Color3 operator-(const Color3& o) const { return {r - o.r, g - o.g, b - o.b}; }
    constexpr Color3 operator*(const Color3& o) const { return {r * o.r, g * o.g, b * o.b}; }
    constexpr Color3 operator/(const Color3& o) const { return {r / o.r, g / o.g, b / o.b}; }
    constexpr Color3 operator*(float s) const { return {r * s, g * s, b * s}; }
    constexpr Color3 operator/(float s) const { return {r / s, g / s, b / s}; }
    constexpr Color3& operator+=(const Color3& o) { r += o.r; g += o.g; b += o.b; return *this; }
    constexpr Color3& operator*=(const Color3& o) { r *= o.r; g *= o.g; b *= o.b; return *this; }
    constexpr Color3& operator*=(float s) { r *= s; g *= s; b *= s; return *this; }
    constexpr bool operator==(const Color3&) const = default;

    constexpr bool is_black() const { return r == 0.f && g == 0.f && b == 0.f; }
    float max_value() const { return std::max(r, std::max(g, b)); }
    float min_value() const { return std::min(r, std::min(g, b)); }
    constexpr float average() const { return (r + g + b) * (1.f / 3.f); }
    // Rec. 709 / sRGB luminance, as Mitsuba's luminance().
    constexpr float luminance() const { return 0.212671f * r + 0.715160f * g + 0.072169f * b; }
    bool is_finite() const { return std::isfinite(r) && std::isfinite(g) && std::isfinite(b); }
    bool has_negative() const { return r < 0.f || g < 0.f || b < 0.f; }
};

constexpr Color3 operator*(float s, const Color3& c) { return c * s; }
inline Color3 exp(const Color3& c) { return {std::exp(c.r), std::exp(c.g), std::exp(c.b)}; }
inline Color3 sqrt(const Color3& c) { return {std::sqrt(c.r), std::sqrt(c.g), std::sqrt(c.b)}; }
inline Color3 clamp(const Color3& c, float lo, float hi) {
    return {std::clamp(c.r, lo, hi), std::clamp(c.g, lo, hi), std::clamp(c.b, lo, hi)};
}
inline std::ostream& operator<<(std::ostream& os, const Color3& c) {
    return os << "(" << c.r << ", " << c.g << ", " << c.b << ")";
}

}  // namespace volguide
