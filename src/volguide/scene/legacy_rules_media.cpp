// The media and volume rules of the Mitsuba 0.x upgrade (legacy_rules.h).
#include <algorithm>
#include <array>
#include <string>

#include "volguide/media/grid_data.h"
#include "volguide/scene/legacy_dom.h"
#include "volguide/scene/legacy_rules.h"

namespace volguide::legacy {

namespace {

// The coefficients 0.6's homogeneous medium reads, checked as 0.6 checks them.
struct Coefficients {
    pugi::xml_node a, s, t, albedo, g;
};

Coefficients coefficients(Dom& dom, pugi::xml_node medium) {
    Coefficients c{dom.param(medium, "sigmaA"), dom.param(medium, "sigmaS"), dom.param(medium, "sigmaT"),
                   dom.param(medium, "albedo"), dom.param(medium, "g")};
    if ((c.a || c.s) && (c.t || c.albedo))
        dom.fail(c.a ? c.a : c.s, "give sigmaA and sigmaS, or sigmaT and albedo, not both (as Mitsuba 0.6 requires)");
    if (!c.a && !c.s && !c.t && !c.albedo)
        dom.fail(medium, "Mitsuba 0.6's homogeneous medium without coefficients is its 'skin1' preset, which is not "
                         "available: give sigmaA and sigmaS");
    if (bool(c.a) != bool(c.s))
        dom.fail(c.a ? c.a : c.s, "give both sigmaA and sigmaS: Mitsuba 0.6 takes the other from its 'skin1' preset, "
                                  "which is not available");
    if (bool(c.t) != bool(c.albedo))
        dom.fail(c.t ? c.t : c.albedo, "give both sigmaT and albedo: Mitsuba 0.6 takes the other from its 'skin1' "
                                       "preset, which is not available");
    return c;
}

// sigma_t and albedo from 0.6's coefficients, in single precision as 0.6 computes them: sigmaS is
// reduced to (1 - g) sigmaS when the medium has a `g` of its own (0.6 stores reduced coefficients).
std::array<Rgb, 2> extinction_and_albedo(Dom& dom, const Coefficients& c) {
    Rgb g{0, 0, 0};
    if (c.g) g = dom.color(c.g);
    for (double x : g)
        if (!(x > -1 && x < 1)) dom.fail(c.g, "the medium's 'g' must lie in (-1, 1) (got {})", x);
    Rgb t{}, albedo{};
    for (size_t i = 0; i < 3; ++i) {
        float sa = 0, ss = 0;
        if (c.a) {
            sa = float(dom.color(c.a)[i]);
            ss = float(dom.color(c.s)[i]);
        } else {
            const float st = float(dom.color(c.t)[i]);
            ss = float(dom.color(c.albedo)[i]) * st;
            sa = st - ss;
        }
        ss *= 1.0f - float(g[i]);
        const float st = sa + ss;
        t[i] = st;
        albedo[i] = st != 0 ? double(ss / st) : 0.0;
    }
    return {t, albedo};
}

bool boundary_is_zero(const GridData& g) {
    for (int z = 0; z < g.nz; ++z)
        for (int y = 0; y < g.ny; ++y)
            for (int x = 0; x < g.nx; ++x) {
                const bool face = x == 0 || y == 0 || z == 0 || x == g.nx - 1 || y == g.ny - 1 || z == g.nz - 1;
                for (int ch = 0; face && ch < g.channels; ++ch)
                    if (g.at(x, y, z, ch) != 0) return false;
            }
    return true;
}

// The grid file's resolution and box: 0.6's `min`/`max` replace the file's box when both are given.
GridData grid_header(Dom& dom, pugi::xml_node volume, pugi::xml_node file) {
    auto path = dom.resolve(dom.attr(file, "value"));
    if (!path) dom.fail(file, "file \"{}\" not found", dom.attr(file, "value"));
    GridData h;
    try {
        h = read_vol_header(*path);
        if (!boundary_is_zero(read_vol_file(*path)))
            dom.warn(volume, "the grid's outermost voxels are not all zero: Mitsuba 0.6's medium ends at the box "
                             "through their centres, volguide's (as Mitsuba 3's) extends half a voxel beyond with "
                             "their values");
    } catch (const InputError& e) {
        dom.fail(file, "{}", e.message());
    }
    pugi::xml_node lo = dom.param(volume, "min"), hi = dom.param(volume, "max");
    if (lo && hi) {
        const auto a = dom.vec3(lo), b = dom.vec3(hi);
        h.bbox = BBox3f(Point3f(float(a[0]), float(a[1]), float(a[2])), Point3f(float(b[0]), float(b[1]), float(b[2])));
    } else if (lo || hi) {
        dom.warn(lo ? lo : hi, "'{}' is ignored without '{}' (as Mitsuba 0.6 ignores it)", lo ? "min" : "max",
                 lo ? "max" : "min");
    }
    for (pugi::xml_node p : {lo, hi})
        if (p) dom.remove(p);
    return h;
}

}  // namespace

void homogeneous_rules(Dom& dom, pugi::xml_node medium) {
    const Coefficients c = coefficients(dom, medium);
    const bool reduced = c.g && dom.color(c.g) != Rgb{0, 0, 0};
    if (c.t && !reduced) {  // already Mitsuba 3's parameters
        dom.set_attr(c.t, "name", "sigma_t");
        if (c.g) dom.remove(c.g);
        return;
    }
    const auto [t, albedo] = extinction_and_albedo(dom, c);
    pugi::xml_node first = c.a ? c.a : c.t;
    for (pugi::xml_node p : {c.a, c.s, c.t, c.albedo, c.g})
        if (p) dom.note_fixed_parameter(p);
    dom.add_value(medium, "rgb", "sigma_t", rgb_text(t), first, first);
    dom.add_value(medium, "rgb", "albedo", rgb_text(albedo), first, first);
    for (pugi::xml_node p : {c.a, c.s, c.t, c.albedo, c.g})
        if (p) dom.remove(p);
}

// 0.6 requires both volumes; Mitsuba 3 would default them (sigma_t 1, albedo 0.75).
void heterogeneous_rules(Dom& dom, pugi::xml_node medium) {
    for (const char* name : {"sigma_t", "albedo"}) {
        const char* name06 = name == std::string_view("sigma_t") ? "density" : "albedo";
        pugi::xml_node p = dom.param(medium, name);
        if (!p) dom.fail(medium, "Mitsuba 0.6's heterogeneous medium needs a '{}' volume", name06);
        const std::string tag = dom.object_tag(p);
        if (tag != "volume" && !(tag.empty() && std::string_view(p.name()) == "ref"))
            dom.fail(p, "Mitsuba 0.6 reads '{}' as a nested volume (e.g. <volume type=\"constvolume\">), not as <{}>",
                     name06, p.name());
    }
}

// 0.6 places the n voxel values of an axis at the corners of n - 1 equal cells spanning the box
// (voxel i at min + i (max - min) / (n - 1)); Mitsuba 3 at the centres of n cells spanning its unit
// cube. The cube is mapped onto the box grown by half a voxel on each side, before 0.6's toWorld:
// the same lookups inside the box.
void gridvolume_rules(Dom& dom, pugi::xml_node volume) {
    pugi::xml_node file = dom.param(volume, "filename");
    if (!file) dom.fail(volume, "Mitsuba 0.6's gridvolume needs 'filename'");
    const GridData h = grid_header(dom, volume, file);
    const int res[3] = {h.nx, h.ny, h.nz};
    double scale[3], offset[3];
    for (int i = 0; i < 3; ++i) {
        if (res[i] < 2)
            dom.fail(file, "Mitsuba 0.6 places a grid's values at the corners of its cells: it needs two or more "
                           "along each axis (this one has {}x{}x{})",
                     h.nx, h.ny, h.nz);
        const double step = (double(h.bbox.hi[i]) - double(h.bbox.lo[i])) / (res[i] - 1);
        scale[i] = res[i] * step;
        offset[i] = double(h.bbox.lo[i]) - 0.5 * step;
    }
    pugi::xml_node t = dom.param(volume, "toWorld");
    if (!t) {
        t = dom.add(volume, "transform", volume);
        t.append_attribute("name").set_value("toWorld");
    }
    pugi::xml_node first_op;
    for (pugi::xml_node c : t.children())
        if (c.type() == pugi::node_element) {
            first_op = c;
            break;
        }
    pugi::xml_node s = dom.add(t, "scale", t, first_op), tr = dom.add(t, "translate", t, first_op);
    const char* axes[3] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i) {
        s.append_attribute(axes[i]).set_value(float_text(scale[i]).c_str());
        tr.append_attribute(axes[i]).set_value(float_text(offset[i]).c_str());
    }
    dom.set_attr(t, "name", "to_world");
}

}  // namespace volguide::legacy
