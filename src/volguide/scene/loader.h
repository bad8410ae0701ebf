#pragma once
// Mitsuba 3 XML scenes → the render-ready Scene.
// Pipeline: XML (pugixml) → Properties records with file:line → factories → Scene.
//
// Supported subset (docs/scene-format.md has the user-facing description):
//  - root <scene version="2.x.y|3.x.y">; object tags bsdf, texture, emitter, shape, sensor, film,
//    rfilter, sampler, integrator, medium, phase, volume;
//    <spectrum type=".."> is a texture object;
//  - values integer, float, boolean, string, rgb, spectrum (constant, wavelength:value pairs or a
//    .spd file; pairs are reduced to linear sRGB exactly as Mitsuba's RGB variants do), point,
//    vector, transform (translate, rotate, scale, matrix 4x4/3x3, lookat; later operations are
//    applied after earlier ones);
//  - <default>, `$name` in any attribute (also inside longer strings, `\$` for a literal '$'),
//    -D overrides of declared defaults only, <include> (scene or single-object files, cycles
//    rejected), <path>, ids, <ref>, <alias>;
//  - every string parameter named `filename` is resolved at load time to an existing absolute
//    path: next to the file mentioning it, then in <path> directories, then the scene directory.
// Everything else (unknown tags or attributes, bad numbers, NaN, unused parameters) is an
// InputError with the file and line it comes from.
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "volguide/core/object.h"
#include "volguide/core/properties.h"
#include "volguide/render/scene.h"

namespace volguide {

struct LoadOptions {
    // -D name=value overrides of <default> values; a name the scene never declares is an error.
    std::map<std::string, std::string> defines;
    // When set, receives the real paths of every XML file read (the main file and its includes,
    // sorted): what a render checkpoint's scene fingerprint covers besides the main file.
    std::vector<std::string>* xml_files = nullptr;
};

// Creates the plugin for one XML object; `tag` is the category (bsdf, shape, ...).
using ObjectFactory = std::function<ObjectPtr(const std::string& tag, const Properties& props)>;

// The real factory table: dispatches to create_<tag> of factories.h.
ObjectPtr create_object(const std::string& tag, const Properties& props);

// Parses the file and instantiates every object; returns the root <scene> record whose children
// are the instantiated top-level objects. Throws InputError (file:line) on any problem.
Properties load_scene_properties(const std::string& path, const LoadOptions& options = {});
// Same with another factory (tests use fakes so they need no real plugins).
Properties load_scene_properties(const std::string& path, const LoadOptions& options,
                                 const ObjectFactory& factory);

std::unique_ptr<Scene> load_scene(const std::string& path, const LoadOptions& options = {});
// The Scene of a loaded root record, with Mitsuba 3's defaults for what the file leaves out: a
// diffuse BSDF of reflectance 0.5 on every shape without one (one object shared by all of them)
// and the `path` integrator.
std::unique_ptr<Scene> make_scene(const Properties& root);

}  // namespace volguide
