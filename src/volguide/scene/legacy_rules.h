#pragma once
// Internal to the upgrade of Mitsuba 0.x files: the rules of the table (scene/legacy_table.cpp) that
// are more than a rename. Each states 0.6's meaning of what it reads, from Mitsuba 0.6's documentation
// and plugins; parameter rules see the plugin element and the parameter, plugin rules run once the
// parameters carry Mitsuba 3's names.
#include <pugixml.hpp>

namespace volguide::legacy {

class Dom;

// ---- parameters (legacy_rules_params.cpp) ---------------------------------------------------------
void strict_normals(Dom&, pugi::xml_node object, pugi::xml_node param);
void sampling_weight(Dom&, pugi::xml_node object, pugi::xml_node param);
void note_if_true(Dom&, pugi::xml_node object, pugi::xml_node param);  // banner, attachLog, sendData, cache
void brute_force(Dom&, pugi::xml_node object, pugi::xml_node param);
void diffuse_reflectance(Dom&, pugi::xml_node object, pugi::xml_node param);
void distribution(Dom&, pugi::xml_node object, pugi::xml_node param);
void texture_coordinates(Dom&, pugi::xml_node object, pugi::xml_node param);
void hdr_file_format(Dom&, pugi::xml_node object, pugi::xml_node param);
void hdr_pixel_format(Dom&, pugi::xml_node object, pugi::xml_node param);
void ldr_file_format(Dom&, pugi::xml_node object, pugi::xml_node param);
void ldr_pixel_format(Dom&, pugi::xml_node object, pugi::xml_node param);
void tracking_method(Dom&, pugi::xml_node object, pugi::xml_node param);
void monochromatic(Dom&, pugi::xml_node object, pugi::xml_node param);
void obj_shape_index(Dom&, pugi::xml_node object, pugi::xml_node param);

// ---- plugins (legacy_rules_plugins.cpp, legacy_rules_bsdf.cpp, legacy_rules_media.cpp) -------------
void shape_defaults(Dom&, pugi::xml_node shape);  // 0.6's BSDF of a shape without one
void obj_materials(Dom&, pugi::xml_node shape);   // loadMaterials, then shape_defaults
void sensor_rules(Dom&, pugi::xml_node sensor);   // fovAxis without fov, the unnamed medium
void emitter_medium(Dom&, pugi::xml_node emitter);
void envmap_rules(Dom&, pugi::xml_node emitter);
void low_discrepancy_sampler(Dom&, pugi::xml_node sampler);  // halton, hammersley, sobol
void volpath_simple(Dom&, pugi::xml_node integrator);
void ldrfilm(Dom&, pugi::xml_node film);
void bitmap_rules(Dom&, pugi::xml_node texture);  // includes the uv transform
void uv_transform(Dom&, pugi::xml_node texture);  // uoffset, voffset, uscale, vscale, uvscale
void diffuse_rules(Dom&, pugi::xml_node bsdf);
void dielectric_rules(Dom&, pugi::xml_node bsdf);
void conductor_rules(Dom&, pugi::xml_node bsdf);
void plastic_rules(Dom&, pugi::xml_node bsdf);
void mask_rules(Dom&, pugi::xml_node bsdf);
void blendbsdf_rules(Dom&, pugi::xml_node bsdf);
void mixturebsdf_rules(Dom&, pugi::xml_node bsdf);
void homogeneous_rules(Dom&, pugi::xml_node medium);
void heterogeneous_rules(Dom&, pugi::xml_node medium);
void gridvolume_rules(Dom&, pugi::xml_node volume);

// ---- the whole file, once its elements are upgraded (legacy_rules_plugins.cpp) ---------------------
// strictNormals=true: no effect where every shading normal is its geometric one, a warning elsewhere.
void strict_normals_effect(Dom&, pugi::xml_node root);

}  // namespace volguide::legacy
