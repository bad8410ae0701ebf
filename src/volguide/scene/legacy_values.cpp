#include "volguide/scene/legacy_values.h"

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "volguide/scene/cie1931.h"
#include "volguide/scene/xml_values.h"

namespace volguide::legacy {

namespace {

// 0.6 spectra: CIE curves without D65, negatives clipped (an emitter's conversion in Mitsuba 3).
constexpr SpectrumToRgbMode kLegacySpectrum{/*within_emitter=*/true, /*unbounded=*/false};

Rgb to_rgb(const Color3& c) {
    return {c.r, c.g, c.b};
}

// "#rrggbb" → the three bytes / 255; nullopt for anything else.
std::optional<Rgb> html_color(std::string_view text) {
    text = trim(text);
    if (text.size() != 7 || text[0] != '#') return std::nullopt;
    Rgb c{};
    for (int i = 0; i < 3; ++i) {
        unsigned v = 0;
        for (char h : text.substr(size_t(1 + 2 * i), 2)) {
            const int d = std::isdigit(static_cast<unsigned char>(h)) ? h - '0'
                          : std::isxdigit(static_cast<unsigned char>(h))
                              ? std::tolower(static_cast<unsigned char>(h)) - 'a' + 10
                              : -1;
            if (d < 0) return std::nullopt;
            v = v * 16 + unsigned(d);
        }
        c[size_t(i)] = double(float(v) / 255.0f);
    }
    return c;
}

// One or three numbers, or an HTML colour (<rgb>, <srgb>).
Rgb color_value(const Dom& dom, pugi::xml_node value) {
    const std::string text = dom.attr(value, "value");
    if (auto c = html_color(text)) return *c;
    std::vector<double> v;
    for (std::string_view t : tokenize_list(text)) {
        auto x = parse_double(t);
        if (!x) dom.fail(value, "<{}>: could not parse \"{}\" as a finite number", value.name(), t);
        v.push_back(*x);
    }
    if (v.size() == 1) return {v[0], v[0], v[0]};
    if (v.size() == 3) return {v[0], v[1], v[2]};
    dom.fail(value, "<{}> needs one value, three, or an HTML colour #rrggbb (got \"{}\")", value.name(), text);
}

void check_intent(Dom& dom, pugi::xml_node value) {
    if (!value.attribute("intent")) return;
    std::string intent = dom.attr(value, "intent");
    for (char& c : intent) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (intent != "reflectance" && intent != "illuminant")
        dom.fail(value, "<{}>: intent \"{}\" must be \"reflectance\" or \"illuminant\"", value.name(), intent);
    value.remove_attribute("intent");
}

void set_rgb(Dom& dom, pugi::xml_node value, const Rgb& c) {
    dom.note_fixed_parameter(value);
    dom.retag(value, "rgb");
    for (const char* a : {"temperature", "scale", "filename", "value"}) value.remove_attribute(a);
    dom.set_attr(value, "value", rgb_text(c));
}

// The sRGB curve's inverse in single precision, as 0.6 computes it.
double srgb_to_linear_f(double v) {
    const float x = float(v);
    return x <= 0.04045f ? double(x * (1.0f / 12.92f)) : double(std::pow((x + 0.055f) * (1.0f / 1.055f), 2.4f));
}

void convert_srgb(Dom& dom, pugi::xml_node value) {
    Rgb c = color_value(dom, value);
    for (double& x : c) x = srgb_to_linear_f(x);
    set_rgb(dom, value, c);
}

void convert_blackbody(Dom& dom, pugi::xml_node value) {
    std::string t(trim(dom.attr(value, "temperature")));
    if (!t.empty() && std::toupper(static_cast<unsigned char>(t.back())) == 'K') t.pop_back();
    auto kelvin = parse_double(t);
    if (!kelvin || !(*kelvin > 0))
        dom.fail(value, "<blackbody>: the temperature must be a positive number of kelvins (got \"{}\")",
                 dom.attr(value, "temperature"));
    double scale = 1;
    if (value.attribute("scale")) {
        auto s = parse_double(dom.attr(value, "scale"));
        if (!s) dom.fail(value, "<blackbody>: could not parse scale \"{}\" as a finite number", dom.attr(value, "scale"));
        scale = *s;
    }
    Rgb c = blackbody_rgb(*kelvin);
    for (double& x : c) x *= scale;
    set_rgb(dom, value, c);
}

bool within_emitter(pugi::xml_node value) {
    for (pugi::xml_node n = value.parent(); n; n = n.parent())
        if (std::strcmp(n.name(), "emitter") == 0) return true;
    return false;
}

// A <spectrum> of 0.6: one value (kept, but an emitter's), three (RGB), pairs or a file (converted).
void convert_spectrum(Dom& dom, pugi::xml_node value) {
    if (value.attribute("type"))
        dom.fail(value, "Mitsuba 0.6's <spectrum> is a value: it takes no 'type' (spectrum plugins are Mitsuba 3's)");
    const bool has_value = value.attribute("value"), has_file = value.attribute("filename");
    if (has_value == has_file) dom.fail(value, "<spectrum> needs exactly one of 'value' or 'filename'");
    const std::string text = dom.attr(value, "value");
    const auto tokens = tokenize_list(text);
    const bool pairs = has_file || text.find(':') != std::string::npos;
    if (value.attribute("intent") && pairs)
        dom.fail(value, "<spectrum>: 'intent' is only read with a single value (as in Mitsuba 0.6)");
    check_intent(dom, value);
    // A constant is grey in 0.6's RGB build. Mitsuba 3 reads it so, except inside an emitter, where its
    // newest releases take the equal-energy colour: there it is written as the grey it is.
    if (!pairs && tokens.size() == 1) {
        if (within_emitter(value)) set_rgb(dom, value, color_value(dom, value));
        return;
    }
    if (!pairs && tokens.size() == 3) return set_rgb(dom, value, color_value(dom, value));
    if (!pairs)
        dom.fail(value, "<spectrum>: Mitsuba 0.6's RGB build reads one value, three (RGB) or wavelength:value "
                        "pairs (got {} values)", tokens.size());
    std::vector<double> wl, val;
    std::string error;
    if (has_file) {
        auto path = dom.resolve(dom.attr(value, "filename"));
        if (!path) dom.fail(value, "file \"{}\" not found", dom.attr(value, "filename"));
        error = read_spd_file(*path, wl, val);
    } else {
        error = parse_spectrum_pairs(text, wl, val);
    }
    if (error.empty()) error = check_spectrum_wavelengths(wl);
    if (!error.empty()) dom.fail(value, "{}", error);
    set_rgb(dom, value, to_rgb(spectrum_to_linear_srgb(wl, val, kLegacySpectrum).rgb));
}

}  // namespace

Rgb blackbody_rgb(double kelvin) {
    // Planck's law in W m^-2 sr^-1 nm^-1 with 0.6's constants, sampled every nanometre of the CIE range.
    const double c = 299792458, k = 1.3806488e-23, h = 6.62606957e-34;
    std::vector<double> wl, val;
    for (double nm = kCieMin; nm <= kCieMax; nm += 1) {
        const double lambda = nm * 1e-9;
        wl.push_back(nm);
        val.push_back((2 * h * c * c) * std::pow(lambda, -5.0) / ((std::exp((h / k) * c / (lambda * kelvin)) - 1.0) * 1e9));
    }
    return to_rgb(spectrum_to_linear_srgb(wl, val, kLegacySpectrum).rgb);
}

void convert_value(Dom& dom, pugi::xml_node value) {
    const std::string_view tag = value.name();
    if (tag == "rgb") {
        check_intent(dom, value);
        if (html_color(dom.attr(value, "value"))) set_rgb(dom, value, color_value(dom, value));
    } else if (tag == "srgb") {
        convert_srgb(dom, value);
    } else if (tag == "blackbody") {
        convert_blackbody(dom, value);
    } else if (tag == "spectrum") {
        convert_spectrum(dom, value);
    } else if (tag == "animation") {
        dom.fail(value, "<animation> (a transform over time) has no equivalent: volguide renders one instant; "
                        "give a single <transform>");
    }
}

}  // namespace volguide::legacy
