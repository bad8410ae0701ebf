#pragma once
// Scalar constants and helpers shared by every module.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace volguide {

inline constexpr float Pi = 3.14159265358979323846f;
inline constexpr double PiDouble = 3.14159265358979323846;  // for double-precision fits and normalisations
inline constexpr float InvPi = 0.31830988618379067154f;
inline constexpr float InvTwoPi = 0.15915494309189533577f;
inline constexpr float InvFourPi = 0.07957747154594766788f;
inline constexpr float Infinity = std::numeric_limits<float>::infinity();
// Largest float strictly below 1: samples must stay in [0, 1).
inline constexpr float OneMinusEpsilon = 0x1.fffffep-1f;
// Relative offset used when spawning rays from surfaces (scaled by the magnitude of the position).
inline constexpr float RayEpsilon = 1e-4f;
inline constexpr float ShadowEpsilon = 1e-3f;

template <typename T>
constexpr T sqr(T x) { return x * x; }
template <typename T>
constexpr T lerp(float t, T a, T b) { return (1.f - t) * a + t * b; }
inline float safe_sqrt(float x) { return std::sqrt(std::max(x, 0.f)); }
inline float safe_acos(float x) { return std::acos(std::clamp(x, -1.f, 1.f)); }
inline float safe_asin(float x) { return std::asin(std::clamp(x, -1.f, 1.f)); }
inline float deg_to_rad(float d) { return d * (Pi / 180.f); }
inline float rad_to_deg(float r) { return r * (180.f / Pi); }
inline float mis_power_heuristic(float pdf_a, float pdf_b) {
    // Power heuristic with beta = 2; robust when pdf_a is infinite (delta) or both are zero. Squares
    // in double: a finite pdf above ~1.8e19 (a grazing area-light sample) overflows a float square
    // and inf / inf would be NaN.
    if (std::isinf(pdf_a)) return 1.f;
    if (std::isinf(pdf_b)) return 0.f;
    const double a2 = double(pdf_a) * pdf_a, b2 = double(pdf_b) * pdf_b;
    return a2 + b2 > 0.0 ? float(a2 / (a2 + b2)) : 0.f;
}

}  // namespace volguide
