// The guided distance pdf along a ray, from Python: the bins the renderer's guided distance
// decision builds for the ray's first segment (integrators/guided/walk/distance_bins.h) and the pdf of the
// tabulated or incremental sampler over them (guiding/guided_distance.h).
//
// The segment: the ray from `origin` along `direction` up to the first surface it hits or t_max,
// whichever is nearer (a distance decision never looks past a surface), in the medium the ray
// travels in first (medium_along: the first shape with media along the ray decides, its interior
// if the ray leaves through it, else its exterior; no such shape: the scene's ambient medium, the
// camera's where no shape bounds it).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <optional>

#include "arrays.h"
#include "bindings.h"
#include "handles.h"
#include "volguide/geometry/interaction.h"
#include "volguide/integrators/guided/walk/distance_bins.h"
#include "volguide/guiding/guided_distance.h"
#include "volguide/guiding/inscatter_cache.h"
#include "volguide/guiding/leaf_estimates.h"
#include "volguide/integrators/guided/training/medium_occupancy.h"
#include "volguide/integrators/guided/walk/walk_guide.h"
#include "volguide/vmm/phase_vmm.h"

namespace volguide::python {

namespace {

Vec3f one_vector(const FloatArray& a, const char* name) {
    const std::vector<Vec3f> v = to_vectors(a, name);
    if (v.size() != 1) throw py::value_error(std::string(name) + " must be one 3-vector");
    return v[0];
}

py::dict bins_dict(const std::vector<DistanceBin>& bins) {
    const py::ssize_t n = py::ssize_t(bins.size());
    py::array_t<float> t0(n), t1(n), albedo(n), inscattered(n), L(n), confidence(n), sigma_t({n, py::ssize_t(3)});
    py::array_t<bool> valid(n);
    for (py::ssize_t i = 0; i < n; ++i) {
        const DistanceBin& b = bins[size_t(i)];
        t0.mutable_at(i) = b.t0;
        t1.mutable_at(i) = b.t1;
        albedo.mutable_at(i) = b.albedo;
        inscattered.mutable_at(i) = b.inscattered;
        L.mutable_at(i) = b.L;
        confidence.mutable_at(i) = b.confidence;
        valid.mutable_at(i) = b.valid;
        for (int c = 0; c < 3; ++c) sigma_t.mutable_at(i, c) = b.sigma_t[c];
    }
    py::dict out;
    out["t0"] = t0;
    out["t1"] = t1;
    out["sigma_t"] = sigma_t;
    out["albedo"] = albedo;
    out["inscattered"] = inscattered;
    out["L"] = L;
    out["valid"] = valid;
    out["confidence"] = confidence;
    return out;
}

py::dict distance_pdf(const FieldHandle& h, const FloatArray& origin, const FloatArray& direction, float t_max,
                      std::shared_ptr<SceneHandle> scene, const std::optional<FloatArray>& t, int n,
                      const std::string& sampler, float c_T, float p_max, float filter_A, float distance_merge) {
    if (!scene) scene = h.scene;
    if (!scene) throw py::value_error("distance_pdf needs the scene (the field was not trained on one here)");
    if (!(t_max > 0.f)) throw py::value_error("t_max must be positive");
    if (!(distance_merge >= 0.f) || !std::isfinite(distance_merge))
        throw py::value_error("distance_merge must be finite and >= 0 (0: leaves)");
    if (sampler != "tabulated" && sampler != "incremental")
        throw py::value_error("sampler must be 'tabulated' or 'incremental', got '" + sampler + "'");
    const Scene& s = *scene->scene;
    const Ray ray(Point3f(one_vector(origin, "origin")), normalize(one_vector(direction, "direction")));
    const Medium* medium = medium_along(s, ray, ambient_medium(s));
    if (!medium) throw py::value_error("the ray starts in vacuum: no distance to guide");
    float t_end = t_max;
    SurfaceInteraction si;
    if (s.intersect(Ray(ray.o, ray.d, t_max), si)) t_end = std::min(t_end, si.t);

    // What the walk guide prepares per medium (walk_guide.cpp), with the defaults of
    // WalkGuideSettings: the phase's in-scattering cache, the per-leaf tables, the leaves' extents.
    const WalkGuideSettings defaults;
    const InscatterCache inscatter(*h.field, hg_phase_vmm(medium->phase().mean_cosine()));
    const LeafEstimates estimates(*h.field, inscatter, defaults.estimate_table);
    const std::vector<float> extents = leaf_extents(h.field->tree());
    std::vector<ProxySegment> proxies;
    std::vector<DistanceBin> bins;
    // distance_merge > 0: the walk steps leaf groups (guiding/leaf_groups.h), as the renderer does.
    std::optional<LeafGroups> groups;
    if (distance_merge > 0.f) groups.emplace(h.field->tree(), estimates, extents, distance_merge);
    const BinField field{*h.field, &estimates, groups ? &*groups : nullptr, extents, defaults.max_bin_optical_depth,
                         defaults.leaf_tau_max};
    BinSource source(ray, t_end, *medium, field, proxies);
    DistanceBin bin;
    while (source(bin)) bins.push_back(bin);

    GuidedDistanceSettings settings = defaults.distance_settings;
    settings.c_T = c_T;
    settings.p_max = p_max;
    settings.filter_A = filter_A;
    std::vector<float> ts;
    if (t) {
        const py::array_t<float> a = *t;
        ts.assign(a.data(), a.data() + a.size());
    } else {
        if (n <= 0) throw py::value_error("n must be positive");
        for (int i = 0; i < n; ++i) ts.push_back(t_end * (float(i) + 0.5f) / float(n));
    }
    py::array_t<float> pdf(py::ssize_t(ts.size()));
    float surface = 0.f;
    if (sampler == "tabulated") {
        const TabulatedDistance table(bins, std::nullopt, settings);
        for (size_t i = 0; i < ts.size(); ++i) pdf.mutable_at(py::ssize_t(i)) = table.pdf(ts[i]);
        surface = table.surface_probability();
    } else {
        for (size_t i = 0; i < ts.size(); ++i)
            pdf.mutable_at(py::ssize_t(i)) = incremental_distance_pdf(bins, ts[i], settings);
        surface = incremental_surface_probability(bins, settings);
    }
    py::dict out;
    out["t"] = py::array_t<float>(py::ssize_t(ts.size()), ts.data());
    out["pdf"] = pdf;
    out["surface_probability"] = surface;
    out["t_end"] = t_end;
    out["g"] = medium->phase().mean_cosine();
    out["bins"] = bins_dict(bins);
    return out;
}

}  // namespace

void bind_distance(py::module_& m) {
    py::class_<FieldHandle> field = py::reinterpret_borrow<py::class_<FieldHandle>>(m.attr("Field"));
    field.def("distance_pdf", &distance_pdf, py::arg("origin"), py::arg("direction"), py::arg("t_max"),
              py::kw_only(), py::arg("scene") = py::none(), py::arg("t") = py::none(), py::arg("n") = 256,
              py::arg("sampler") = "tabulated", py::arg("c_T") = GuidedDistanceSettings{}.c_T,
              py::arg("p_max") = GuidedDistanceSettings{}.p_max, py::arg("filter_A") = GuidedDistanceSettings{}.filter_A,
              py::arg("distance_merge") = WalkGuideSettings{}.distance_merge,
              "The guided distance pdf along the ray's first segment (up to the first surface or t_max) in the "
              "medium the ray starts in: a dict with t, pdf (at t, default n midpoints of (0, t_end)), "
              "surface_probability (the mass of reaching t_end), t_end, g (the medium's mean cosine) and the bins "
              "(t0, t1, sigma_t, albedo, inscattered, L, valid, confidence). sampler: tabulated or incremental. "
              "distance_merge > 0: the bins are groups of leaves whose estimates agree (the renderer's "
              "distance_merge parameter).");
}

}  // namespace volguide::python
