// The BSDF rules of the Mitsuba 0.x upgrade (legacy_rules.h).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <initializer_list>
#include <string>
#include <vector>

#include "volguide/core/image.h"
#include "volguide/render/bsdfs/ior.h"
#include "volguide/render/image_io.h"
#include "volguide/scene/legacy_dom.h"
#include "volguide/scene/legacy_rules.h"
#include "volguide/scene/xml_values.h"

namespace volguide::legacy {

namespace {

// The largest texel of a bitmap texture whose file holds floating-point values; 0 otherwise (8-bit
// images never exceed 1).
double bitmap_maximum(Dom& dom, pugi::xml_node texture) {
    if (std::string_view(texture.name()) != "texture" || dom.attr(texture, "type") != "bitmap") return 0;
    const std::string name = dom.attr(dom.param(texture, "filename"), "value");
    if (!is_float_image(name)) return 0;
    auto path = dom.resolve(name);
    if (!path) return 0;  // the bitmap reports the missing file at its line
    Image image;
    try {
        image = read_image(*path);
    } catch (const InputError&) {
        return 0;  // the bitmap reports a file it cannot read at its line
    }
    double m = 0;
    for (const Color3& c : image.pixels) m = std::max({m, double(c.r), double(c.g), double(c.b)});
    return m;
}

// 0.6's BSDFs scale a reflectance-like parameter whose largest component exceeds 1 by 0.99 / max (with
// a warning), unless ensureEnergyConservation is false; Mitsuba 3 does not. Constant values are
// scaled here; a texture that would be is an error (Mitsuba 3 has no scaled texture).
void conserve_energy(Dom& dom, pugi::xml_node bsdf, std::initializer_list<const char*> params) {
    pugi::xml_node flag = dom.param(bsdf, "ensureEnergyConservation");
    const bool on = !flag || dom.boolean(flag);
    if (flag) dom.remove(flag);
    if (!on) return;
    for (const char* name : params) {
        pugi::xml_node p = dom.param(bsdf, name);
        if (!p) continue;
        if (!dom.is_constant_color(p)) {
            const double m = bitmap_maximum(dom, p);
            if (m > 1)
                dom.fail(p, "Mitsuba 0.6 scales this texture by {} (its maximum {} exceeds 1: ensureEnergyConservation); "
                            "no equivalent: scale the image, or set ensureEnergyConservation to false",
                         0.99 / m, m);
            continue;
        }
        Rgb c = dom.color(p);
        const double m = std::max({c[0], c[1], c[2]});
        if (!(m > 1)) continue;
        const double scale = double(0.99f * (1.0f / float(m)));
        for (double& x : c) x = double(float(x) * float(scale));
        dom.warn(p, "'{}' exceeds 1 ({}): scaled by {} to conserve energy, as Mitsuba 0.6 does "
                    "(ensureEnergyConservation=false keeps it)",
                 name, m, scale);
        dom.note_fixed_parameter(p);
        dom.retag(p, "rgb");
        dom.set_attr(p, "value", rgb_text(c));
    }
}

// 0.6's `extEta` of a conductor: a number or a dielectric's name (default air).
double exterior_eta(Dom& dom, pugi::xml_node bsdf) {
    pugi::xml_node p = dom.param(bsdf, "extEta");
    if (!p) return double(*named_ior("air"));
    double eta = 0;
    if (std::string_view(p.name()) == "string") {
        auto v = named_ior(dom.string(p));
        if (!v) dom.fail(p, "unknown index of refraction '{}' for 'extEta'", dom.string(p));
        eta = double(*v);
    } else {
        eta = dom.number(p);
    }
    if (!(eta > 0) || !std::isfinite(eta)) dom.fail(p, "'extEta' must be a finite index of refraction > 0");
    dom.remove(p);
    return eta;
}

// eta and k of a conductor as 0.6 sets them: the material's (default Cu), each replaced by an explicit
// value when given, both divided by the exterior's index.
void conductor_ior(Dom& dom, pugi::xml_node bsdf) {
    pugi::xml_node material = dom.param(bsdf, "material"), eta = dom.param(bsdf, "eta"), k = dom.param(bsdf, "k");
    const std::string name = material ? dom.string(material) : "Cu";
    const std::string lowered = lowercase(name);
    auto preset = conductor_preset(lowered == "none" ? "none" : name);
    if (!preset && (material || !eta || !k))
        dom.fail(material ? material : bsdf, "unknown conductor material '{}' (Mitsuba's data/ior names: Cu, Au, Ag, Al, "
                                             "Cr, W, a-C, ...)",
                 name);
    const double ext = exterior_eta(dom, bsdf);
    Rgb e = eta ? dom.color(eta) : Rgb{preset->eta.r, preset->eta.g, preset->eta.b};
    Rgb kk = k ? dom.color(k) : Rgb{preset->k.r, preset->k.g, preset->k.b};
    for (Rgb* c : {&e, &kk})
        for (double& x : *c) x = double(float(x) / float(ext));
    pugi::xml_node at = material ? material : eta ? eta : k ? k : bsdf;
    pugi::xml_node before = material ? material : eta ? eta : k ? k : pugi::xml_node();
    for (pugi::xml_node p : {eta, k})
        if (p) dom.note_fixed_parameter(p);
    dom.add_value(bsdf, "rgb", "eta", rgb_text(e), at, before);
    dom.add_value(bsdf, "rgb", "k", rgb_text(kk), at, before);
    for (pugi::xml_node p : {material, eta, k})
        if (p) dom.remove(p);
}

}  // namespace

void diffuse_rules(Dom& dom, pugi::xml_node bsdf) {
    conserve_energy(dom, bsdf, {"reflectance"});
}

void dielectric_rules(Dom& dom, pugi::xml_node bsdf) {
    conserve_energy(dom, bsdf, {"specular_reflectance", "specular_transmittance"});
}

void conductor_rules(Dom& dom, pugi::xml_node bsdf) {
    conductor_ior(dom, bsdf);
    conserve_energy(dom, bsdf, {"specular_reflectance"});
}

void plastic_rules(Dom& dom, pugi::xml_node bsdf) {
    conserve_energy(dom, bsdf, {"specular_reflectance", "diffuse_reflectance"});
}

void mask_rules(Dom& dom, pugi::xml_node bsdf) {
    conserve_energy(dom, bsdf, {"opacity"});
}

// 0.6's blendbsdf weight defaults to 0.5; Mitsuba 3's is required.
void blendbsdf_rules(Dom& dom, pugi::xml_node bsdf) {
    if (!dom.param(bsdf, "weight")) dom.add_value(bsdf, "float", "weight", "0.5", bsdf);
}

// A mixture w0 f0 + w1 f1 with w0 + w1 = 1 is Mitsuba 3's blend of weight w1; other mixtures have no
// equivalent.
void mixturebsdf_rules(Dom& dom, pugi::xml_node bsdf) {
    pugi::xml_node weights = dom.param(bsdf, "weights");
    if (!weights) dom.fail(bsdf, "Mitsuba 0.6's mixturebsdf needs 'weights'");
    std::vector<double> w;
    const std::string text = dom.string(weights);  // the tokens view it
    for (std::string_view t : tokenize_list(text)) {
        auto x = parse_double(t);
        if (!x) dom.fail(weights, "could not parse weight \"{}\" as a finite number", t);
        w.push_back(*x);
    }
    int nested = 0;
    for (pugi::xml_node c : bsdf.children())
        if (c.type() == pugi::node_element && dom.object_tag(c) == "bsdf") ++nested;
    if (w.size() != 2 || nested != 2 || std::abs(w[0] + w[1] - 1) > 1e-6 || w[0] < 0 || w[1] < 0)
        dom.fail(bsdf, "a mixturebsdf is read as Mitsuba 3's 'blendbsdf' only with two BSDFs whose weights sum to 1 "
                       "(got {} BSDFs, weights \"{}\"): no equivalent otherwise",
                 nested, dom.string(weights));
    dom.note_fixed_parameter(weights);
    dom.add_value(bsdf, "float", "weight", float_text(w[1]), weights, weights);
    dom.remove(weights);
}

}  // namespace volguide::legacy
