// Accel throughput (single thread): rays/s of closest-hit and occlusion queries on a generated
// ~100k-triangle mesh (a bumpy lat-long sphere) plus one analytic sphere.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <vector>

#include "volguide/core/sampler.h"
#include "volguide/core/warp.h"
#include "volguide/geometry/accel.h"
#include "volguide/geometry/shapes/mesh_shape.h"
#include "volguide/scene/factories.h"

using namespace volguide;

namespace {

TriangleMesh bumpy_sphere(int rings, int segments) {
    TriangleMesh m;
    for (int i = 0; i <= rings; ++i)
        for (int j = 0; j < segments; ++j) {
            float theta = Pi * float(i) / float(rings), phi = 2.f * Pi * float(j) / float(segments);
            float r = 1.f + 0.05f * std::sin(7.f * theta) * std::cos(11.f * phi);
            m.positions.push_back(spherical_direction(std::sin(theta), std::cos(theta), phi) * r);
        }
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            uint32_t a = uint32_t(i * segments + j), b = uint32_t(i * segments + (j + 1) % segments);
            uint32_t c = a + uint32_t(segments), d = b + uint32_t(segments);
            m.indices.insert(m.indices.end(), {a, c, b, b, c, d});
        }
    return m;
}

struct BenchScene {
    std::shared_ptr<Shape> mesh, sphere;
    std::unique_ptr<Accel> accel;
    std::vector<Ray> rays;
    BenchScene() {
        Properties props("shape", "generated", {"bench", 0});
        mesh =
            std::make_shared<MeshShape>(props, bumpy_sphere(158, 316), MeshOptions{}, "bumpy_sphere", false);
        Properties sp("shape", "sphere", {"bench", 0});
        sp.set("center", "point", Vec3f(2.f, 0.f, 0.f), {"bench", 0});
        sp.set("radius", "float", 0.5, {"bench", 0});
        sphere = std::dynamic_pointer_cast<Shape>(create_shape(sp));
        accel = std::make_unique<Accel>(std::vector<const Shape*>{mesh.get(), sphere.get()});
        // Rays from a sphere of radius 4 towards random points in the central region.
        for (uint64_t i = 0; i < (1u << 16); ++i) {
            Sampler s(3, 0, i);
            Point3f o = warp::square_to_uniform_sphere(s.next_2d()) * 4.f;
            Point3f target = (Vec3f(s.next_1d(), s.next_1d(), s.next_1d()) - Vec3f(0.5f)) * 3.f;
            rays.emplace_back(o, normalize(target - o));
        }
    }
};

BenchScene& scene() {
    static BenchScene s;
    return s;
}

void BM_Intersect(benchmark::State& state) {
    BenchScene& s = scene();
    size_t i = 0, hits = 0;
    for (auto _ : state) {
        SurfaceInteraction si;
        hits += s.accel->intersect(s.rays[i++ & (s.rays.size() - 1)], si);
        benchmark::DoNotOptimize(si);
    }
    state.SetItemsProcessed(int64_t(state.iterations()));
    state.counters["hit_fraction"] = double(hits) / double(std::max<size_t>(state.iterations(), 1));
    state.counters["triangles"] = double(s.mesh->triangle_mesh()->triangle_count());
}
BENCHMARK(BM_Intersect);

void BM_Occluded(benchmark::State& state) {
    BenchScene& s = scene();
    size_t i = 0, hits = 0;
    for (auto _ : state) hits += s.accel->occluded(s.rays[i++ & (s.rays.size() - 1)]);
    state.SetItemsProcessed(int64_t(state.iterations()));
    state.counters["hit_fraction"] = double(hits) / double(std::max<size_t>(state.iterations(), 1));
}
BENCHMARK(BM_Occluded);

void BM_Build(benchmark::State& state) {
    BenchScene& s = scene();
    for (auto _ : state) {
        Accel accel({s.mesh.get(), s.sphere.get()});
        benchmark::DoNotOptimize(&accel);
    }
}
BENCHMARK(BM_Build)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
