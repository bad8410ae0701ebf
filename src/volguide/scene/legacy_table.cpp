// The table of Mitsuba 0.6's plugins and parameters (from its documentation, doc/ and the plugins'
// headers) and what volguide reads each as. A parameter not listed for its plugin is one 0.6 would not
// have read: a warning, and it is dropped (legacy_upgrade.cpp).
#include "volguide/scene/legacy_table.h"

#include "volguide/scene/legacy_rules.h"

namespace volguide::legacy {

namespace {

// ---- families: what 0.6's base classes read for every plugin of a kind -----------------------------

constexpr ParamRule kMonteCarlo[] = {
    {"maxDepth"},
    {"rrDepth"},
    {"hideEmitters"},
    {"strictNormals", Act::hook, nullptr, strict_normals},
};
constexpr ParamRule kSampler[] = {{"sampleCount"}};
// A name ending in '[' stands for every parameter it begins: 0.6's films read annotations
// `metadata['key']` and `label[x, y]`.
constexpr const char* kAnnotation = "annotations (metadata['...'], label[...]) are not written: volguide adds no "
                                    "metadata or text to its images";
constexpr ParamRule kFilm[] = {
    {"metadata[", Act::note, kAnnotation},
    {"label[", Act::note, kAnnotation},
    {"width"},
    {"height"},
    {"cropOffsetX"},
    {"cropOffsetY"},
    {"cropWidth"},
    {"cropHeight"},
    {"highQualityEdges", Act::rename, "sample_border"},
};
constexpr ParamRule kSensor[] = {
    {"toWorld"}, {"shutterOpen"}, {"shutterClose"}, {"nearClip"}, {"farClip"}, {"focusDistance"},
};
constexpr ParamRule kEmitter[] = {
    {"toWorld"},
    {"samplingWeight", Act::hook, nullptr, sampling_weight},
};
// The area emitter takes its shape's placement; the constant one has none.
constexpr ParamRule kAreaEmitter[] = {
    {"samplingWeight", Act::hook, nullptr, sampling_weight},
    {"toWorld", Act::note, "an area emitter is placed by its shape: its 'toWorld' has no effect"},
};
constexpr ParamRule kConstantEmitter[] = {
    {"samplingWeight", Act::hook, nullptr, sampling_weight},
    {"toWorld", Act::drop},  // a constant emitter looks the same from every orientation
};
constexpr ParamRule kShape[] = {{"toWorld"}, {"interior"}, {"exterior"}};
constexpr ParamRule kMesh[] = {{"toWorld"}, {"interior"}, {"exterior"}, {"faceNormals"}, {"flipNormals"}};
// Every BSDF: energy conservation, applied by each plugin's rule to the parameters 0.6 checks; the
// BSDFs without reflectances of their own have nothing to apply it to.
constexpr ParamRule kBsdf[] = {{"ensureEnergyConservation", Act::plugin}};
constexpr ParamRule kBsdfWithout[] = {{"ensureEnergyConservation", Act::drop}};
// Every 2-D texture: uv offsets and scales (uv_transform).
constexpr ParamRule kTexture2D[] = {
    {"uoffset", Act::plugin}, {"voffset", Act::plugin}, {"uscale", Act::plugin},
    {"vscale", Act::plugin},  {"uvscale", Act::plugin}, {"coordinates", Act::hook, nullptr, texture_coordinates},
};

// ---- integrators ------------------------------------------------------------------------------------

constexpr ParamRule kDirect[] = {
    {"shadingSamples"}, {"emitterSamples"}, {"bsdfSamples"}, {"hideEmitters"},
    {"strictNormals", Act::hook, nullptr, strict_normals},
};
constexpr ParamRule kPtracer[] = {
    {"maxDepth"},
    {"rrDepth"},
    {"granularity", Act::note,
     "ptracer's 'granularity' (work unit size) has no effect in volguide: its passes are the render loop's"},
    {"bruteForce", Act::hook, nullptr, brute_force},
};

// ---- samplers, films, filters, sensors --------------------------------------------------------------

constexpr ParamRule kDimension[] = {
    {"dimension", Act::note,
     "'dimension' (how many sample dimensions are stratified) has no effect: volguide samples independently"},
};
constexpr ParamRule kScramble[] = {
    {"scramble", Act::note, "'scramble' has no effect: volguide samples independently"},
};
constexpr ParamRule kHdrFilm[] = {
    {"fileFormat", Act::hook, nullptr, hdr_file_format},
    {"pixelFormat", Act::hook, nullptr, hdr_pixel_format},
    {"componentFormat"},
    {"channelNames", Act::note, "'channelNames' has no effect: volguide names its channels R, G, B"},
    {"attachLog", Act::hook, nullptr, note_if_true},
    {"banner", Act::hook, nullptr, note_if_true},
};
constexpr ParamRule kLdrFilm[] = {
    {"fileFormat", Act::hook, nullptr, ldr_file_format},
    {"pixelFormat", Act::hook, nullptr, ldr_pixel_format},
    {"tonemapMethod"},
    {"gamma"},
    {"exposure"},
    {"key"},
    {"burn"},
    {"banner", Act::hook, nullptr, note_if_true},
};
constexpr ParamRule kTiledHdrFilm[] = {
    {"pixelFormat", Act::hook, nullptr, hdr_pixel_format},
    {"componentFormat"},
};
constexpr ParamRule kBox[] = {{"radius"}};
constexpr ParamRule kGaussian[] = {{"stddev"}};
constexpr ParamRule kMitchell[] = {{"B"}, {"C"}};
constexpr ParamRule kLanczos[] = {{"lobes"}};
constexpr ParamRule kPerspective[] = {{"fov"}, {"fovAxis", Act::plugin}, {"focalLength"}};
constexpr ParamRule kThinLens[] = {{"fov"}, {"fovAxis", Act::plugin}, {"focalLength"}, {"apertureRadius"}};

// ---- shapes -----------------------------------------------------------------------------------------

constexpr const char* kSmoothAngle =
    "'maxSmoothAngle' (normals recomputed with crease detection) has no equivalent: remove it to use the "
    "file's normals, or set faceNormals";
constexpr ParamRule kObj[] = {
    {"filename"},
    {"flipTexCoords"},
    {"maxSmoothAngle", Act::reject, kSmoothAngle},
    {"shapeIndex", Act::hook, nullptr, obj_shape_index},
    {"collapse", Act::drop},  // one shape or one per group: the same surfaces
    {"loadMaterials", Act::plugin},
};
constexpr ParamRule kPly[] = {
    {"filename"},
    {"maxSmoothAngle", Act::reject, kSmoothAngle},
    {"srgb", Act::drop},  // vertex colours are read only by vertexcolors, which has no equivalent
};
constexpr ParamRule kSerialized[] = {
    {"filename"},
    {"shapeIndex"},
    {"maxSmoothAngle", Act::reject, kSmoothAngle},
};
constexpr ParamRule kFlip[] = {{"flipNormals"}};
constexpr ParamRule kSphere[] = {{"center"}, {"radius"}, {"flipNormals"}};
constexpr ParamRule kCylinder[] = {{"p0"}, {"p1"}, {"radius"}, {"flipNormals"}};

// ---- BSDFs ------------------------------------------------------------------------------------------

constexpr ParamRule kDiffuse[] = {
    {"reflectance"},
    {"diffuseReflectance", Act::hook, nullptr, diffuse_reflectance},
};
constexpr ParamRule kDielectric[] = {
    {"intIOR"}, {"extIOR"}, {"specularReflectance"}, {"specularTransmittance"},
};
constexpr ParamRule kRoughDielectric[] = {
    {"intIOR"},
    {"extIOR"},
    {"specularReflectance"},
    {"specularTransmittance"},
    {"distribution", Act::hook, nullptr, distribution},
    {"alpha"},
    {"alphaU"},
    {"alphaV"},
    {"sampleVisible"},
};
constexpr ParamRule kConductor[] = {
    {"material", Act::plugin}, {"eta", Act::plugin}, {"k", Act::plugin}, {"extEta", Act::plugin},
    {"specularReflectance"},
};
constexpr ParamRule kRoughConductor[] = {
    {"material", Act::plugin},
    {"eta", Act::plugin},
    {"k", Act::plugin},
    {"extEta", Act::plugin},
    {"specularReflectance"},
    {"distribution", Act::hook, nullptr, distribution},
    {"alpha"},
    {"alphaU"},
    {"alphaV"},
    {"sampleVisible"},
};
constexpr ParamRule kPlastic[] = {
    {"intIOR"}, {"extIOR"}, {"specularReflectance"}, {"diffuseReflectance"}, {"nonlinear"},
};
constexpr ParamRule kRoughPlastic[] = {
    {"intIOR"},      {"extIOR"},
    {"specularReflectance"}, {"diffuseReflectance"},
    {"nonlinear"},   {"distribution", Act::hook, nullptr, distribution},
    {"alpha"},       {"sampleVisible"},
};
constexpr ParamRule kMask[] = {{"opacity"}};
constexpr ParamRule kBlend[] = {{"weight"}};
constexpr ParamRule kMixture[] = {{"weights", Act::plugin}};

// ---- textures ---------------------------------------------------------------------------------------

constexpr ParamRule kBitmap[] = {
    {"filename"},
    {"filterType", Act::plugin},
    {"wrapMode", Act::plugin},
    {"wrapModeU", Act::plugin},
    {"wrapModeV", Act::plugin},
    {"gamma", Act::plugin},
    {"maxAnisotropy", Act::note, "'maxAnisotropy' (of EWA filtering) has no effect: volguide filters bilinearly"},
    {"cache", Act::hook, nullptr, note_if_true},
    {"channel", Act::reject,
     "'channel' (one channel of the image as a grey texture) has no equivalent: save that channel as an image "
     "of its own"},
};
constexpr ParamRule kCheckerboard[] = {{"color0"}, {"color1"}};

// ---- emitters ---------------------------------------------------------------------------------------

constexpr ParamRule kArea[] = {{"radiance"}};
constexpr ParamRule kPoint[] = {{"position"}, {"intensity"}};
constexpr ParamRule kSpot[] = {{"intensity"}, {"cutoffAngle"}, {"beamWidth"}, {"texture"}};
constexpr ParamRule kDirectional[] = {{"direction"}, {"irradiance"}};
constexpr ParamRule kConstant[] = {{"radiance"}};
constexpr ParamRule kEnvmap[] = {
    {"filename"},
    {"scale"},
    {"gamma", Act::plugin},
    {"cache", Act::hook, nullptr, note_if_true},
};

// ---- media, phase functions, volumes ----------------------------------------------------------------

constexpr ParamRule kHomogeneous[] = {
    {"material", Act::reject,
     "the named medium presets (Jensen et al., Narasimhan et al.) are not available: give sigmaA and sigmaS "
     "(the presets are in 1/mm, so with a scale that converts to scene units)"},
    {"sigmaA", Act::plugin},
    {"sigmaS", Act::plugin},
    {"sigmaT", Act::plugin},
    {"albedo", Act::plugin},
    {"g", Act::plugin},
    {"scale"},
    {"densityMultiplier", Act::reject, "'densityMultiplier' is called 'scale' since Mitsuba 0.4"},
    {"sizeMultiplier", Act::reject, "'sizeMultiplier' is called 'scale' since Mitsuba 0.4"},
    {"strategy", Act::note,
     "'strategy' (how distances are sampled in a chromatic medium) has no effect: volguide samples with "
     "spectral MIS, same expectation"},
    {"channel", Act::note, "'channel' (the channel distances are sampled in) has no effect: volguide samples "
                           "with spectral MIS, same expectation"},
    {"samplingDensity", Act::note, "'samplingDensity' has no effect: volguide samples with spectral MIS"},
    {"mediumSamplingWeight", Act::note,
     "'mediumSamplingWeight' has no effect: volguide samples distances by the extinction"},
    {"monochromatic", Act::hook, nullptr, monochromatic},
};
constexpr ParamRule kHeterogeneous[] = {
    {"method", Act::hook, nullptr, tracking_method},
    {"density", Act::rename, "sigma_t"},
    {"albedo"},
    {"orientation", Act::reject,
     "'orientation' serves the microflake phase function, which has no equivalent: remove both"},
    {"scale"},
    {"stepSize", Act::note, "'stepSize' (of Simpson quadrature) has no effect: volguide tracks without steps"},
    {"densityMultiplier", Act::reject, "'densityMultiplier' is called 'scale' since Mitsuba 0.4"},
    {"sigmaA", Act::reject, "heterogeneous media take 'density' and 'albedo' volumes, not sigmaA/sigmaS"},
    {"sigmaS", Act::reject, "heterogeneous media take 'density' and 'albedo' volumes, not sigmaA/sigmaS"},
};
constexpr ParamRule kHg[] = {{"g"}};
constexpr ParamRule kConstVolume[] = {{"value"}};
constexpr ParamRule kGridVolume[] = {
    {"filename"},
    {"toWorld", Act::plugin},
    {"min", Act::plugin},
    {"max", Act::plugin},
    {"sendData", Act::hook, nullptr, note_if_true},
};

// ---- messages of the plugins without an equivalent --------------------------------------------------

constexpr const char* kUnbiasedInstead =
    "no equivalent in volguide: render with 'volpath' (or 'path' without media), which converges to the same "
    "image";
constexpr const char* kBiasedInstead =
    "no equivalent in volguide: render with 'volpath' (or 'path' without media), which converges to the image "
    "this method approximates";
constexpr const char* kNoSubsurface =
    "no equivalent: model the interior as a 'homogeneous' medium inside a 'dielectric' shape and render with "
    "'volpath'";

constexpr const char* kNoBump =
    "no equivalent: Mitsuba 0.6's bump mapping builds its frame differently from Mitsuba 3's 'bumpmap' (which also "
    "adds a shadowing term); remove it or write the Mitsuba 3 bumpmap in a 3.0 file";

// clang-format off
constexpr PluginRule kPlugins[] = {
    // integrators
    {"integrator", "path", nullptr, nullptr, {}, kMonteCarlo},
    {"integrator", "volpath", nullptr, nullptr, {}, kMonteCarlo},
    {"integrator", "volpath_simple", "volpath", nullptr, {}, kMonteCarlo, volpath_simple},
    {"integrator", "direct", nullptr, nullptr, kDirect},
    {"integrator", "ptracer", nullptr, nullptr, kPtracer},
    {"integrator", "bdpt", nullptr, kUnbiasedInstead},
    {"integrator", "pssmlt", nullptr, kUnbiasedInstead},
    {"integrator", "mlt", nullptr, kUnbiasedInstead},
    {"integrator", "erpt", nullptr, kUnbiasedInstead},
    {"integrator", "ppm", nullptr, kBiasedInstead},
    {"integrator", "sppm", nullptr, kBiasedInstead},
    {"integrator", "photonmapper", nullptr, kBiasedInstead},
    {"integrator", "vpl", nullptr, kBiasedInstead},
    {"integrator", "irrcache", nullptr, kBiasedInstead},
    {"integrator", "ao", nullptr, "no equivalent in volguide (ambient occlusion)"},
    {"integrator", "adaptive", nullptr,
     "no equivalent in volguide (adaptive sampling): use its nested integrator directly, with a fixed "
     "sample count or --time"},
    {"integrator", "multichannel", nullptr, "no equivalent in volguide: render each nested integrator on its own"},
    {"integrator", "field", nullptr, "no equivalent in volguide (geometry buffers)"},
    {"integrator", "motion", nullptr, "no equivalent in volguide (motion vectors)"},
    // samplers
    {"sampler", "independent", nullptr, nullptr, {}, kSampler},
    {"sampler", "stratified", nullptr, nullptr, kDimension, kSampler},
    {"sampler", "ldsampler", nullptr, nullptr, kDimension, kSampler},
    {"sampler", "halton", "independent", nullptr, kScramble, kSampler, low_discrepancy_sampler},
    {"sampler", "hammersley", "independent", nullptr, kScramble, kSampler, low_discrepancy_sampler},
    {"sampler", "sobol", "independent", nullptr, kScramble, kSampler, low_discrepancy_sampler},
    // films and reconstruction filters
    {"film", "hdrfilm", nullptr, nullptr, kHdrFilm, kFilm},
    {"film", "ldrfilm", nullptr, nullptr, kLdrFilm, kFilm, ldrfilm},
    {"film", "tiledhdrfilm", "hdrfilm", nullptr, kTiledHdrFilm, kFilm},  // tiles are storage: same pixels
    {"film", "mfilm", nullptr, "no equivalent in volguide (MATLAB/Mathematica/NumPy output): use hdrfilm"},
    {"rfilter", "box", nullptr, nullptr, kBox},
    {"rfilter", "tent"},
    {"rfilter", "gaussian", nullptr, nullptr, kGaussian},
    {"rfilter", "mitchell", nullptr, nullptr, kMitchell},
    {"rfilter", "catmullrom"},
    {"rfilter", "lanczos", nullptr, nullptr, kLanczos},
    // sensors
    {"sensor", "perspective", nullptr, nullptr, kPerspective, kSensor, sensor_rules},
    {"sensor", "thinlens", nullptr, nullptr, kThinLens, kSensor, sensor_rules},
    {"sensor", "orthographic", nullptr, nullptr, {}, kSensor, sensor_rules},
    {"sensor", "telecentric", nullptr, "no equivalent in volguide: use 'orthographic'"},
    {"sensor", "spherical", nullptr, "no equivalent in volguide"},
    {"sensor", "perspective_rdist", nullptr, "no equivalent in volguide: use 'perspective' (no lens distortion)"},
    {"sensor", "radiancemeter", nullptr, "no equivalent in volguide"},
    {"sensor", "irradiancemeter", nullptr, "no equivalent in volguide"},
    {"sensor", "fluencemeter", nullptr, "no equivalent in volguide"},
    // shapes
    {"shape", "obj", nullptr, nullptr, kObj, kMesh, obj_materials},
    {"shape", "ply", nullptr, nullptr, kPly, kMesh, shape_defaults},
    {"shape", "serialized", nullptr, nullptr, kSerialized, kMesh, shape_defaults},
    {"shape", "rectangle", nullptr, nullptr, kFlip, kShape, shape_defaults},
    {"shape", "cube", nullptr, nullptr, kFlip, kShape, shape_defaults},
    {"shape", "disk", nullptr, nullptr, kFlip, kShape, shape_defaults},
    {"shape", "sphere", nullptr, nullptr, kSphere, kShape, shape_defaults},
    {"shape", "cylinder", nullptr, nullptr, kCylinder, kShape, shape_defaults},
    {"shape", "shapegroup"},
    {"shape", "instance", nullptr, nullptr, {}, kShape},
    {"shape", "hair", nullptr, "no equivalent in volguide (Mitsuba 3 models hair as 'bsplinecurve', also not read)"},
    {"shape", "heightfield", nullptr, "no equivalent in volguide: convert the height field to a mesh (ply, obj)"},
    {"shape", "deformable", nullptr, "no equivalent in volguide (animated meshes)"},
    // BSDFs
    {"bsdf", "diffuse", nullptr, nullptr, kDiffuse, kBsdf, diffuse_rules},
    {"bsdf", "dielectric", nullptr, nullptr, kDielectric, kBsdf, dielectric_rules},
    {"bsdf", "thindielectric", nullptr, nullptr, kDielectric, kBsdf, dielectric_rules},
    {"bsdf", "roughdielectric", nullptr, nullptr, kRoughDielectric, kBsdf, dielectric_rules},
    {"bsdf", "conductor", nullptr, nullptr, kConductor, kBsdf, conductor_rules},
    {"bsdf", "roughconductor", nullptr, nullptr, kRoughConductor, kBsdf, conductor_rules},
    {"bsdf", "plastic", nullptr, nullptr, kPlastic, kBsdf, plastic_rules},
    {"bsdf", "roughplastic", nullptr, nullptr, kRoughPlastic, kBsdf, plastic_rules},
    {"bsdf", "twosided", nullptr, nullptr, {}, kBsdfWithout},
    {"bsdf", "mask", nullptr, nullptr, kMask, kBsdf, mask_rules},
    {"bsdf", "blendbsdf", nullptr, nullptr, kBlend, kBsdfWithout, blendbsdf_rules},
    {"bsdf", "mixturebsdf", "blendbsdf", nullptr, kMixture, kBsdfWithout, mixturebsdf_rules},
    {"bsdf", "null", nullptr, nullptr, {}, kBsdfWithout},
    {"bsdf", "bumpmap", nullptr, kNoBump},
    {"bsdf", "bump", nullptr, kNoBump},  // Mitsuba 0.4's name
    {"bsdf", "normalmap", nullptr,
     "no equivalent: Mitsuba 0.6's normal mapping differs from Mitsuba 3's 'normalmap' (its validity test, no "
     "shadowing term); remove it or write the Mitsuba 3 normalmap in a 3.0 file"},
    {"bsdf", "roughdiffuse", nullptr, "no equivalent in volguide (Oren-Nayar): use 'diffuse'"},
    {"bsdf", "coating", nullptr, "no equivalent in volguide: use 'plastic' for a coated diffuse surface"},
    {"bsdf", "roughcoating", nullptr, "no equivalent in volguide: use 'roughplastic' for a coated diffuse surface"},
    {"bsdf", "phong", nullptr, "no equivalent in volguide: use 'roughplastic'"},
    {"bsdf", "ward", nullptr, "no equivalent in volguide: use 'roughplastic' or 'roughconductor'"},
    {"bsdf", "hk", nullptr, "no equivalent in volguide: use a homogeneous medium inside a thin shape"},
    {"bsdf", "irawan", nullptr, "no equivalent in volguide (woven cloth)"},
    {"bsdf", "difftrans", nullptr, "no equivalent in volguide (diffuse transmission)"},
    // textures
    {"texture", "bitmap", nullptr, nullptr, kBitmap, kTexture2D, bitmap_rules},
    {"texture", "checkerboard", nullptr, nullptr, kCheckerboard, kTexture2D, uv_transform},
    {"texture", "scale", nullptr, "no equivalent in volguide (a scaled texture): scale the image or the parameter"},
    {"texture", "vertexcolors", nullptr,
     "no equivalent: Mitsuba 3's 'mesh_attribute' (name 'vertex_color') reads a PLY's colours, but not as 0.6 "
     "does (sRGB decoding); write it in a 3.0 file"},
    {"texture", "gridtexture", nullptr, "no equivalent in volguide"},
    {"texture", "wireframe", nullptr, "no equivalent in volguide"},
    {"texture", "curvature", nullptr, "no equivalent in volguide"},
    // emitters
    {"emitter", "area", nullptr, nullptr, kArea, kAreaEmitter},
    {"emitter", "point", nullptr, nullptr, kPoint, kEmitter, emitter_medium},
    {"emitter", "spot", nullptr, nullptr, kSpot, kEmitter, emitter_medium},
    {"emitter", "directional", nullptr, nullptr, kDirectional, kEmitter, emitter_medium},
    {"emitter", "constant", nullptr, nullptr, kConstant, kConstantEmitter},
    {"emitter", "envmap", nullptr, nullptr, kEnvmap, kEmitter, envmap_rules},
    {"emitter", "sun", nullptr, "no equivalent in volguide: use an 'envmap' or a 'directional' emitter"},
    {"emitter", "sky", nullptr, "no equivalent in volguide: use an 'envmap' of the sky"},
    {"emitter", "sunsky", nullptr, "no equivalent in volguide: use an 'envmap' of the sky and a 'directional' sun"},
    {"emitter", "collimated", nullptr, "no equivalent in volguide (a collimated beam)"},
    // media, phase functions, volumes
    {"medium", "homogeneous", nullptr, nullptr, kHomogeneous, {}, homogeneous_rules},
    {"medium", "heterogeneous", nullptr, nullptr, kHeterogeneous, {}, heterogeneous_rules},
    {"phase", "isotropic"},
    {"phase", "hg", nullptr, nullptr, kHg},
    {"phase", "rayleigh", nullptr, "no equivalent in volguide: use 'hg' or 'isotropic'"},
    {"phase", "kkay", nullptr, "no equivalent in volguide: use 'hg'"},
    {"phase", "microflake", nullptr, "no equivalent in volguide: use 'hg'"},
    {"phase", "mixturephase", nullptr, "no equivalent in volguide: use a single 'hg'"},
    {"volume", "constvolume", nullptr, nullptr, kConstVolume},
    {"volume", "gridvolume", nullptr, nullptr, kGridVolume, {}, gridvolume_rules},
    {"volume", "hgridvolume", nullptr, "no equivalent in volguide: merge the grids into one 'gridvolume'"},
    {"volume", "volcache", nullptr, "no equivalent in volguide: use its nested volume directly"},
    // subsurface scattering
    {"subsurface", "dipole", nullptr, kNoSubsurface},
    {"subsurface", "singlescatter", nullptr, kNoSubsurface},
};
// clang-format on

const ParamRule* find_in(std::span<const ParamRule> rules, std::string_view name) {
    for (const ParamRule& r : rules) {
        const std::string_view rule = r.name;
        if (name == rule || (rule.ends_with('[') && name.starts_with(rule))) return &r;
    }
    return nullptr;
}

}  // namespace

const PluginRule* find_plugin(std::string_view category, std::string_view type) {
    for (const PluginRule& p : kPlugins)
        if (category == p.category && type == p.type) return &p;
    return nullptr;
}

const ParamRule* find_param(const PluginRule& plugin, std::string_view name) {
    if (const ParamRule* r = find_in(plugin.params, name)) return r;
    return find_in(plugin.family, name);
}

std::span<const PluginRule> plugin_table() {
    return kPlugins;
}

}  // namespace volguide::legacy
