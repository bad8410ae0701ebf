#include "volguide/render/sensors/projective_camera.h"

#include <cmath>

#include "volguide/media/medium.h"
#include "volguide/render/sensors/hdrfilm.h"
#include "volguide/render/sensors/sampler_settings.h"

namespace volguide {

namespace {

template <typename T>
std::shared_ptr<T> single_child(const Properties& props, const char* category) {
    auto children = props.children(category);
    if (children.size() > 1) fail(children[1]->loc, "a sensor can only have one <{}>", category);
    if (children.empty()) return nullptr;
    auto typed = std::dynamic_pointer_cast<T>(std::get<ObjectPtr>(children[0]->value));
    if (!typed) fail(children[0]->loc, "the <{}> child of the sensor has the wrong kind", category);
    return typed;
}

}  // namespace

ProjectiveCamera::ProjectiveCamera(const Properties& props) {
    to_world_ = props.get_transform("to_world");
    near_clip_ = props.get_float("near_clip", 1e-2f);
    far_clip_ = props.get_float("far_clip", 1e4f);
    check_clip(&props);
    // Only a thin lens focuses; a pinhole accepts (and has no use for) Mitsuba's focus_distance.
    float focus = props.get_float("focus_distance", far_clip_);
    if (!(focus > 0.f)) props.fail_at("focus_distance", "focus_distance must be positive, got {}", focus);
    // The scene is static (no animated transforms), so the shutter interval cannot change the image.
    float open = props.get_float("shutter_open", 0.f), close = props.get_float("shutter_close", 0.f);
    if (!(open >= 0.f) || !(close >= open))
        props.fail_at(props.has("shutter_close") ? "shutter_close" : "shutter_open",
                      "shutter_close ({}) must not be smaller than shutter_open ({})", close, open);

    film_ = single_child<Film>(props, "film");
    if (!film_) film_ = make_default_film();
    if (auto sampler = single_child<SamplerSettings>(props, "sampler")) {
        sample_count_ = sampler->sample_count;
        seed_ = sampler->seed;
    }
    aspect_ = float(film_->width()) / float(film_->height());
    medium_ = get_object_as<Medium>(props, "medium");  // the medium the camera sits in
}

ProjectiveCamera::ProjectiveCamera(std::shared_ptr<Film> film, const Transform& to_world, float near_clip,
                                   float far_clip) {
    film_ = std::move(film);
    to_world_ = to_world;
    near_clip_ = near_clip;
    far_clip_ = far_clip;
    check_clip(nullptr);
    aspect_ = float(film_->width()) / float(film_->height());
}

void ProjectiveCamera::check_clip(const Properties* props) const {
    auto bad = [&](const char* name, const std::string& msg) {
        if (props) props->fail_at(name, "{}", msg);
        throw InputError({}, msg);
    };
    if (!(near_clip_ > 0.f) || !std::isfinite(near_clip_))
        bad("near_clip", fmt::format("near_clip must be positive and finite, got {}", near_clip_));
    if (!(far_clip_ > near_clip_))
        bad("far_clip", fmt::format("far_clip ({}) must exceed near_clip ({})", far_clip_, near_clip_));
}

}  // namespace volguide
