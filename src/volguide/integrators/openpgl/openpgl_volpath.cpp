#include "volguide/integrators/openpgl/openpgl_volpath.h"

#include <tbb/task_arena.h>

#include <chrono>

#include "volguide/render/scene.h"

namespace volguide {

OpenPglVolPathIntegrator::OpenPglVolPathIntegrator(const Properties& props)
    : settings_(OpenPglSettings::from(props)), walk_(settings_.walk) {}

void OpenPglVolPathIntegrator::preprocess(const Scene& scene, const PreprocessContext& context) {
    walk_.preprocess(scene, context);
    threads_.clear();
    field_.reset();  // the old device's thread limit ends before the new one's starts
    // The same bounds as guided_volpath's field: the scene's shapes with a small margin.
    field_ = std::make_unique<OpenPglField>(guiding_bounds(scene), tbb::this_task_arena::max_concurrency(),
                                            settings_.max_samples_per_leaf);
    time_budget_ = context.time_budget;
    training_ = settings_.training_spp > 0;
    training_spp_done_ = 0;
    training_seconds_ = 0;
    update_seconds_ = 0;
}

OpenPglThreadState& OpenPglVolPathIntegrator::thread_state() const {
    std::unique_ptr<OpenPglThreadState>& ts = threads_.local();
    if (!ts) ts = std::make_unique<OpenPglThreadState>(&field_->field());
    return *ts;
}

Color3 OpenPglVolPathIntegrator::Li(const Scene& scene, Sampler& sampler, const CameraRay& camera) const {
    OpenPglThreadState& ts = thread_state();
    OpenPglWalkPolicy policy(settings_, ts, *field_);
    if (!training_) return walk_.walk(scene, sampler, camera.ray, &policy);
    ts.recorder.begin_path();
    const Color3 L = walk_.walk(scene, sampler, camera.ray, &policy, &ts.recorder);
    ts.recorder.end_path(*field_);
    return L;
}

void OpenPglVolPathIntegrator::end_pass(const PassReport& pass) {
    if (!training_) return;
    const int spp_done = pass.spp_done;
    const double seconds = pass.seconds;
    const auto start = std::chrono::steady_clock::now();
    field_->update();
    const double update = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    update_seconds_ += update;
    training_spp_done_ = spp_done;
    training_seconds_ = seconds + update;  // job time when the last training update ended
    const bool budget_share_used = time_budget_ > 0 && seconds >= settings_.training_fraction * time_budget_;
    if (spp_done >= settings_.training_spp || budget_share_used) training_ = false;
}

std::vector<std::pair<std::string, double>> OpenPglVolPathIntegrator::statistics() const {
    if (!field_) return {};
    int64_t medium = 0, guided_medium = 0, surface = 0, guided_surface = 0, distance = 0, vsp = 0, vsp_scattered = 0;
    for (const auto& ts : threads_)
        if (ts) {
            medium += ts->medium_vertices;
            guided_medium += ts->guided_medium;
            surface += ts->surface_vertices;
            guided_surface += ts->guided_surface;
            distance += ts->distance_decisions;
            vsp += ts->vsp_decisions;
            vsp_scattered += ts->vsp_scattered;
        }
    auto share = [](int64_t part, int64_t all) { return all > 0 ? double(part) / double(all) : 0.0; };
    std::vector<std::pair<std::string, double>> out = {
        {"openpgl_medium_vertices", double(medium)},
        {"openpgl_guided_medium_fraction", share(guided_medium, medium)},
        {"openpgl_surface_vertices", double(surface)},
        {"openpgl_guided_surface_fraction", share(guided_surface, surface)},
        {"openpgl_training_spp", double(training_spp_done_)},
        {"openpgl_updates", double(field_->updates())},
        {"openpgl_training_samples", double(field_->samples_total())},
        {"openpgl_training_seconds", training_seconds_},
        {"openpgl_update_seconds", update_seconds_}};
    if (settings_.vsp) {  // the distance decisions that used Open PGL's VSP, and how often those scattered
        out.push_back({"openpgl_vsp_decision_fraction", share(vsp, distance)});
        out.push_back({"openpgl_vsp_scatter_fraction", share(vsp_scattered, vsp)});
    }
    return out;
}

std::string OpenPglVolPathIntegrator::to_string() const {
    return "openpgl_volpath[" + settings_.to_string() + "]";
}

}  // namespace volguide
