#include "volguide/integrators/integrator_configuration.h"

#include <fmt/format.h>

#include <algorithm>
#include <vector>

#include "volguide/integrators/integrator.h"

namespace volguide {

namespace {

bool output_only(const std::string& name) { return name == "save_field" || name == "save_pixel_estimate"; }

std::string value_text(const Properties::Value& value) {
    struct Visitor {
        std::string operator()(bool v) const { return v ? "true" : "false"; }
        std::string operator()(int64_t v) const { return std::to_string(v); }
        std::string operator()(double v) const { return fmt::format("{:.17g}", v); }
        std::string operator()(const std::string& v) const { return "\"" + v + "\""; }
        std::string operator()(const Color3& c) const { return fmt::format("[{:.9g}, {:.9g}, {:.9g}]", c.r, c.g, c.b); }
        std::string operator()(const Vec3f& v) const { return fmt::format("({:.9g}, {:.9g}, {:.9g})", v.x, v.y, v.z); }
        std::string operator()(const Transform&) const { return "transform"; }
        std::string operator()(const ObjectPtr& o) const {
            if (!o) return "null";
            if (const auto* integrator = dynamic_cast<const Integrator*>(o.get())) return integrator->configuration();
            return o->to_string();
        }
    };
    return std::visit(Visitor{}, value);
}

}  // namespace

std::string integrator_configuration(const Properties& props) {
    std::vector<std::string> items;
    for (const Properties::Entry& e : props.entries()) {
        if (output_only(e.name)) continue;
        items.push_back((e.name.empty() ? e.category : e.name) + "=" + value_text(e.value));
    }
    std::sort(items.begin(), items.end());
    std::string text = props.type() + "{";
    for (size_t i = 0; i < items.size(); ++i) text += (i ? ", " : "") + items[i];
    return text + "}";
}

}  // namespace volguide
