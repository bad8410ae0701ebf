#include "volguide/scene/xml_properties.h"

#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "volguide/core/frame.h"
#include "volguide/core/log.h"
#include "volguide/scene/cie1931.h"
#include "volguide/scene/xml_values.h"

namespace volguide {

namespace {

double number(const XmlElement& el, std::string_view text, std::string_view what,
              bool allow_infinity = false) {
    auto v = parse_double(text, allow_infinity);
    if (!v) el.fail_here("<{}>: could not parse {} \"{}\" as a finite number", el.tag(), what, text);
    return *v;
}

std::vector<double> number_list(const XmlElement& el, std::string_view text, std::string_view what) {
    std::vector<double> out;
    for (std::string_view t : tokenize_list(text)) out.push_back(number(el, t, what));
    return out;
}

Vec3f vec3_of(const std::vector<double>& v) {
    return {float(v[0]), float(v[1]), float(v[2])};
}

// "x y z" in a named attribute (lookat origin/target/up).
Vec3f named_vec3(const XmlElement& el, std::string_view attr) {
    std::vector<double> v = number_list(el, el.get(attr), attr);
    if (v.size() != 3)
        el.fail_here("<{}>: '{}' needs exactly 3 values (got \"{}\")", el.tag(), attr, el.get(attr));
    return vec3_of(v);
}

// Either value="a" / value="a b c" or separate x/y/z attributes (absent ones = def).
Vec3f xyz_vector(const XmlElement& el, double def, bool require_all) {
    if (el.has("value")) {
        if (el.has("x") || el.has("y") || el.has("z"))
            el.fail_here("<{}>: 'value' cannot be combined with 'x'/'y'/'z'", el.tag());
        std::vector<double> v = number_list(el, el.get("value"), "value");
        if (v.size() == 1) return Vec3f(float(v[0]));
        if (v.size() == 3) return vec3_of(v);
        el.fail_here("<{}>: 'value' needs 1 or 3 numbers (got {})", el.tag(), v.size());
    }
    Vec3f out = Vec3f(static_cast<float>(def));
    const char* names[3] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i) {
        if (el.has(names[i]))
            out[i] = float(number(el, el.get(names[i]), names[i]));
        else if (require_all)
            el.fail_here("<{}> needs 'value' or all of 'x', 'y', 'z' (missing '{}')", el.tag(), names[i]);
    }
    return out;
}

bool has_nan(const Matrix4& m) {
    for (const auto& row : m.m)
        for (double x : row)
            if (!std::isfinite(x)) return true;
    return false;
}

Transform transform_op(const XmlElement& op) {
    std::string_view tag = op.tag();
    if (tag == "translate") {
        op.expect({"value", "x", "y", "z"}, {});
        return Transform::translate(xyz_vector(op, 0.0, false));
    }
    if (tag == "scale") {
        op.expect({"value", "x", "y", "z"}, {});
        return Transform::scale(xyz_vector(op, 1.0, false));
    }
    if (tag == "rotate") {
        op.expect({"value", "x", "y", "z", "angle"}, {"angle"});
        Vec3f axis = xyz_vector(op, 0.0, false);
        if (axis == Vec3f(0.f)) op.fail_here("<rotate>: the rotation axis is zero");
        return Transform::rotate(axis, float(number(op, op.get("angle"), "angle")));
    }
    if (tag == "lookat") {
        op.expect({"origin", "target", "up"}, {"origin", "target"});
        Vec3f origin = named_vec3(op, "origin"), target = named_vec3(op, "target");
        Vec3f up = op.has("up") ? named_vec3(op, "up") : Vec3f(0.f);
        if (target == origin) op.fail_here("<lookat>: origin and target coincide");
        if (up == Vec3f(0.f)) {  // as Mitsuba: any up vector perpendicular to the view direction
            Vec3f s, t;
            coordinate_system(normalize(target - origin), s, t);
            up = s;
        }
        try {
            Transform tr = Transform::look_at(origin, target, up);
            if (has_nan(tr.matrix())) op.fail_here("<lookat>: invalid look-at transformation");
            return tr;
        } catch (const std::domain_error& e) {
            op.fail_here("<lookat>: {}", e.what());
        }
    }
    if (tag == "matrix") {
        op.expect({"value"}, {"value"});
        std::vector<double> v = number_list(op, op.get("value"), "matrix entry");
        Matrix4 m = Matrix4::identity();
        if (v.size() == 16) {
            for (int i = 0; i < 4; ++i)
                for (int j = 0; j < 4; ++j) m.m[i][j] = v[size_t(i * 4 + j)];
        } else if (v.size() == 9) {  // 3x3 block, last row/column from the identity (as Mitsuba)
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) m.m[i][j] = v[size_t(i * 3 + j)];
        } else {
            op.fail_here("<matrix> needs 16 (4x4) or 9 (3x3) values, row-major (got {})", v.size());
        }
        try {
            return Transform(m);
        } catch (const std::domain_error&) {
            op.fail_here("<matrix> is singular (not invertible)");
        }
    }
    op.fail_here("<{}> is not a transform operation", tag);
}

Transform parse_transform(const XmlElement& el, const PropertyContext& ctx) {
    Transform t;
    for (pugi::xml_node child : el.node().children()) {
        if (child.type() == pugi::node_pcdata || child.type() == pugi::node_cdata)
            el.fail_here("<transform> may not contain text");
        if (child.type() != pugi::node_element) continue;
        XmlElement op(el.file(), child, *ctx.params);
        if (!is_transform_op_tag(op.tag()))
            op.fail_here(
                "<{}> cannot appear inside <transform> (only translate, rotate, scale, matrix, lookat)",
                op.tag());
        if (op.node().first_child()) op.fail_here("<{}> cannot have child elements", op.tag());
        t = transform_op(op) * t;  // later operations apply after earlier ones
    }
    return t;
}

bool is_unbounded_spectrum_name(std::string_view name) {
    return name == "eta" || name == "k" || name == "int_ior" || name == "ext_ior";
}

Color3 spectrum_value(const XmlElement& el, const std::string& name, const PropertyContext& ctx) {
    const bool has_value = !el.get("value").empty(), has_file = !el.get("filename").empty();
    if (has_value == has_file) el.fail_here("<spectrum> needs exactly one of 'value' or 'filename'");
    std::vector<double> wl, val;
    std::string error;
    if (has_value) {
        auto tokens = tokenize_list(el.get("value"));
        if (tokens.size() == 1 && tokens[0].find(':') == std::string_view::npos)
            return Color3(float(number(el, tokens[0], "value")));  // constant: gray in RGB mode
        error = parse_spectrum_pairs(el.get("value"), wl, val);
    } else {
        error = read_spd_file(resolve_filename(el, el.get("filename"), ctx), wl, val);
    }
    if (error.empty()) error = check_spectrum_wavelengths(wl);
    if (!error.empty()) el.fail_here("{}", error);
    SpectrumToRgbMode mode{ctx.within_emitter, is_unbounded_spectrum_name(name)};
    SpectrumToRgbResult r = spectrum_to_linear_srgb(wl, val, mode);
    if (r.clamped)
        warn(el.loc(), "spectrum '{}' is out of the sRGB gamut; clamped to ({}, {}, {})", name, r.rgb.r, r.rgb.g,
             r.rgb.b);
    return r.rgb;
}

}  // namespace

bool is_value_tag(std::string_view tag) {
    static constexpr std::array<std::string_view, 9> tags = {
        "integer", "float", "boolean", "string", "rgb", "spectrum", "point", "vector", "transform"};
    for (auto t : tags)
        if (t == tag) return true;
    return false;
}

bool is_transform_op_tag(std::string_view tag) {
    return tag == "translate" || tag == "rotate" || tag == "scale" || tag == "matrix" || tag == "lookat";
}

std::string resolve_filename(const XmlElement& el, const std::string& name, const PropertyContext& ctx) {
    FileResolver::Dir current{el.file().directory(), el.file().display_directory()};
    auto r = ctx.resolver->resolve(name, current);
    if (!r)
        el.fail_here(
            "file \"{}\" not found (looked next to {}, in the <path> directories and the scene directory)",
            name, el.file().display_path());
    return r->path.string();
}

void add_value_property(const XmlElement& el, Properties& props, const PropertyContext& ctx) {
    std::string_view tag = el.tag();
    if (tag != "transform" && el.node().first_child())
        el.fail_here("<{}> is a value and cannot contain elements or text", tag);
    if (tag == "spectrum")
        el.expect({"name", "value", "filename"}, {"name"});
    else if (tag == "point" || tag == "vector")
        el.expect({"name", "value", "x", "y", "z"}, {"name"});
    else if (tag == "transform")
        el.expect({"name"}, {"name"});
    else
        el.expect({"name", "value"}, {"name", "value"});

    const std::string& name = el.get("name");
    if (name.empty()) el.fail_here("<{}> has an empty name", tag);
    if (name.front() == '_') el.fail_here("<{}>: names starting with '_' are reserved (\"{}\")", tag, name);
    const std::string& value = el.get("value");
    std::string category(tag);

    if (tag == "integer") {
        auto v = parse_int64(value);
        if (!v) el.fail_here("<integer name=\"{}\">: could not parse \"{}\" as an integer", name, value);
        props.set(name, category, *v, el.loc());
    } else if (tag == "float") {
        auto v = parse_double(value, /*allow_infinity=*/true);
        if (!v) el.fail_here("<float name=\"{}\">: could not parse \"{}\" as a number", name, value);
        props.set(name, category, *v, el.loc());
    } else if (tag == "boolean") {
        auto v = parse_bool(value);
        if (!v) el.fail_here("<boolean name=\"{}\">: \"{}\" must be \"true\" or \"false\"", name, value);
        props.set(name, category, *v, el.loc());
    } else if (tag == "string") {
        // File parameters are resolved now so that a missing file is reported at its own line.
        std::string s = name == "filename" ? resolve_filename(el, value, ctx) : value;
        props.set(name, category, std::move(s), el.loc());
    } else if (tag == "rgb") {
        std::vector<double> v = number_list(el, value, "rgb component");
        if (v.size() == 1) v = {v[0], v[0], v[0]};
        if (v.size() != 3)
            el.fail_here("<rgb name=\"{}\"> needs one or three values (got \"{}\")", name, value);
        props.set(name, category, Color3(float(v[0]), float(v[1]), float(v[2])), el.loc());
    } else if (tag == "spectrum") {
        props.set(name, category, spectrum_value(el, name, ctx), el.loc());
    } else if (tag == "point" || tag == "vector") {
        props.set(name, category, xyz_vector(el, 0.0, /*require_all=*/true), el.loc());
    } else if (tag == "transform") {
        props.set(name, category, parse_transform(el, ctx), el.loc());
    } else {
        el.fail_here("<{}> is not a value element", tag);
    }
}

}  // namespace volguide
