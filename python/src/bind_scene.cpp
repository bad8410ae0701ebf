// Scenes, integrators and rendering: load_scene, Scene, create_integrator, Integrator, render,
// train, radiance.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <optional>

#include "arrays.h"
#include "bindings.h"
#include "handles.h"
#include "interruptible.h"
#include "volguide/core/parallel.h"
#include "volguide/integrators/guided/guided_volpath.h"
#include "volguide/integrators/render_loop.h"
#include "volguide/render/image_compare.h"
#include "volguide/scene/loader.h"

namespace volguide::python {

namespace {

// A separate random stream for radiance() (camera paths use stream 0).
constexpr uint64_t kRadianceStream = 0x9A1DA7CEull;

// -D values as the loader reads them: Python's True/False as the XML booleans true/false.
std::map<std::string, std::string> defines_from(const py::kwargs& kwargs) {
    std::map<std::string, std::string> defines;
    for (const auto& [key, value] : kwargs) {
        const std::string name = py::str(key);
        if (py::isinstance<py::bool_>(value)) defines[name] = value.cast<bool>() ? "true" : "false";
        else defines[name] = py::str(value);
    }
    return defines;
}

std::shared_ptr<SceneHandle> load(const std::string& path, const py::kwargs& kwargs) {
    auto handle = std::make_shared<SceneHandle>();
    handle->path = path;
    handle->defines = defines_from(kwargs);
    LoadOptions options;
    options.defines = handle->defines;
    py::gil_scoped_release release;
    const auto t0 = std::chrono::steady_clock::now();
    handle->scene = load_scene(path, options);
    handle->load_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return handle;
}

// Parameters of create_integrator as the XML loader would type them.
Properties integrator_properties(const std::string& type, const py::kwargs& kwargs) {
    const SourceLocation here{"<python create_integrator>", 0};
    Properties props("integrator", type, here);
    for (const auto& [key, value] : kwargs) {
        const std::string name = py::str(key);
        if (py::isinstance<py::bool_>(value)) props.set(name, "boolean", value.cast<bool>(), here);
        else if (py::isinstance<py::int_>(value)) props.set(name, "integer", value.cast<int64_t>(), here);
        else if (py::isinstance<py::float_>(value)) props.set(name, "float", value.cast<double>(), here);
        else if (py::isinstance<py::str>(value)) props.set(name, "string", value.cast<std::string>(), here);
        else throw py::type_error("create_integrator: parameter '" + name + "' must be a bool, int, float or str");
    }
    return props;
}

IntegratorHandle create(const std::string& type, const py::kwargs& kwargs) {
    const Properties props = integrator_properties(type, kwargs);
    auto integrator = std::dynamic_pointer_cast<Integrator>(create_object("integrator", props));
    props.check_all_used();
    return {std::move(integrator), nullptr};
}

IntegratorHandle scene_integrator(const std::shared_ptr<SceneHandle>& scene) {
    // Aliasing: the integrator's lifetime is the scene handle's.
    Integrator& own = const_cast<Integrator&>(scene->scene->integrator());
    return {std::shared_ptr<Integrator>(scene, &own), scene};
}

Integrator& integrator_of(const std::shared_ptr<SceneHandle>& scene, const std::optional<IntegratorHandle>& chosen) {
    return chosen ? *chosen->integrator : const_cast<Integrator&>(scene->scene->integrator());
}

// One point of the convergence curve against a reference (as the CLI's --reference records it).
struct ConvergencePoint {
    int spp = 0;
    double seconds = 0;
    ImageDiff diff;
};

py::list convergence_list(const std::vector<ConvergencePoint>& points) {
    py::list out;
    for (const ConvergencePoint& p : points) {
        py::dict d = image_diff_dict(p.diff);
        d["spp"] = p.spp;
        d["seconds"] = p.seconds;
        out.append(d);
    }
    return out;
}

py::dict counters(const Integrator& integrator) {
    py::dict out;
    for (const auto& [name, value] : integrator.statistics()) out[py::str(name)] = value;
    return out;
}

// The content of the CLI's --stats file (apps/volguide/cmd_render.cpp) that a Python render has.
py::dict stats_dict(const SceneHandle& scene, const RenderResult& r, const RenderOptions& options,
                    const Integrator& integrator) {
    const RenderStats& s = r.stats;
    py::dict j;
    j["scene"] = scene.path;
    j["defines"] = scene.defines;
    j["width"] = r.mean.width;
    j["height"] = r.mean.height;
    j["spp"] = r.spp;
    j["spp_requested"] = options.spp;
    j["time_budget"] = options.time_budget;
    j["seed"] = s.seed;
    j["threads"] = s.threads;
    j["passes"] = s.passes;
    j["samples"] = s.samples;
    j["discarded_samples"] = s.discarded_samples;
    j["nonfinite_samples"] = s.nonfinite_samples;
    if (s.first_nonfinite) {
        py::dict at;
        at["x"] = s.first_nonfinite->x;
        at["y"] = s.first_nonfinite->y;
        at["sample"] = s.first_nonfinite->sample;
        j["first_nonfinite"] = at;
    }
    j["cancelled"] = s.cancelled;
    j["time_limited"] = s.time_limited;
    py::dict time;
    time["load"] = scene.load_seconds;
    time["preprocess"] = s.preprocess_seconds;
    time["render"] = s.render_seconds;
    time["total"] = s.total_seconds;
    time["total_with_load"] = scene.load_seconds + s.total_seconds;
    j["time"] = time;
    j["integrator"] = counters(integrator);
    return j;
}

void check_positive(const char* name, std::optional<double> value) {
    if (value && !(*value > 0 && std::isfinite(*value)))
        throw py::value_error(std::string(name) + " must be positive");
}

py::tuple render_scene(const std::shared_ptr<SceneHandle>& scene, std::optional<int> spp, std::optional<double> time,
                       uint64_t seed, std::optional<int> threads, const std::optional<IntegratorHandle>& chosen,
                       const std::optional<FloatArray>& reference) {
    check_positive("spp", spp ? std::optional<double>(*spp) : std::nullopt);
    check_positive("time", time);
    check_positive("threads", threads ? std::optional<double>(*threads) : std::nullopt);
    Integrator& integrator = integrator_of(scene, chosen);
    std::atomic<bool> cancel{false};
    RenderOptions options;
    options.spp = spp.value_or(0);
    options.time_budget = time.value_or(0.0);
    options.seed = seed;
    options.threads = threads.value_or(0);
    options.cancel = &cancel;
    // Convergence against the reference at 1, 2, 4, ... spp and at the end (the CLI's --reference).
    std::optional<Image> ref;
    if (reference) {
        ref = array_to_image(*reference, "reference");
        const Film& film = scene->scene->sensor().film();
        if (ref->width != film.width() || ref->height != film.height())
            throw py::value_error("reference size differs from the film's");
    }
    std::vector<ConvergencePoint> convergence;
    if (ref)
        options.on_pass = [&](int spp, double seconds, const Image& mean) {
            if ((spp & (spp - 1)) == 0) convergence.push_back({spp, seconds, compare_images(mean, *ref)});
        };
    RenderResult result;
    run_interruptible(
        [&] {
            std::lock_guard lock(scene->jobs);
            result = render(*scene->scene, integrator, options);
        },
        cancel);
    py::dict stats = stats_dict(*scene, result, options, integrator);
    if (ref && result.spp > 0) {
        const ImageDiff final_diff = compare_images(result.mean, *ref);
        if (convergence.empty() || convergence.back().spp != result.spp)
            convergence.push_back({result.spp, result.stats.total_seconds, final_diff});
        stats["reference"] = image_diff_dict(final_diff);
        stats["convergence"] = convergence_list(convergence);
    }
    return py::make_tuple(image_to_array(result.mean), stats);
}

// Runs a guided_volpath integrator's preprocessing (training or loading its field, the pixel
// estimate) without rendering.
FieldHandle train(const std::shared_ptr<SceneHandle>& scene, const std::optional<IntegratorHandle>& chosen,
                  uint64_t seed, std::optional<int> threads, std::optional<double> time) {
    check_positive("time", time);
    auto* guided = dynamic_cast<GuidedVolPathIntegrator*>(&integrator_of(scene, chosen));
    if (!guided) throw py::value_error("train: the integrator is not guided_volpath (nothing to train)");
    std::atomic<bool> cancel{false};
    PreprocessContext context;
    context.seed = seed;
    context.time_budget = time.value_or(0.0);
    context.cancel = &cancel;
    run_interruptible(
        [&] {
            std::lock_guard lock(scene->jobs);
            tbb::task_arena arena(threads.value_or(0) > 0 ? *threads : tbb::task_arena::automatic);
            arena_execute(arena, [&] { guided->preprocess(*scene->scene, context); });
        },
        cancel);
    return {std::make_shared<const GuidingField>(guided->field()), scene};
}

// The mean of `spp` radiance samples along each ray (origin, direction), as a camera ray would
// get them: the path starts in the sensor's medium.
py::array_t<float> radiance(const std::shared_ptr<SceneHandle>& scene, const FloatArray& origins,
                            const FloatArray& directions, int spp, uint64_t seed, std::optional<int> threads,
                            const std::optional<IntegratorHandle>& chosen) {
    if (spp <= 0) throw py::value_error("spp must be positive");
    std::vector<Vec3f> o = to_vectors(origins, "origins"), d = to_vectors(directions, "directions");
    broadcast_pair(o, d, "origins", "directions");
    const Integrator& integrator = integrator_of(scene, chosen);
    std::vector<Color3> out(o.size(), Color3(0.f));
    std::atomic<bool> cancel{false};
    run_interruptible(
        [&] {
            std::lock_guard lock(scene->jobs);
            tbb::task_arena arena(threads.value_or(0) > 0 ? *threads : tbb::task_arena::automatic);
            arena_execute(arena, [&] {
                parallel_for(size_t(0), o.size(), [&](size_t i) {
                    if (cancel.load(std::memory_order_relaxed)) return;
                    // A ray of no pixel: guided RR/splitting compares with the film centre's pixel
                    // estimate (any value keeps the estimate unbiased; it only shapes the splitting).
                    const CameraRay camera_ray{Ray(o[i], normalize(d[i])), Point2f(0.5f, 0.5f)};
                    Color3 sum(0.f);
                    for (int k = 0; k < spp; ++k) {
                        Sampler sampler(seed, i, uint64_t(k), kRadianceStream);
                        sum += integrator.Li(*scene->scene, sampler, camera_ray);
                    }
                    out[i] = sum / float(spp);
                });
            });
        },
        cancel);
    return colors_to_array(out);
}

}  // namespace

void bind_scene(py::module_& m) {
    py::class_<SceneHandle, std::shared_ptr<SceneHandle>>(m, "Scene", "A loaded scene (volguide.load_scene).")
        .def_readonly("path", &SceneHandle::path)
        .def_readonly("defines", &SceneHandle::defines)
        .def_readonly("load_seconds", &SceneHandle::load_seconds)
        .def_property_readonly("width", [](const SceneHandle& s) { return s.scene->sensor().film().width(); })
        .def_property_readonly("height", [](const SceneHandle& s) { return s.scene->sensor().film().height(); })
        .def_property_readonly("bounds",
                               [](const SceneHandle& s) {
                                   const BBox3f& b = s.scene->bbox();
                                   return py::make_tuple(py::make_tuple(b.lo.x, b.lo.y, b.lo.z),
                                                         py::make_tuple(b.hi.x, b.hi.y, b.hi.z));
                               })
        .def_property_readonly("integrator", &scene_integrator, "The scene's own integrator (from its XML).")
        .def("__repr__", [](const SceneHandle& s) {
            return "<volguide.Scene '" + s.path + "' " + std::to_string(s.scene->sensor().film().width()) + "x" +
                   std::to_string(s.scene->sensor().film().height()) + ">";
        });

    py::class_<IntegratorHandle>(m, "Integrator", "An integrator: a scene's own or from create_integrator.")
        .def("statistics", [](const IntegratorHandle& h) { return counters(*h.integrator); },
             "Named counters of the last render (the --stats 'integrator' block).")
        .def_property_readonly("is_guided",
                               [](const IntegratorHandle& h) {
                                   return dynamic_cast<const GuidedVolPathIntegrator*>(h.integrator.get()) != nullptr;
                               })
        .def_property_readonly(
            "field",
            [](const IntegratorHandle& h) -> std::optional<FieldHandle> {
                auto* g = dynamic_cast<const GuidedVolPathIntegrator*>(h.integrator.get());
                if (!g || g->field().empty()) return std::nullopt;
                return FieldHandle{std::make_shared<const GuidingField>(g->field()), h.owner};
            },
            "A copy of the field of the last training (guided_volpath), or None.")
        .def_property_readonly(
            "pixel_estimate",
            [](const IntegratorHandle& h) -> std::optional<py::array_t<float>> {
                auto* g = dynamic_cast<const GuidedVolPathIntegrator*>(h.integrator.get());
                if (!g || g->pixel_estimate().empty()) return std::nullopt;
                return image_to_array(g->pixel_estimate().image());
            },
            "The pixel estimate I of guided RR/splitting of the last training, (H, W, 3) before its floor, or None.")
        .def("__repr__", [](const IntegratorHandle& h) { return "<volguide.Integrator " + h.integrator->to_string() + ">"; });

    m.def("load_scene", &load, py::arg("path"),
          "Loads a Mitsuba 3 XML scene; keyword arguments are -D overrides of its <default> values.");
    m.def("create_integrator", &create, py::arg("type"),
          "An integrator of the XML type `type` (volpath, guided_volpath, ...); keyword arguments are its "
          "parameters (bool -> boolean, int -> integer, float -> float, str -> string).");
    m.def("render", &render_scene, py::arg("scene"), py::kw_only(), py::arg("spp") = py::none(),
          py::arg("time") = py::none(), py::arg("seed") = 0, py::arg("threads") = py::none(),
          py::arg("integrator") = py::none(), py::arg("reference") = py::none(),
          "Renders the scene; returns (image, stats): a float32 (H, W, 3) array and the --stats dict "
          "(with a reference image: its 'reference' relMSEs and the 'convergence' curve at 1, 2, 4, ... spp). "
          "Releases the GIL; Ctrl-C stops the render and raises KeyboardInterrupt.");
    m.def("train", &train, py::arg("scene"), py::kw_only(), py::arg("integrator") = py::none(), py::arg("seed") = 0,
          py::arg("threads") = py::none(), py::arg("time") = py::none(),
          "Runs a guided_volpath integrator's preprocessing (train or load the field) and returns the Field.");
    m.def("radiance", &radiance, py::arg("scene"), py::arg("origins"), py::arg("directions"), py::kw_only(),
          py::arg("spp") = 16, py::arg("seed") = 0, py::arg("threads") = py::none(),
          py::arg("integrator") = py::none(),
          "Mean radiance arriving at each origin from each direction, (N, 3): `spp` paths of the integrator "
          "along the ray, which starts in the sensor's medium as a camera ray does.");
}

}  // namespace volguide::python
