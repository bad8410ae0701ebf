// replay_sample SCENE.xml X Y SAMPLE SEED [name=value ...]: recomputes one camera sample of a render
// exactly as the render loop draws it (Sampler(seed, pixel index, sample), the same film position and
// camera ray) and prints its radiance, e.g. to debug the sample `volguide render` reports as the first
// non-finite one. Films with sample_border are not supported (the pixel index would include the border).
#include <fmt/format.h>

#include <cfenv>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "volguide/core/sampler.h"
#include "volguide/integrators/integrator.h"
#include "volguide/render/scene.h"
#include "volguide/scene/loader.h"

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
        if (film.sample_border()) throw std::runtime_error("films with sample_border are not supported");
        Integrator& integrator = const_cast<Integrator&>(scene->integrator());
        PreprocessContext context;
        context.seed = seed;
        integrator.preprocess(*scene, context);
        // REPLAY_TRAP_FP=1: stop (SIGFPE) at the first invalid operation, to find it in a debugger.
        if (const char* trap = std::getenv("REPLAY_TRAP_FP"); trap && std::string(trap) == "1")
            feenableexcept(FE_INVALID);
        Sampler sampler(seed, uint64_t(y) * film.width() + uint64_t(x), uint64_t(s));
        Vec2f u = sampler.next_2d();
        Point2f uv((float(x) + u.x) / float(film.width()), (float(y) + u.y) / float(film.height()));
        auto [ray, weight] = scene->sensor().sample_ray(uv, Point2f(0.5f, 0.5f));
        Color3 L = weight * integrator.Li(*scene, sampler, ray);
        fmt::print("pixel ({}, {}) sample {} seed {}: L = ({}, {}, {})\n", x, y, s, seed, L.r, L.g, L.b);
        return L.is_finite() ? 0 : 3;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "replay_sample: %s\n", e.what());
        return 1;
    }
}
