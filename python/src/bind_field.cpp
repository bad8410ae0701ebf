// The guiding field from Python: train (bind_scene.cpp's train) or load it, then look inside: the
// leaves' bounds, lobes and sample counts as arrays; L~ and L~_i at points; the guided direction
// pdf and its product lobes at a vertex; the pixel estimate the field predicts for a scene.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <optional>

#include "arrays.h"
#include "bindings.h"
#include "handles.h"
#include "interruptible.h"
#include "volguide/core/parallel.h"
#include "volguide/guiding/field_io.h"
#include "volguide/guiding/guided_direction.h"
#include "volguide/integrators/guided/estimates/cache_estimate.h"
#include "volguide/integrators/integrator.h"
#include "volguide/integrators/guided/training/medium_occupancy.h"
#include "volguide/integrators/guided/estimates/pixel_estimate.h"
#include "volguide/media/phase_hg.h"
#include "volguide/vmm/phase_vmm.h"

namespace volguide::python {

namespace {

template <class T>
py::array_t<T> zeros(std::vector<py::ssize_t> shape) {
    py::array_t<T> a(shape);
    std::fill(a.mutable_data(), a.mutable_data() + a.size(), T(0));
    return a;
}

// Lobes of N mixtures as padded arrays: weights (N, K), mu (N, K, 3), kappa (N, K), lobes (N,).
template <class Mixture>
void add_lobes(py::dict& out, const std::string& prefix, const std::vector<const Mixture*>& mixtures) {
    const py::ssize_t n = py::ssize_t(mixtures.size());
    int k_max = 1;
    for (const Mixture* m : mixtures)
        if (m) k_max = std::max(k_max, m->count);
    auto count = zeros<int32_t>({n});
    auto weights = zeros<float>({n, k_max});
    auto mu = zeros<float>({n, k_max, 3});
    auto kappa = zeros<float>({n, k_max});
    auto c = count.mutable_unchecked<1>();
    auto w = weights.mutable_unchecked<2>();
    auto m3 = mu.mutable_unchecked<3>();
    auto k2 = kappa.mutable_unchecked<2>();
    for (py::ssize_t i = 0; i < n; ++i) {
        const Mixture* m = mixtures[size_t(i)];
        if (!m) continue;
        c(i) = m->count;
        for (int k = 0; k < m->count; ++k) {
            w(i, k) = m->weight[k];
            m3(i, k, 0) = m->mu_x[k];
            m3(i, k, 1) = m->mu_y[k];
            m3(i, k, 2) = m->mu_z[k];
            k2(i, k) = m->kappa[k];
        }
    }
    out[py::str(prefix + "lobes")] = count;
    out[py::str(prefix + "weights")] = weights;
    out[py::str(prefix + "mu")] = mu;
    out[py::str(prefix + "kappa")] = kappa;
}

py::dict leaves(const FieldHandle& h) {
    const GuidingField& f = *h.field;
    const auto& ls = f.leaves();
    const py::ssize_t n = py::ssize_t(ls.size());
    auto lo = zeros<float>({n, 3}), hi = zeros<float>({n, 3}), fluence = zeros<float>({n, 3});
    auto samples = zeros<uint32_t>({n});
    auto medium_fraction = zeros<float>({n});
    auto valid = zeros<bool>({n}), valid_indirect = zeros<bool>({n});
    std::vector<const Vmm*> vmm(ls.size()), indirect(ls.size());
    for (py::ssize_t i = 0; i < n; ++i) {
        const GuidingLeaf& leaf = ls[size_t(i)];
        const BBox3f& b = f.tree().leaf_bounds(int(i));
        for (int a = 0; a < 3; ++a) {
            lo.mutable_at(i, a) = b.lo[a];
            hi.mutable_at(i, a) = b.hi[a];
            fluence.mutable_at(i, a) = leaf.fluence[a];
        }
        samples.mutable_at(i) = leaf.samples;
        medium_fraction.mutable_at(i) = leaf.medium_fraction;
        valid.mutable_at(i) = leaf.valid;
        valid_indirect.mutable_at(i) = leaf.valid_indirect;
        vmm[size_t(i)] = leaf.valid ? &leaf.vmm : nullptr;
        indirect[size_t(i)] = leaf.valid_indirect ? &leaf.vmm_indirect : nullptr;
    }
    py::dict out;
    out["lo"] = lo;
    out["hi"] = hi;
    out["fluence"] = fluence;
    out["samples"] = samples;
    out["medium_fraction"] = medium_fraction;
    out["valid"] = valid;
    add_lobes(out, "", vmm);
    out["valid_indirect"] = valid_indirect;
    add_lobes(out, "indirect_", indirect);
    return out;
}

py::array_t<int32_t> leaf_at(const FieldHandle& h, const FloatArray& points) {
    const std::vector<Vec3f> p = to_vectors(points, "points");
    py::array_t<int32_t> out(py::ssize_t(p.size()));
    for (size_t i = 0; i < p.size(); ++i)
        out.mutable_at(py::ssize_t(i)) = h.field->empty() ? -1 : h.field->tree().leaf_at(Point3f(p[i]));
    return out;
}

py::array_t<float> incident(const FieldHandle& h, const FloatArray& points, const FloatArray& directions) {
    std::vector<Vec3f> p = to_vectors(points, "points"), d = to_vectors(directions, "directions");
    broadcast_pair(p, d, "points", "directions");
    std::vector<Color3> out(p.size());
    for (size_t i = 0; i < p.size(); ++i) out[i] = h.field->incident(Point3f(p[i]), normalize(d[i]));
    return colors_to_array(out);
}

InscatterMode inscatter_mode(const std::string& mode) {
    if (mode == "exact") return InscatterMode::Exact;
    if (mode == "a3") return InscatterMode::A3;
    throw py::value_error("mode must be 'exact' or 'a3', got '" + mode + "'");
}

py::array_t<float> inscattered(const FieldHandle& h, const FloatArray& points, const FloatArray& directions, float g,
                               const std::string& mode) {
    std::vector<Vec3f> p = to_vectors(points, "points"), d = to_vectors(directions, "directions");
    broadcast_pair(p, d, "points", "directions");
    const PhaseVmm phase = hg_phase_vmm(g);
    const InscatterMode m = inscatter_mode(mode);
    std::vector<Color3> out(p.size());
    for (size_t i = 0; i < p.size(); ++i) out[i] = h.field->inscattered(Point3f(p[i]), normalize(d[i]), phase, m);
    return colors_to_array(out);
}

DirectionGuiding direction_mode(const std::string& mode) {
    if (mode == "product") return DirectionGuiding::Product;
    if (mode == "incident") return DirectionGuiding::Incident;
    if (mode == "phase") return DirectionGuiding::Phase;
    throw py::value_error("mode must be 'product', 'incident' or 'phase', got '" + mode + "'");
}

Vec3f single_vector(const FloatArray& a, const char* name) {
    const std::vector<Vec3f> v = to_vectors(a, name);
    if (v.size() != 1) throw py::value_error(std::string(name) + " must be one 3-vector");
    return v[0];
}

// The guided direction sampler of a medium vertex at `point` reached travelling along `direction`
// in an HG medium with mean cosine g (wi = -direction).
py::array_t<float> direction_pdf(const FieldHandle& h, const FloatArray& point, const FloatArray& direction, float g,
                                 const FloatArray& wo, const std::string& mode, float phase_prob) {
    const Vec3f x = single_vector(point, "point"), d = normalize(single_vector(direction, "direction"));
    const std::vector<Vec3f> w = to_vectors(wo, "wo");
    const HGPhase phase(g);
    const PhaseVmm phase_vmm = hg_phase_vmm(g);
    const GuidedDirectionSampler sampler(direction_mode(mode), h.field->leaf_at(Point3f(x)), phase, -d, phase_prob,
                                         &phase_vmm);
    py::array_t<float> out(py::ssize_t(w.size()));
    for (size_t i = 0; i < w.size(); ++i) out.mutable_at(py::ssize_t(i)) = sampler.pdf(normalize(w[i]));
    return out;
}

// The product lobes V_L x V_f at a vertex (the leaf's own lobes where the phase is isotropic) and
// the product's integral Z.
py::dict product_lobes(const FieldHandle& h, const FloatArray& point, const FloatArray& direction, float g) {
    const Vec3f x = single_vector(point, "point"), d = normalize(single_vector(direction, "direction"));
    const GuidingLeaf* leaf = h.field->leaf_at(Point3f(x));
    const HGPhase phase(g);
    const PhaseVmm phase_vmm = hg_phase_vmm(g);
    const GuidedDirectionSampler sampler(DirectionGuiding::Product, leaf, phase, -d, 0.f, &phase_vmm);
    py::dict out;
    if (const auto* product = sampler.product()) {
        const auto mixture = product->mixture();
        add_lobes(out, "", std::vector<const decltype(mixture)*>{&mixture});
        out["integral"] = sampler.product_integral();
    } else {
        add_lobes(out, "", std::vector<const Vmm*>{leaf && leaf->valid ? &leaf->vmm : nullptr});
        out["integral"] = leaf && leaf->valid ? 1.0 : 0.0;
    }
    out["guided"] = sampler.guided();
    return out;
}

py::array_t<float> pixel_estimate(const std::shared_ptr<SceneHandle>& scene, const FieldHandle& h, int rays_per_pixel,
                                  uint64_t seed, bool volume_only, std::optional<int> threads) {
    if (rays_per_pixel <= 0) throw py::value_error("rays_per_pixel must be positive");
    PixelEstimateSettings settings;
    settings.rays_per_pixel = rays_per_pixel;
    settings.volume_only = volume_only;
    std::atomic<bool> cancel{false};
    PreprocessContext context;
    context.seed = seed;
    context.cancel = &cancel;
    Image image;
    run_interruptible(
        [&] {
            std::lock_guard lock(scene->jobs);
            tbb::task_arena arena(threads.value_or(0) > 0 ? *threads : tbb::task_arena::automatic);
            arena_execute(arena, [&] {
                // As guided_volpath: a field without medium fractions (format 2) gets them measured
                // here, so that surfaces read the leaves that are mostly medium.
                std::optional<GuidingField> measured;
                if (!h.field->empty() && !h.field->has_medium_fractions()) {
                    measured.emplace(*h.field);
                    measured->set_medium_fractions(
                        medium_fractions(*scene->scene, h.field->tree(), kMediumFractionPoints, seed), false);
                }
                const GuidingField& field = measured ? *measured : *h.field;
                const CacheEstimator estimator(*scene->scene, field);
                image = PixelEstimate::raymarch(*scene->scene, field, estimator, settings, context).image();
            });
        },
        cancel);
    return image_to_array(image);
}

}  // namespace

void bind_field(py::module_& m) {
    py::class_<FieldHandle>(m, "Field", "A guiding field (kd-tree leaves with VMMs of incident radiance and fluence).")
        .def_static(
            "load",
            [](const std::string& path, std::shared_ptr<SceneHandle> scene) {
                return FieldHandle{std::make_shared<const GuidingField>(load_field(path)), std::move(scene)};
            },
            py::arg("path"), py::arg("scene") = py::none(),
            "Loads a field saved by save() or guided_volpath's save_field; `scene` is the default of distance_pdf.")
        .def("save", [](const FieldHandle& h, const std::string& path) { save_field(path, *h.field); }, py::arg("path"))
        .def_property_readonly("leaf_count", [](const FieldHandle& h) { return h.field->leaves().size(); })
        .def_property_readonly("bounds",
                               [](const FieldHandle& h) {
                                   const BBox3f& b = h.field->tree().bounds();
                                   return py::make_tuple(py::make_tuple(b.lo.x, b.lo.y, b.lo.z),
                                                         py::make_tuple(b.hi.x, b.hi.y, b.hi.z));
                               })
        .def_property_readonly("scene", [](const FieldHandle& h) { return h.scene; })
        .def("leaves", &leaves,
             "Per leaf, as arrays over N leaves: lo, hi (N, 3) bounds; fluence (N, 3); samples; medium_fraction "
             "(the share of the leaf inside a medium, -1 if not measured); valid; lobes (lobe "
             "count), weights (N, K), mu (N, K, 3), kappa (N, K) of V_L (zero-padded; zero for invalid leaves); "
             "the same with the prefix indirect_ for the indirect-light VMM.")
        .def("leaf_at", &leaf_at, py::arg("points"), "Leaf index of each point, -1 outside the field.")
        .def("incident", &incident, py::arg("points"), py::arg("directions"),
             "L~(x, w) = Phi V_L(w), (N, 3); w points towards the light; a single point or direction broadcasts.")
        .def("inscattered", &inscattered, py::arg("points"), py::arg("directions"), py::arg("g"),
             py::arg("mode") = "exact",
             "L~_i(x, w) for rays travelling along w in an HG medium of mean cosine g, (N, 3); mode exact or a3.")
        .def("direction_pdf", &direction_pdf, py::arg("point"), py::arg("direction"), py::arg("g"), py::arg("wo"),
             py::kw_only(), py::arg("mode") = "product", py::arg("phase_prob") = 0.f,
             "pdf of guided direction sampling at a vertex reached travelling along `direction`, evaluated at the "
             "new directions wo (N, 3): phase_prob f_HG + (1 - phase_prob) V (V_L x phase for product).")
        .def("product_lobes", &product_lobes, py::arg("point"), py::arg("direction"), py::arg("g"),
             "The product guide V_L x V_f at a vertex: lobes, weights, mu, kappa (one row), integral Z, guided.");
    m.def("pixel_estimate", &pixel_estimate, py::arg("scene"), py::arg("field"), py::kw_only(),
          py::arg("rays_per_pixel") = 4, py::arg("seed") = 0, py::arg("volume_only") = false,
          py::arg("threads") = py::none(),
          "The pixel estimate I the field predicts for the scene's camera (raymarch, pixel_estimate.h), (H, W, 3).");
}

}  // namespace volguide::python
