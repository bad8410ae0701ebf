#include "volguide/render/bsdfs/conductor_ior.h"

#include "volguide/render/bsdfs/bsdf_util.h"
#include "volguide/render/bsdfs/ior.h"

namespace volguide {

ConductorIor ConductorIor::parse(const Properties& props) {
    ConductorIor c;
    const std::string material = props.get_string("material", "none");
    if (props.has("eta") || props.has("k") || material == "none") {
        if (material != "none") props.fail_at("material", "specify either 'eta'/'k' or 'material', not both");
        c.eta = nonnegative_texture(props, "eta", Color3(0.f));
        c.k = nonnegative_texture(props, "k", Color3(1.f));
        return c;
    }
    std::optional<ComplexIor> preset = conductor_preset(material);
    if (!preset) {
        std::string names = "none";
        for (const ConductorPreset& p : conductor_table()) names += std::string(", ") + p.name;
        props.fail_at("material", "unknown conductor material '{}'; valid names: {}", material, names);
    }
    c.eta = std::make_shared<ConstantTexture>(preset->eta);
    c.k = std::make_shared<ConstantTexture>(preset->k);
    return c;
}

}  // namespace volguide
