// The plugin rules of the Mitsuba 0.x upgrade (legacy_rules.h) for shapes, sensors, emitters, samplers,
// integrators, films and textures; BSDFs are in legacy_rules_bsdf.cpp, media in legacy_rules_media.cpp.
#include <cctype>
#include <cstring>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "volguide/scene/legacy_dom.h"
#include "volguide/scene/legacy_rules.h"
#include "volguide/scene/xml_values.h"

namespace volguide::legacy {

namespace {

bool is_element(pugi::xml_node n) {
    return n.type() == pugi::node_element;
}

std::vector<pugi::xml_node> elements_of(pugi::xml_node node) {
    std::vector<pugi::xml_node> out;
    for (pugi::xml_node c : node.children())
        if (is_element(c)) out.push_back(c);
    return out;
}

// What 0.6's Shape::configure looks at when a shape has no BSDF.
struct ShapeChildren {
    bool bsdf = false, emitter = false, medium_transition = false;
};

ShapeChildren shape_children(const Dom& dom, pugi::xml_node shape) {
    ShapeChildren s;
    for (pugi::xml_node c : shape.children()) {
        if (!is_element(c)) continue;
        const std::string tag = dom.object_tag(c), name = dom.attr(c, "name");
        // An unnamed reference out of this file is taken for the shape's BSDF, what such references
        // nearly always are (0.6 would know; the upgrade of one file cannot).
        const bool unknown_ref = tag.empty() && std::strcmp(c.name(), "ref") == 0 && name.empty();
        s.bsdf = s.bsdf || tag == "bsdf" || unknown_ref;
        s.emitter = s.emitter || tag == "emitter";
        s.medium_transition = s.medium_transition || name == "interior" || name == "exterior";
    }
    return s;
}

// The `medium` an emitter or sensor sits in: 0.6 takes a nested or referenced medium of any name.
void name_medium_child(Dom& dom, pugi::xml_node object) {
    for (pugi::xml_node c : object.children())
        if (is_element(c) && dom.object_tag(c) == "medium") dom.set_attr(c, "name", "medium");
}

// 0.6's `gamma` of an image (bitmap, envmap): -1 sRGB, 1 linear, absent: from the file (sRGB for 8-bit
// images, linear for floating-point ones). Returns whether the image is to be read raw (no sRGB curve);
// the caller removes the parameter.
bool raw_from_gamma(Dom& dom, pugi::xml_node object, pugi::xml_node gamma) {
    const bool hdr = is_float_image(dom.attr(dom.param(object, "filename"), "value"));
    const double g = dom.number(gamma);
    if (g == 1) return !hdr;
    if (g == -1 && !hdr) return false;
    if (g == -1)
        dom.fail(gamma, "gamma -1 on a floating-point image (its values decoded with the sRGB curve) has no "
                        "equivalent: remove it");
    dom.fail(gamma, "gamma {} has no equivalent: Mitsuba 3 reads 8-bit images through the sRGB curve (gamma -1) or "
                    "as they are ('raw', gamma 1); convert the image",
             g);
}

// The string value of an optional 0.6 parameter, removed; `def` when absent.
std::string take_string(Dom& dom, pugi::xml_node object, const char* name, const std::string& def) {
    pugi::xml_node p = dom.param(object, name);
    if (!p) return def;
    std::string v = lowercase(dom.string(p));
    dom.remove(p);
    return v;
}

}  // namespace

// ---- shapes -------------------------------------------------------------------------------------------

// A shape without a BSDF: 0.6 makes an emitter's black (an absorbing light), a medium boundary's
// index-matched (null), and anything else diffuse 0.5, Mitsuba 3's default.
void shape_defaults(Dom& dom, pugi::xml_node shape) {
    const ShapeChildren s = shape_children(dom, shape);
    if (s.bsdf || (!s.emitter && !s.medium_transition)) return;
    pugi::xml_node bsdf = dom.add(shape, "bsdf", shape);
    if (s.emitter) {
        bsdf.append_attribute("type").set_value("diffuse");
        dom.add_value(bsdf, "rgb", "reflectance", "0", shape);
    } else {
        bsdf.append_attribute("type").set_value("null");
    }
}

// The materials an OBJ file names: its `mtllib` and `usemtl` lines.
struct ObjMaterials {
    bool library = false;
    std::set<std::string> used;
};

ObjMaterials obj_materials_of(const Dom& dom, pugi::xml_node shape) {
    ObjMaterials m;
    auto path = dom.resolve(dom.attr(dom.param(shape, "filename"), "value"));
    if (!path) return m;  // the shape reports the missing file at its line
    std::ifstream in(*path);
    std::string line;
    while (std::getline(in, line)) {
        const auto tokens = tokenize_list(trim(line));
        if (tokens.size() >= 1 && tokens[0] == "mtllib") m.library = true;
        if (tokens.size() >= 2 && tokens[0] == "usemtl") m.used.emplace(tokens[1]);
    }
    return m;
}

// 0.6 gives an OBJ the materials of its .mtl file unless loadMaterials is false, and a BSDF named after
// a material to the faces using it. volguide gives an OBJ one BSDF and reads no .mtl: a BSDF named after
// the only material is the shape's, one named after no material is ignored (as 0.6 ignores it), and
// anything that would give faces different materials is an error.
void obj_materials(Dom& dom, pugi::xml_node shape) {
    const ObjMaterials m = obj_materials_of(dom, shape);
    for (pugi::xml_node c : elements_of(shape)) {
        const std::string name = dom.stripped_name(c);
        if (dom.object_tag(c) != "bsdf" || name.empty()) continue;
        if (!m.used.count(name)) {
            dom.warn(c, "the OBJ file uses no material '{}': this BSDF is ignored, as Mitsuba 0.6 ignores it", name);
            dom.remove(c);
        } else if (m.used.size() > 1) {
            dom.fail(c, "a BSDF named after one of the OBJ's materials ('{}') has no equivalent: volguide gives an "
                        "OBJ one BSDF; split the file by material",
                     name);
        }
    }
    pugi::xml_node load = dom.param(shape, "loadMaterials");
    const bool load_materials = !load || dom.boolean(load);
    if (load) dom.remove(load);
    if (load_materials && m.library && !m.used.empty() && !shape_children(dom, shape).bsdf)
        dom.fail(shape, "Mitsuba 0.6 gives this OBJ the materials of its .mtl file (loadMaterials): volguide reads no "
                        ".mtl; give the shape a BSDF, or loadMaterials=false for 0.6's default");
    shape_defaults(dom, shape);
}

// Where every shading normal is the geometric one (analytic shapes, the flat rectangle and cube, meshes
// with faceNormals), strictNormals has nothing to drop: the image is 0.6's. A smooth mesh, or shapes in
// files this one includes, may differ at grazing angles: said once, at the parameter's line.
void strict_normals_effect(Dom& dom, pugi::xml_node root) {
    if (!dom.strict_normals()) return;
    std::vector<pugi::xml_node> stack{root};
    std::string smooth;
    while (!stack.empty() && smooth.empty()) {
        pugi::xml_node n = stack.back();
        stack.pop_back();
        const std::string_view tag = n.name();
        if (tag == "include") smooth = "the files it includes";
        if (tag == "shape") {
            const std::string type = dom.attr(n, "type");
            pugi::xml_node flat = dom.param(n, "face_normals");
            if ((type == "obj" || type == "ply" || type == "serialized") && !(flat && dom.boolean(flat)))
                smooth = "its " + type + " mesh at line " + std::to_string(dom.loc(n).line);
        }
        for (pugi::xml_node c : elements_of(n)) stack.push_back(c);
    }
    if (!smooth.empty())
        warn(*dom.strict_normals(),
             "strictNormals=true is read as false: volguide follows the shading normals where 0.6 drops paths at "
             "vertices whose shading and geometric normals disagree about a direction's side, so the image may differ "
             "at grazing angles of smooth meshes ({}); meshes with faceNormals are unaffected",
             smooth);
}

// ---- sensors and emitters ------------------------------------------------------------------------------

void sensor_rules(Dom& dom, pugi::xml_node sensor) {
    if (pugi::xml_node axis = dom.param(sensor, "fovAxis")) {
        if (!dom.param(sensor, "fov")) {
            dom.warn(axis, "'fovAxis' is ignored without 'fov' (as Mitsuba 0.6 ignores it)");
            dom.remove(axis);
        } else {
            const std::string a = lowercase(dom.string(axis));
            if (a != "x" && a != "y" && a != "diagonal" && a != "smaller" && a != "larger")
                dom.fail(axis, "unknown fovAxis '{}' (x, y, diagonal, smaller or larger)", a);
            dom.set_attr(axis, "name", "fov_axis");
            dom.set_attr(axis, "value", a);
        }
    }
    name_medium_child(dom, sensor);
}

void emitter_medium(Dom& dom, pugi::xml_node emitter) {
    name_medium_child(dom, emitter);
}

void envmap_rules(Dom& dom, pugi::xml_node emitter) {
    if (pugi::xml_node gamma = dom.param(emitter, "gamma")) {
        if (raw_from_gamma(dom, emitter, gamma))
            dom.fail(gamma, "gamma 1 on an 8-bit environment map has no equivalent (Mitsuba 3 decodes it with the "
                            "sRGB curve): convert the image to OpenEXR");
        dom.remove(gamma);
    }
    name_medium_child(dom, emitter);
}

// ---- samplers, integrators, films ---------------------------------------------------------------------

void low_discrepancy_sampler(Dom& dom, pugi::xml_node sampler) {
    pugi::xml_node count = dom.param(sampler, "sample_count");
    dom.warn(sampler, "Mitsuba 0.6's sampler '{}' is read as 'independent' ({} samples per pixel): same "
                      "expectation, different noise",
             dom.attr(sampler, "type"), count ? dom.attr(count, "value") : std::string("4"));
}

void volpath_simple(Dom& dom, pugi::xml_node integrator) {
    dom.warn(integrator, "Mitsuba 0.6's 'volpath_simple' is read as 'volpath': same expectation, different noise "
                         "(volpath weights its light samples by MIS)");
}

// The ldrfilm's tonemap is volguide's (render/sensors/hdrfilm.h, make_ldrfilm), which refuses what a
// method does not use; 0.6 reads such values and ignores them, so they go. Mitsuba 3 has no ldrfilm:
// the upgraded file gets an hdrfilm and loses a tonemap other than the plain sRGB curve, which is said.
void ldrfilm(Dom& dom, pugi::xml_node film) {
    pugi::xml_node method = dom.param(film, "tonemap_method");
    const std::string m = method ? lowercase(dom.string(method)) : "gamma";
    if (m != "gamma" && m != "reinhard") dom.fail(method, "tonemapMethod must be 'gamma' or 'reinhard', got '{}'", m);
    if (method) dom.set_attr(method, "value", m);
    static const std::vector<const char*> unused_by_gamma{"key", "burn"}, unused_by_reinhard{"exposure"};
    for (const char* unused : m == "gamma" ? unused_by_gamma : unused_by_reinhard)
        if (pugi::xml_node p = dom.param(film, unused)) dom.remove(p);
    if (!dom.for_mitsuba3()) return;
    std::string lost;
    for (const char* name : {"tonemap_method", "gamma", "exposure", "key", "burn"}) {
        pugi::xml_node p = dom.param(film, name);
        if (!p) continue;
        const std::string v = dom.attr(p, "value");
        const bool is_default = (std::string_view(name) == "tonemap_method" && v == "gamma") ||
                                (std::string_view(name) == "gamma" && dom.number(p) == -1) ||
                                (std::string_view(name) == "exposure" && dom.number(p) == 0);
        if (!is_default) lost += fmt::format("{}{}={}", lost.empty() ? "" : ", ", name, v);
        dom.remove(p);
    }
    if (!lost.empty())
        dom.warn(film, "Mitsuba 3 has no ldrfilm: the upgraded file has an hdrfilm and loses the PNG tonemap ({}); "
                       "`volguide render` of the 0.6 file applies it",
                 lost);
    dom.set_attr(film, "type", "hdrfilm");
}

// ---- textures -------------------------------------------------------------------------------------------

// 0.6 looks a texture up at uv * (uscale, vscale) + (uoffset, voffset): a scale, then a translation.
// (Mitsuba 3's upgrade writes them the other way round, which also scales the offset.)
void uv_transform(Dom& dom, pugi::xml_node texture) {
    double v[5] = {0, 0, 1, 1, 1};
    const char* names[5] = {"uoffset", "voffset", "uscale", "vscale", "uvscale"};
    pugi::xml_node first;
    for (int i = 0; i < 5; ++i) {
        pugi::xml_node p = dom.param(texture, names[i]);
        if (!p) continue;
        v[i] = dom.number(p);
        dom.note_fixed_parameter(p);
        if (!first) first = p;
    }
    if (!first) return;
    const double su = dom.param(texture, "uscale") ? v[2] : v[4], sv = dom.param(texture, "vscale") ? v[3] : v[4];
    pugi::xml_node t = dom.add(texture, "transform", first, first);
    t.append_attribute("name").set_value("to_uv");
    pugi::xml_node scale = dom.add(t, "scale", first), translate = dom.add(t, "translate", first);
    scale.append_attribute("x").set_value(float_text(su).c_str());
    scale.append_attribute("y").set_value(float_text(sv).c_str());
    translate.append_attribute("x").set_value(float_text(v[0]).c_str());
    translate.append_attribute("y").set_value(float_text(v[1]).c_str());
    for (const char* n : names)
        if (pugi::xml_node p = dom.param(texture, n)) dom.remove(p);
}

void bitmap_rules(Dom& dom, pugi::xml_node texture) {
    const bool has_filter = dom.param(texture, "filterType");
    const std::string filter = take_string(dom, texture, "filterType", "ewa");
    if (filter == "ewa" || filter == "trilinear")
        dom.warn(texture, "Mitsuba 0.6 filters this bitmap with {} over each ray's footprint{}; volguide reads it "
                          "bilinearly (Mitsuba 3's filter): the same texture, sharper where it is minified",
                 filter == "ewa" ? "EWA" : "trilinear MIP mapping", has_filter ? "" : " (its default)");
    else if (filter != "bilinear" && filter != "nearest")
        dom.fail(texture, "unknown filterType '{}' (ewa, trilinear, bilinear or nearest)", filter);
    if (filter == "nearest") dom.add_value(texture, "string", "filter_type", "nearest", texture);

    const std::string both = take_string(dom, texture, "wrapMode", "repeat");
    const std::string u = take_string(dom, texture, "wrapModeU", both), v = take_string(dom, texture, "wrapModeV", both);
    if (u != v) dom.fail(texture, "different wrap modes along u and v ('{}', '{}') have no equivalent", u, v);
    if (u == "zero" || u == "one")
        dom.fail(texture, "wrap mode '{}' (a constant outside [0, 1]) has no equivalent: use repeat, mirror or clamp", u);
    if (u != "repeat" && u != "mirror" && u != "clamp") dom.fail(texture, "unknown wrap mode '{}'", u);
    if (u != "repeat") dom.add_value(texture, "string", "wrap_mode", u, texture);

    if (pugi::xml_node gamma = dom.param(texture, "gamma")) {
        if (raw_from_gamma(dom, texture, gamma)) dom.add_value(texture, "boolean", "raw", "true", gamma);
        dom.remove(gamma);
    }
    // 0.6 keeps texels in half precision (its MIP maps store half floats).
    dom.add_value(texture, "string", "format", "fp16", texture);
    uv_transform(dom, texture);
}

}  // namespace volguide::legacy
