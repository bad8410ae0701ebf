#pragma once
// Root of every scene plugin (BSDF, emitter, shape, texture, medium, sensor, ...), so the
// scene loader can hold children of any kind and hand them to parents by name.
#include <memory>
#include <string>

namespace volguide {

class Object {
public:
    virtual ~Object() = default;
    virtual std::string to_string() const { return "Object"; }
};

using ObjectPtr = std::shared_ptr<Object>;

}  // namespace volguide
