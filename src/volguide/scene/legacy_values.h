#pragma once
// Internal to the upgrade of Mitsuba 0.x files: Mitsuba 0.6's value elements as Mitsuba 3 writes the
// same values. volguide reads 0.6 files as 0.6's default build (RGB, SPECTRUM_SAMPLES = 3) reads them.
#include <pugixml.hpp>

#include "volguide/scene/legacy_dom.h"

namespace volguide::legacy {

// Rewrites one value element in place:
//  - <rgb value="#rrggbb"> (HTML colours, components / 255, linear) and the `intent` attribute of
//    <rgb> and <spectrum> (no effect in the RGB build: removed once checked);
//  - <srgb> → <rgb> decoded with the sRGB curve;
//  - <blackbody temperature="T[K]" scale="s"> → <rgb> of Planck's radiance (W m⁻² sr⁻¹ nm⁻¹);
//  - <spectrum> of wavelength:value pairs or a .spd file → <rgb>: 0.6 integrates every spectrum
//    against the CIE curves without D65, reflectances included, and clips negatives only (Mitsuba 3
//    does so for an emitter's spectra); three values without wavelengths are the RGB build's RGB; a
//    constant inside an emitter → <rgb> (the grey 0.6 means, which Mitsuba 3's newest releases would
//    read as the equal-energy colour);
//  - <animation> → an error: volguide renders one instant.
void convert_value(Dom& dom, pugi::xml_node value);

// The linear sRGB colour of a black body at `kelvin` (Mitsuba 0.6's BlackBodySpectrum, RGB build).
Rgb blackbody_rgb(double kelvin);

}  // namespace volguide::legacy
