#pragma once
// Helpers for the geometry tests: hand-built shape Properties (no BSDF/emitter children) and
// shape creation through the real factory, with the loader's unused-parameter check.
#include <memory>
#include <string>

#include "volguide/core/properties.h"
#include "volguide/geometry/shape.h"
#include "volguide/scene/factories.h"

namespace volguide::test {

inline SourceLocation test_loc(const std::string& file = "test.xml") {
    return {file, 1};
}

struct ShapeProps {
    Properties props;
    explicit ShapeProps(const std::string& type, const std::string& file = "test.xml")
        : props("shape", type, test_loc(file)) {}
    ShapeProps& f(const std::string& name, double v) { return set(name, "float", v); }
    ShapeProps& b(const std::string& name, bool v) { return set(name, "boolean", v); }
    ShapeProps& s(const std::string& name, const std::string& v) { return set(name, "string", v); }
    ShapeProps& p(const std::string& name, Vec3f v) { return set(name, "point", v); }
    ShapeProps& t(const std::string& name, const Transform& v) { return set(name, "transform", v); }
    template <typename V>
    ShapeProps& set(const std::string& name, const std::string& category, V v) {
        props.set(name, category, Properties::Value(v), test_loc());
        return *this;
    }
};

inline std::shared_ptr<Shape> make_shape(const ShapeProps& sp) {
    ObjectPtr obj = create_shape(sp.props);
    sp.props.check_all_used();
    return std::dynamic_pointer_cast<Shape>(obj);
}

}  // namespace volguide::test
