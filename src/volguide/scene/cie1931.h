#pragma once
// CIE 1931 colour matching and the spectrum → linear sRGB conversion that Mitsuba 3's RGB variants
// apply to <spectrum> values given as wavelength:value pairs.
#include <span>

#include "volguide/core/color.h"

namespace volguide {

// The tables cover 360..830 nm at 5 nm (95 samples), as Mitsuba's MI_CIE_MIN/MAX/SAMPLES.
inline constexpr double kCieMin = 360.0;
inline constexpr double kCieMax = 830.0;
inline constexpr int kCieSamples = 95;
// Mitsuba's MI_CIE_Y_NORMALIZATION: scales the curves so that a unit spectrum has luminance 1.
inline constexpr double kCieYNormalization = 1.0 / 106.7502593994140625;
// Mitsuba's MI_CIE_D65_NORMALIZATION: scales the D65 table so that its luminance is 1.
inline constexpr double kCieD65Normalization = 1.0 / 98.99741751876255;

struct Xyz {
    double x = 0, y = 0, z = 0;
};

// Colour matching functions, linearly interpolated in the 5 nm table; zero outside [360, 830].
Xyz cie1931_xyz(double wavelength_nm);
// CIE D65 relative power, interpolated and multiplied by kCieD65Normalization; zero outside.
double cie_d65(double wavelength_nm);
// XYZ → linear Rec. 709 / sRGB primaries with Mitsuba's matrix.
Color3 xyz_to_linear_srgb(const Xyz& xyz);

// How a piecewise-linear spectrum is turned into RGB (Mitsuba 3 xml.cpp, RGB mode):
//  - values are multiplied by kCieYNormalization;
//  - reflectance-like values (not an emitter's own parameter, or an unbounded eta/k/IOR) are
//    integrated against CMF × D65 so that a flat 1 maps to (1, 1, 1); an emitter's radiance is
//    integrated against the CMFs alone;
//  - bounded values (neither emitter nor eta/k/IOR) are clipped to [0, 1], others only at 0.
struct SpectrumToRgbMode {
    bool within_emitter = false;
    bool unbounded = false;  // parameter named eta, k, int_ior or ext_ior
};

struct SpectrumToRgbResult {
    Color3 rgb;
    bool clamped = false;  // out of gamut (Mitsuba warns)
};

// wavelengths must be strictly increasing and of the same size as values (size >= 2).
SpectrumToRgbResult spectrum_to_linear_srgb(std::span<const double> wavelengths,
                                            std::span<const double> values, SpectrumToRgbMode mode);

}  // namespace volguide
