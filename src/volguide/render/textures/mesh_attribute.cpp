// `mesh_attribute` (Mitsuba 3): the value of a mesh's per-vertex or per-face attribute at the hit,
// times `scale`. The attribute is the hit shape's (a texture is shared by every shape using it);
// the scene loader checks that each mesh whose BSDF uses the texture has the attribute
// (scene/loader.cpp), so eval never meets a shape without it.
#include <cmath>
#include <stdexcept>

#include "volguide/geometry/shape.h"
#include "volguide/render/textures/textures.h"

namespace volguide {

namespace {

class MeshAttributeTexture final : public Texture {
  public:
    MeshAttributeTexture(std::string name, float scale) : name_(std::move(name)), scale_(scale) {}

    Color3 eval(const SurfaceInteraction& si) const override {
        return si.shape ? si.shape->eval_attribute(name_, si) * scale_ : Color3(0.f);
    }
    // Mitsuba 3 has no mean for this texture (it depends on the shape): BSDFs that need one
    // (sampling weights) cannot take it, there as here.
    Color3 mean() const override {
        throw std::invalid_argument("the 'mesh_attribute' texture has no mean value (as in Mitsuba 3); "
                                    "this parameter cannot be a mesh attribute");
    }
    std::string to_string() const override { return "MeshAttribute[" + name_ + "]"; }

  private:
    std::string name_;
    float scale_;
};

}  // namespace

std::shared_ptr<Texture> make_mesh_attribute_texture(const Properties& props) {
    std::string name = props.get_string("name");
    if (name.rfind("vertex_", 0) != 0 && name.rfind("face_", 0) != 0)
        props.fail_at("name", "mesh_attribute: the name must start with \"vertex_\" or \"face_\" (got \"{}\")", name);
    const float scale = props.get_float("scale", 1.f);
    if (!std::isfinite(scale)) props.fail_at("scale", "mesh_attribute: 'scale' must be finite (got {})", scale);
    return std::make_shared<MeshAttributeTexture>(std::move(name), scale);
}

}  // namespace volguide
