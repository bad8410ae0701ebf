// replay_sample SCENE.xml X Y SAMPLE SEED [name=value ...]: recomputes one camera sample of a render
// through the render loop's own entry point (camera_sample.h: film_sample draws its stream and film
// position, camera_sample_value its ray, radiance and weight) after the same preprocessing, and
// prints the value the film splats, e.g. to debug the sample `volguide render` reports as the first
// non-finite one. X and Y are film pixels (in the filter's border with sample_border). An integrator
// that learns at the end of every pass (guided_volpath) is first rendered through the passes before
// the sample's own (render_loop's pass_schedule), so that it replays with the state that drew it.
#include <fmt/format.h>

#include <cfenv>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "volguide/integrators/camera_sample.h"
#include "volguide/integrators/integrator.h"
#include "volguide/integrators/render_loop.h"
#include "volguide/render/scene.h"
#include "volguide/render/sensors/rfilters.h"
#include "volguide/scene/loader.h"

namespace {

// The number of samples per pixel rendered before the pass that draws sample `s`.
int samples_before_pass_of(int s) {
    int done = 0;
    for (int n : volguide::pass_schedule(s + 1)) {
        if (done + n > s) break;
        done += n;
    }
    return done;
}

}  // namespace

int main(int argc, char** argv) {
    using namespace volguide;
    if (argc < 6) {
        std::fprintf(stderr, "usage: replay_sample SCENE.xml X Y SAMPLE SEED [name=value ...]\n");
        return 2;
    }
    try {
        LoadOptions load;
        for (int k = 6; k < argc; ++k) {
            std::string d = argv[k];
            size_t eq = d.find('=');
            if (eq == std::string::npos) throw std::runtime_error("expected name=value, got '" + d + "'");
            load.defines[d.substr(0, eq)] = d.substr(eq + 1);
        }
        auto scene = load_scene(argv[1], load);
        const int x = std::atoi(argv[2]), y = std::atoi(argv[3]), s = std::atoi(argv[4]);
        const uint64_t seed = std::strtoull(argv[5], nullptr, 10);
        const Film& film = scene->sensor().film();
        const FilmGrid grid{film.width(), film.height(), film.sample_border() ? filter_border_size(film.filter()) : 0};
        Integrator& integrator = const_cast<Integrator&>(scene->integrator());
        const int before = samples_before_pass_of(s);
        if (before > 0) {
            RenderOptions options;
            options.spp = before;
            options.seed = seed;
            render(*scene, options);
        } else {
            PreprocessContext context;
            context.seed = seed;
            integrator.preprocess(*scene, context);
        }
        // REPLAY_TRAP_FP=1: stop (SIGFPE) at the first invalid operation, to find it in a debugger.
        if (const char* trap = std::getenv("REPLAY_TRAP_FP"); trap && std::string(trap) == "1")
            feenableexcept(FE_INVALID);
        FilmSample sample = film_sample(grid, seed, x, y, uint64_t(s));
        const Color3 L = camera_sample_value(*scene, integrator, sample.film_uv, sample.sampler);
        fmt::print("pixel ({}, {}) sample {} seed {}: L = ({}, {}, {})\n", x, y, s, seed, L.r, L.g, L.b);
        return L.is_finite() ? 0 : 3;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "replay_sample: %s\n", e.what());
        return 1;
    }
}
