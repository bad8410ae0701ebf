// The parameter rules of the Mitsuba 0.x upgrade (legacy_rules.h): one 0.6 parameter each.
#include <cctype>
#include <string>

#include "volguide/scene/legacy_dom.h"
#include "volguide/scene/legacy_rules.h"

namespace volguide::legacy {

namespace {

std::string name_of(const Dom& dom, pugi::xml_node param) {
    return dom.attr(param, "name");
}

}  // namespace

// 0.6's strictNormals=true drops paths at vertices whose shading and geometric normals put a direction
// on different sides; volguide follows the shading normals (0.6's default). Whether that changes the
// image depends on the shapes: strict_normals_effect decides once the file is read.
void strict_normals(Dom& dom, pugi::xml_node, pugi::xml_node param) {
    if (dom.boolean(param)) dom.set_strict_normals(param);
    dom.remove(param);
}

void sampling_weight(Dom& dom, pugi::xml_node, pugi::xml_node param) {
    const double w = dom.number(param);
    if (w != 1)
        dom.warn(param, "samplingWeight {} has no effect: volguide picks the emitter of a light sample uniformly, as "
                        "Mitsuba 3 does (0.6 in proportion to samplingWeight), with the same expectation",
                 w);
    dom.remove(param);
}

void note_if_true(Dom& dom, pugi::xml_node, pugi::xml_node param) {
    const std::string name = name_of(dom, param);
    if (dom.boolean(param)) {
        const char* why = name == "banner"      ? "volguide draws no banner into its images"
                          : name == "attachLog" ? "volguide attaches no render log to its images"
                          : name == "sendData"  ? "volguide renders on one machine (network rendering only)"
                                                : "volguide keeps no MIP map cache";  // cache
        dom.warn(param, "'{}' has no effect: {}", name, why);
    }
    dom.remove(param);
}

void brute_force(Dom& dom, pugi::xml_node, pugi::xml_node param) {
    if (dom.boolean(param))
        dom.fail(param, "bruteForce=true (only light paths that hit the aperture by chance) has no equivalent: "
                        "volguide's ptracer connects every vertex to the sensor; remove it");
    dom.remove(param);
}

// 0.6's diffuse reads `reflectance`, or `diffuseReflectance` when there is none (Mitsuba 3's upgrade
// renames the latter).
void diffuse_reflectance(Dom& dom, pugi::xml_node object, pugi::xml_node param) {
    if (dom.param(object, "reflectance")) {
        dom.warn(param, "'diffuseReflectance' is ignored: Mitsuba 0.6's diffuse reads 'reflectance' when both are given");
        dom.remove(param);
    } else {
        dom.set_attr(param, "name", "reflectance");
    }
}

void distribution(Dom& dom, pugi::xml_node, pugi::xml_node param) {
    const std::string d = lowercase(dom.string(param));
    if (d == "phong")
        dom.fail(param, "the Phong microfacet distribution has no equivalent: use 'beckmann' (its alpha = "
                        "sqrt(2 / (exponent + 2)) for a Phong exponent) or 'ggx'");
    if (d != "beckmann" && d != "ggx")
        dom.fail(param, "unknown microfacet distribution '{}' (Mitsuba 0.6's are beckmann, ggx and phong)", d);
    dom.set_attr(param, "value", d);
}

void texture_coordinates(Dom& dom, pugi::xml_node, pugi::xml_node param) {
    if (dom.string(param) != "uv")
        dom.fail(param, "only 'uv' texture coordinates exist (as in Mitsuba 0.6), got '{}'", dom.string(param));
    dom.remove(param);
}

void hdr_file_format(Dom& dom, pugi::xml_node, pugi::xml_node param) {
    const std::string f = lowercase(dom.string(param));
    if (f != "openexr" && f != "rgbe" && f != "pfm")
        dom.fail(param, "unknown fileFormat '{}' (Mitsuba 0.6's hdrfilm writes openexr, rgbe or pfm)", f);
    if (f != "openexr")
        dom.warn(param, "fileFormat '{}' is not written: volguide writes the format -o names (OpenEXR, or a PNG)", f);
    dom.remove(param);
}

void hdr_pixel_format(Dom& dom, pugi::xml_node, pugi::xml_node param) {
    const std::string f = lowercase(dom.string(param));
    if (f == "rgb" || f == "rgba") {
        dom.set_attr(param, "name", "pixel_format");
        dom.set_attr(param, "value", f);
        return;
    }
    dom.warn(param, "pixelFormat '{}' is not written: volguide writes RGB", dom.string(param));
    dom.remove(param);
}

void ldr_file_format(Dom& dom, pugi::xml_node, pugi::xml_node param) {
    const std::string f = lowercase(dom.string(param));
    if (f != "png" && f != "jpeg" && f != "jpg")
        dom.fail(param, "unknown fileFormat '{}' (Mitsuba 0.6's ldrfilm writes png or jpeg)", f);
    if (f != "png")
        dom.warn(param, "fileFormat '{}' is not written: volguide writes the format -o names (a PNG with this "
                        "film's tonemap, or OpenEXR)",
                 f);
    dom.remove(param);
}

void ldr_pixel_format(Dom& dom, pugi::xml_node, pugi::xml_node param) {
    const std::string f = lowercase(dom.string(param));
    if (f != "rgb" && f != "rgba" && f != "luminance" && f != "luminancealpha")
        dom.fail(param, "unknown pixelFormat '{}' (Mitsuba 0.6's ldrfilm writes luminance, luminanceAlpha, rgb or "
                        "rgba)",
                 dom.string(param));
    if (f != "rgb") dom.warn(param, "pixelFormat '{}' is not written: volguide writes RGB PNGs", dom.string(param));
    dom.remove(param);
}

void tracking_method(Dom& dom, pugi::xml_node, pugi::xml_node param) {
    const std::string m = lowercase(dom.string(param));
    if (m == "simpson")
        dom.warn(param, "method 'simpson' (sampling by Simpson quadrature, slightly biased) is read as volguide's "
                        "unbiased tracking: the image is the one the quadrature approximates");
    else if (m != "woodcock")
        dom.fail(param, "unknown method '{}' (Mitsuba 0.6's heterogeneous medium tracks by woodcock or simpson)", m);
    dom.remove(param);
}

void monochromatic(Dom& dom, pugi::xml_node, pugi::xml_node param) {
    if (dom.boolean(param))
        dom.fail(param, "monochromatic=true (every channel given one channel's coefficients) has no equivalent: "
                        "give grey sigmaA and sigmaS");
    dom.remove(param);
}

void obj_shape_index(Dom& dom, pugi::xml_node, pugi::xml_node param) {
    if (dom.number(param) != -1)
        dom.fail(param, "'shapeIndex' (one object of an OBJ file) has no equivalent: volguide loads the whole "
                        "file; split it");
    dom.remove(param);
}

}  // namespace volguide::legacy
