#pragma once
// Shared by the media unit tests: the first object of a category in a loaded scene record, a
// volume loaded from an XML snippet, and the optical depth along a line by quadrature of eval().
#include <memory>
#include <string>

#include "test_loader_util.h"
#include "volguide/media/medium.h"
#include "volguide/media/volume.h"

namespace volguide::test {

template <typename T>
std::shared_ptr<T> first(const Properties& root, const std::string& category) {
    auto kids = root.children(category);
    if (kids.empty()) return nullptr;
    return std::dynamic_pointer_cast<T>(std::get<ObjectPtr>(kids[0]->value));
}

inline std::shared_ptr<Volume> load_volume(const ScratchDir& dir, const std::string& body) {
    std::string path = dir.write("v.xml", scene(body));
    return first<Volume>(load_scene_properties(path), "volume");
}

// Optical depth along p0 + t d, t in [0, len], by fine midpoint quadrature of the medium's eval.
inline double optical_depth(const Medium& m, const Point3f& p0, const Vec3f& d, double len, int steps = 20000) {
    double tau = 0.0;
    for (int i = 0; i < steps; ++i) {
        const double t = (i + 0.5) / steps * len;
        tau += m.eval(p0 + d * float(t)).sigma_t.r * len / steps;
    }
    return tau;
}

}  // namespace volguide::test
