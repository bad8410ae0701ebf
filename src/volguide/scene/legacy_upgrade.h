#pragma once
// Scene files of Mitsuba 0.4 to 0.6 (versions 0.4.0 – 0.6.x) read as Mitsuba 3 reads what they mean.
// The tree of such a file is rewritten in place, before the reader's second pass, into the Mitsuba 3
// form: first Mitsuba 3's own upgrade of pre-2.0 files (parameter names from camelCase to snake_case,
// <lookAt>, reserved ids, diffuseReflectance, uv offsets and scales), then every 0.6 plugin and
// parameter as its Mitsuba 3 equivalent under 0.6's documented semantics (the table of
// scene/legacy_table.cpp; docs/scene-format.md, "Mitsuba 0.6 scenes", lists it). A plugin or
// parameter without an equivalent is an InputError at its line naming what to use instead; a
// parameter Mitsuba 0.6 would have ignored (it warned about unused parameters, and forks added their
// own) is a warning at its line and is dropped. `volguide upgrade` writes the rewritten file.
#include <string>
#include <string_view>

#include "volguide/scene/file_resolver.h"
#include "volguide/scene/scene_parameters.h"
#include "volguide/scene/xml_file.h"

namespace volguide {

// What the rewritten tree is for. `volguide` is what the loader renders: where Mitsuba 3 has no
// equivalent but volguide has one (the ldrfilm's tonemapped PNG), volguide's is kept. `mitsuba3` is
// what `volguide upgrade` writes, which Mitsuba 3 reads too: such parts become their nearest Mitsuba 3
// form, with a warning naming what is lost.
enum class UpgradeTarget { volguide, mitsuba3 };

struct LegacyContext {
    UpgradeTarget target = UpgradeTarget::volguide;
    const SceneParameters* params = nullptr;  // `$name` in attributes the rules read
    const FileResolver* resolver = nullptr;   // data files the rules read (.vol headers, images)
};

// Whether the file's root carries a version of Mitsuba 0.4 to 0.6 (`$name` substituted).
bool is_legacy_file(const XmlFile& file, const SceneParameters& params);
// A root version the reader refuses, with the message saying which versions are read; empty when the
// version is one of 0.4.0 – 0.6.x, 2.x or 3.x (or not a version at all: the reader reports that).
std::string unsupported_version_message(std::string_view version);

// Rewrites a 0.x file (is_legacy_file) into the Mitsuba 3 form; its root's version becomes 3.0.0.
void upgrade_legacy_file(XmlFile& file, const LegacyContext& ctx);
// Mitsuba 0.6 renders a scene without an integrator with `direct`, Mitsuba 3 with `path`: the main
// file of a 0.x scene whose files declare no integrator gets 0.6's, written out.
void add_legacy_default_integrator(XmlFile& main);

// Mitsuba 3's rename of pre-2.0 parameter names: a lower-case letter followed by upper-case ones
// gets an underscore and the upper-case run is lowered ("sigmaA" → "sigma_a", "intIOR" → "int_ior").
std::string snake_case(std::string_view name);

}  // namespace volguide
