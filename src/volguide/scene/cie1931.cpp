// CIE 1931 2° standard observer and CIE D65 (both the standard CIE tabulations at 5 nm,
// 360..830 nm) and the spectrum → RGB reduction used for <spectrum> wavelength:value lists.
#include "volguide/scene/cie1931.h"

#include <algorithm>
#include <array>

namespace volguide {
namespace {

using Table = std::array<double, kCieSamples>;

// x̄(λ); each line holds five consecutive 5 nm samples starting at the wavelength in the comment.
constexpr Table kCieX = {
    0.0001299,      0.0002321,      0.0004149,      0.0007416,      0.001368,        // 360
    0.002236,       0.004243,       0.00765,        0.01431,        0.02319,         // 385
    0.04351,        0.07763,        0.13438,        0.21477,        0.2839,          // 410
    0.3285,         0.34828,        0.34806,        0.3362,         0.3187,          // 435
    0.2908,         0.2511,         0.19536,        0.1421,         0.09564,         // 460
    0.05795001,     0.03201,        0.0147,         0.0049,         0.0024,          // 485
    0.0093,         0.0291,         0.06327,        0.1096,         0.1655,          // 510
    0.2257499,      0.2904,         0.3597,         0.4334499,      0.5120501,       // 535
    0.5945,         0.6784,         0.7621,         0.8425,         0.9163,          // 560
    0.9786,         1.0263,         1.0567,         1.0622,         1.0456,          // 585
    1.0026,         0.9384,         0.8544499,      0.7514,         0.6424,          // 610
    0.5419,         0.4479,         0.3608,         0.2835,         0.2187,          // 635
    0.1649,         0.1212,         0.0874,         0.0636,         0.04677,         // 660
    0.0329,         0.0227,         0.01584,        0.01135916,     0.008110916,     // 685
    0.005790346,    0.004109457,    0.002899327,    0.00204919,     0.001439971,     // 710
    0.0009999493,   0.0006900786,   0.0004760213,   0.0003323011,   0.0002348261,    // 735
    0.0001661505,   0.000117413,    0.00008307527,  0.00005870652,  0.00004150994,   // 760
    0.00002935326,  0.00002067383,  0.00001455977,  0.00001025398,  0.000007221456,  // 785
    0.000005085868, 0.000003581652, 0.000002522525, 0.000001776509, 0.000001251141,  // 810
};

// ȳ(λ)
constexpr Table kCieY = {
    0.000003917,  0.000006965,  0.00001239,    0.00002202,    0.000039,       // 360
    0.000064,     0.00012,      0.000217,      0.000396,      0.00064,        // 385
    0.00121,      0.00218,      0.004,         0.0073,        0.0116,         // 410
    0.01684,      0.023,        0.0298,        0.038,         0.048,          // 435
    0.06,         0.0739,       0.09098,       0.1126,        0.13902,        // 460
    0.1693,       0.20802,      0.2586,        0.323,         0.4073,         // 485
    0.503,        0.6082,       0.71,          0.7932,        0.862,          // 510
    0.9148501,    0.954,        0.9803,        0.9949501,     1.0,            // 535
    0.995,        0.9786,       0.952,         0.9154,        0.87,           // 560
    0.8163,       0.757,        0.6949,        0.631,         0.5668,         // 585
    0.503,        0.4412,       0.381,         0.321,         0.265,          // 610
    0.217,        0.175,        0.1382,        0.107,         0.0816,         // 635
    0.061,        0.04458,      0.032,         0.0232,        0.017,          // 660
    0.01192,      0.00821,      0.005723,      0.004102,      0.002929,       // 685
    0.002091,     0.001484,     0.001047,      0.00074,       0.00052,        // 710
    0.0003611,    0.0002492,    0.0001719,     0.00012,       0.0000848,      // 735
    0.00006,      0.0000424,    0.00003,       0.0000212,     0.00001499,     // 760
    0.0000106,    0.0000074657, 0.0000052578,  0.0000037029,  0.0000026078,   // 785
    0.0000018366, 0.0000012934, 0.00000091093, 0.00000064153, 0.00000045181,  // 810
};

// z̄(λ); zero from 655 nm on.
constexpr Table kCieZ = {
    0.0006061,  0.001086,    0.001946,   0.003486,    0.006450001,    // 360
    0.01054999, 0.02005001,  0.03621,    0.06785001,  0.1102,         // 385
    0.2074,     0.3713,      0.6456,     1.0390501,   1.3856,         // 410
    1.62296,    1.74706,     1.7826,     1.77211,     1.7441,         // 435
    1.6692,     1.5281,      1.28764,    1.0419,      0.8129501,      // 460
    0.6162,     0.46518,     0.3533,     0.272,       0.2123,         // 485
    0.1582,     0.1117,      0.07824999, 0.05725001,  0.04216,        // 510
    0.02984,    0.0203,      0.0134,     0.008749999, 0.005749999,    // 535
    0.0039,     0.002749999, 0.0021,     0.0018,      0.001650001,    // 560
    0.0014,     0.0011,      0.001,      0.0008,      0.0006,         // 585
    0.00034,    0.00024,     0.00019,    0.0001,      0.00004999999,  // 610
    0.00003,    0.00002,     0.00001,    0.0,         0.0,            // 635
    // 660..830: 35 zeros (value-initialised)
};

// CIE standard illuminant D65, relative spectral power (100 at 560 nm).
constexpr Table kD65 = {
    46.6383, 49.3637, 52.0891, 51.0323, 49.9755,  // 360
    52.3118, 54.6482, 68.7015, 82.7549, 87.1204,  // 385
    91.486,  92.4589, 93.4318, 90.057,  86.6823,  // 410
    95.7736, 104.865, 110.936, 117.008, 117.41,   // 435
    117.812, 116.336, 114.861, 115.392, 115.923,  // 460
    112.367, 108.811, 109.082, 109.354, 108.578,  // 485
    107.802, 106.296, 104.79,  106.239, 107.689,  // 510
    106.047, 104.405, 104.225, 104.046, 102.023,  // 535
    100.0,   98.1671, 96.3342, 96.0611, 95.788,   // 560
    92.2368, 88.6856, 89.3459, 90.0062, 89.8026,  // 585
    89.5991, 88.6489, 87.6987, 85.4936, 83.2886,  // 610
    83.4939, 83.6992, 81.863,  80.0268, 80.1207,  // 635
    80.2146, 81.2462, 82.2778, 80.281,  78.2842,  // 660
    74.0027, 69.7213, 70.6652, 71.6091, 72.979,   // 685
    74.349,  67.9765, 61.604,  65.7448, 69.8856,  // 710
    72.4863, 75.087,  69.3398, 63.5927, 55.0054,  // 735
    46.4182, 56.6118, 66.8054, 65.0941, 63.3828,  // 760
    63.8434, 64.304,  61.8779, 59.4519, 55.7054,  // 785
    51.959,  54.6998, 57.4406, 58.8765, 60.3125,  // 810
};

// Table lookup with the same index arithmetic as Mitsuba (linear between 5 nm samples).
struct TablePosition {
    int i0;
    double w1;
};
inline bool table_position(double wavelength, TablePosition& pos) {
    if (!(wavelength >= kCieMin && wavelength <= kCieMax)) return false;
    double t = (wavelength - kCieMin) * ((kCieSamples - 1) / (kCieMax - kCieMin));
    pos.i0 = std::clamp(int(t), 0, kCieSamples - 2);
    pos.w1 = t - pos.i0;
    return true;
}
inline double lerp_table(const Table& table, const TablePosition& p) {
    return (1.0 - p.w1) * table[p.i0] + p.w1 * table[p.i0 + 1];
}

}  // namespace

Xyz cie1931_xyz(double wavelength_nm) {
    TablePosition p;
    if (!table_position(wavelength_nm, p)) return {};
    return {lerp_table(kCieX, p), lerp_table(kCieY, p), lerp_table(kCieZ, p)};
}

double cie_d65(double wavelength_nm) {
    TablePosition p;
    if (!table_position(wavelength_nm, p)) return 0.0;
    return lerp_table(kD65, p) * kCieD65Normalization;
}

Color3 xyz_to_linear_srgb(const Xyz& c) {
    return {float(3.240479 * c.x - 1.537150 * c.y - 0.498535 * c.z),
            float(-0.969256 * c.x + 1.875991 * c.y + 0.041556 * c.z),
            float(0.055648 * c.x - 0.204043 * c.y + 1.057311 * c.z)};
}

SpectrumToRgbResult spectrum_to_linear_srgb(std::span<const double> wavelengths,
                                            std::span<const double> values, SpectrumToRgbMode mode) {
    const bool bounded = !(mode.within_emitter || mode.unbounded);
    const bool with_d65 = !(mode.within_emitter && !mode.unbounded);

    // Mitsuba integrates with a fixed Riemann sum of 1000 points over [360, 830]; points outside
    // the listed wavelengths contribute nothing (the spectrum is zero there).
    constexpr int steps = 1000;
    Xyz acc;
    size_t index = 0;
    for (int i = 0; i < steps; ++i) {
        double w = kCieMin + (i / double(steps - 1)) * (kCieMax - kCieMin);
        if (w < wavelengths.front() || w > wavelengths.back()) continue;
        // Interval [index, index+1] containing w (the last one for w == back()).
        while (index + 2 < wavelengths.size() && wavelengths[index + 1] <= w) ++index;
        double w0 = wavelengths[index], w1 = wavelengths[index + 1];
        double v0 = values[index] * kCieYNormalization, v1 = values[index + 1] * kCieYNormalization;
        double v = ((w - w1) * v0 + (w0 - w) * v1) / (w0 - w1);
        double weight = v * (with_d65 ? cie_d65(w) : 1.0);
        Xyz cmf = cie1931_xyz(w);
        acc.x += cmf.x * weight;
        acc.y += cmf.y * weight;
        acc.z += cmf.z * weight;
    }
    const double dw = (kCieMax - kCieMin) / steps;
    Color3 rgb = xyz_to_linear_srgb({acc.x * dw, acc.y * dw, acc.z * dw});

    SpectrumToRgbResult result{rgb, false};
    if (bounded && (rgb.min_value() < 0.f || rgb.max_value() > 1.f)) {
        result.rgb = clamp(rgb, 0.f, 1.f);
        result.clamped = true;
    } else if (!bounded && rgb.min_value() < 0.f) {
        result.rgb = {std::max(rgb.r, 0.f), std::max(rgb.g, 0.f), std::max(rgb.b, 0.f)};
        result.clamped = true;
    }
    return result;
}

}  // namespace volguide
