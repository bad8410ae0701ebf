// Guiding field costs (issue 6):
//  - PhotonPass: photons/s of the pre-pass on the bundled demo (fog room, sun through a window);
//  - FieldBuild: kd-tree + per-leaf EM fit (8 lobes) of the samples those photons deposited,
//    reported per leaf; TreeBuild/{threads}/{concurrent}: the kd-tree alone, sequential (0) or with
//    large subtrees' halves built concurrently (1), in an arena of 1 or 2 threads;
//  - Incident / Inscattered{Exact,A3}: one query of L~ and L~_i at a random point and direction;
//  - InscatteredA3Prepared: the same A3 query through an InscatterCache prepared for the phase
//    (and InscatterCachePrepare: the preparation itself, with the cache's bytes per leaf);
//  - memory per leaf (bytes of GuidingLeaf plus its tree nodes) as a counter;
//  - Distance{Incremental,Tabulated}/{early,late,late chromatic}: one guided distance sample
//    (docs/theory.md §7.3 vs §7.2, default settings) on a 20-bin ray whose in-scattered radiance sits in
//    the first / last three bins, grey sigma_t (/0, /1) or chromatic (/2), bins handed out from
//    memory (the scene walk's cost is not included); `steps` is the mean number of bins the
//    incremental sampler pulled (the tabulated one always reads 20).
//  - GuidedDirection{Construct,Sample,Pdf}: the directional sampler per vertex (8-lobe leaf x HG
//    g = 0.6, 3 phase lobes, prepared phase VMM; "/unprepared" looks the phase VMM up per vertex).
//  - DistanceQuery/{0,30,50}: one whole guided distance decision as the renderer makes it (BinSource
//    over the demo field's leaves, its 16x16 estimate tables, a homogeneous grey medium of the demo's
//    fog density, the incremental sampler, default settings) from a random point in a random
//    direction; the argument is distance_merge x 100 (0: leaves; else LeafGroups). Counters:
//    `bins` per query and `leaf_groups` (0: leaves).
//  - SegmentDecision/{0,1,2,3}: one distance decision from a medium vertex of known leaf in the demo's
//    homogeneous fog: free flight, distance="vsp" (one lookup per segment; vsp_equiangular 0), the
//    incremental bins, distance="vsp_product" (vsp plus 4 candidates' point lookups when it scatters);
//  - SegmentDecisionEquiangular/{0,1,2}: the same from random points of bench/scenes/foglamp.xml's fog
//    (a small spherical lamp; its own 1 M-photon field): free flight, distance="vsp", distance="vsp"
//    with vsp_equiangular 0.5 (a light sample per scatter, the mixture's density); counters
//    `scattered` and `equiangular` (the fraction of scatters drawn from the mixture);
//  - LeafTableLookup: one bin's read of L~_i and L~ from a leaf's 16x16 table (LeafEstimates::lookup,
//    the ray's direction prepared once), random leaves of the demo field;
//  - RouletteEstimate: the E[X] lookup of guided RR / splitting at a medium vertex
//    (GuidedVertex::estimate at the distance stage: init, leaf descent + table lookup) at random
//    points of the demo's fog;
//  - GuidedVertex/{0,1}: one medium vertex's object as the walk asks it (init, the distance-stage
//    estimate, the next segment's scatter probability; 1: with the direction mixture built between),
//    counters `descents_per_vertex`, `products_per_vertex`;
//  - LeafWalk{Cursor,Traverse}/{2000,50000}: the leaves crossed by a random ray through a kd-tree of
//    the demo's photon positions split to ~2000 leaves (a benchmark scene's field) or ~50000, by the rope
//    cursor the distance sampler uses and by the stack traversal; time per ray, `time_per_leaf`
//    counter (leaves/ray is the `leaves` counter; both walks yield the same leaves).
//  - Sized{Distance,Direction,LeafAt} (issue 39 deliverable 2): a guided decision's cost against the
//    field's size, on demo-photon fields (4 M photons) of about 1 k, 4 k, 16 k and 64 k leaves (the last
//    argument; `leaves` is the count reached), each queried at 2^18 random points of the fog with random
//    directions, so that at 64 k leaves a query reads its leaf from memory as a render's scattered vertices
//    do. SizedDistance/{0,1,2}/L: one distance decision per segment from a vertex of known leaf (as
//    SegmentDecision): vsp, vsp_product, the incremental bins (their cost grows with the leaves crossed:
//    `lookups`). SizedDirection/L: one direction decision (direction="product") with its leaf lookup
//    (init, descent, leaf VMM x phase product, one sample; `descents` per vertex). SizedLeafAt/L: the
//    descent alone. Counters `depth`, `valid` (fraction of fitted leaves), `lobes` (per valid leaf).
//   cmake --build build --target bench_guiding && build/bench_guiding
#include <limits>
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>
#include <vector>

#include "volguide/core/parallel.h"
#include "volguide/core/sampler.h"
#include "volguide/core/warp.h"
#include "volguide/guiding/leaf_groups.h"
#include "volguide/guiding/guided_distance.h"
#include "volguide/guiding/guided_direction.h"
#include "volguide/guiding/inscatter_cache.h"
#include "volguide/integrators/guided/walk/distance_bins.h"
#include "volguide/integrators/guided/walk/guided_vertex.h"
#include "volguide/integrators/guided/guided_volpath.h"
#include "volguide/integrators/guided/walk/walk_guide.h"
#include "volguide/integrators/guided/training/photon_pass.h"
#include "volguide/media/homogeneous.h"
#include "volguide/media/phase_hg.h"
#include "volguide/media/phase_isotropic.h"
#include "volguide/render/scene.h"
#include "volguide/scene/loader.h"

using namespace volguide;

namespace {

// A distance decision that is not a camera segment's (no pixel buffer P_G).
constexpr float kNoCameraBuffer = std::numeric_limits<float>::quiet_NaN();

constexpr int64_t kPhotons = 1000000;

Scene& demo_scene() {
    static std::unique_ptr<Scene> scene =
        load_scene(std::string(VOLGUIDE_SOURCE_DIR) + "/scenes/demo/light-shafts.xml");
    return *scene;
}

const PhotonPassResult& demo_photons() {
    static PhotonPassResult r = [] {
        PhotonPassSettings ps;
        ps.photons = kPhotons;
        return trace_photons(demo_scene(), ps, PreprocessContext{});
    }();
    return r;
}

const GuidingField& demo_field() {
    static GuidingField f = GuidingField::build(guiding_bounds(demo_scene()), demo_photons().samples);
    return f;
}

// The demo scene's fog: the first shape's interior medium, else the sensor's (null: none).
const Medium* demo_medium() {
    const Scene& scene = demo_scene();
    for (const auto& shape : scene.shapes())
        if (const Medium* m = shape->interior_medium()) return m;
    return scene.sensor().medium();
}

// The demo's photon positions split into ~2000 leaves (a benchmark scene's field; its tree fits in
// the L2 cache) or ~50000 (a 50 M-photon field's size; it does not).
SpatialTree make_walk_tree(int leaves) {
    std::vector<Point3f> points;
    for (const RadianceSample& r : demo_photons().samples) points.push_back(r.position);
    SpatialTreeSettings settings;
    settings.max_samples = std::max(1, int(points.size()) / leaves);
    return SpatialTree::build(guiding_bounds(demo_scene()), points, settings);
}
const SpatialTree& walk_tree(int leaves = 2000) {
    if (leaves == 2000) {
        static const SpatialTree small = make_walk_tree(2000);
        return small;
    }
    if (leaves != 50000) throw std::invalid_argument("walk_tree: 2000 or 50000 leaves");
    static const SpatialTree large = make_walk_tree(50000);  // ~73,000 leaves (split at points/50000)
    return large;
}

template <bool Cursor>
void BM_LeafWalk(benchmark::State& state) {
    const SpatialTree& tree = walk_tree(int(state.range(0)));
    const BBox3f b = tree.bounds();
    std::vector<Ray> rays;
    for (int i = 0; i < 4096; ++i) {
        Sampler s(7, 0, uint64_t(i));
        const Vec3f e = b.extents();
        rays.emplace_back(b.lo + Vec3f(e.x * s.next_1d(), e.y * s.next_1d(), e.z * s.next_1d()),
                          warp::square_to_uniform_sphere(s.next_2d()));
    }
    size_t i = 0;
    int64_t leaves = 0;
    for (auto _ : state) {
        const Ray& ray = rays[i++ & 4095];
        float length = 0.f;
        if constexpr (Cursor) {
            SpatialTree::RayCursor cursor(tree, ray, 0.f, Infinity);
            int leaf;
            float t0, t1;
            while (cursor.next(leaf, t0, t1)) length += t1 - t0, ++leaves;
        } else {
            tree.traverse(ray, 0.f, Infinity, [&](int, float t0, float t1) {
                length += t1 - t0;
                ++leaves;
                return true;
            });
        }
        benchmark::DoNotOptimize(length);
    }
    state.counters["leaf_count"] = double(tree.leaf_count());
    state.counters["leaves"] = benchmark::Counter(double(leaves), benchmark::Counter::kAvgIterations);
    // Seconds per leaf crossed (printed with an SI prefix: 57n = 57 ns).
    state.counters["time_per_leaf"] =
        benchmark::Counter(double(leaves), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_PhotonPass(benchmark::State& state) {
    PhotonPassSettings ps;
    ps.photons = kPhotons;
    int64_t samples = 0;
    for (auto _ : state) samples = int64_t(trace_photons(demo_scene(), ps, PreprocessContext{}).samples.size());
    state.counters["photons/s"] = benchmark::Counter(double(kPhotons), benchmark::Counter::kIsIterationInvariantRate);
    state.counters["deposits_per_photon"] = double(samples) / double(kPhotons);
}

void BM_FieldBuild(benchmark::State& state) {
    const auto& samples = demo_photons().samples;
    int leaves = 0;
    for (auto _ : state) {
        GuidingField f = GuidingField::build(guiding_bounds(demo_scene()), samples);
        leaves = f.tree().leaf_count();
        benchmark::DoNotOptimize(f);
    }
    state.counters["leaves"] = leaves;
    state.counters["s_per_leaf"] =
        benchmark::Counter(double(leaves), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
    state.counters["bytes_per_leaf"] =
        double(sizeof(GuidingLeaf)) + double(sizeof(SpatialTree::Node)) * 2.0 + double(sizeof(BBox3f));
}

// The kd-tree alone over the demo's photon positions (default leaf_samples), in an arena of
// state.range(0) threads; state.range(1) = 0 builds sequentially (parallel_min_samples above the
// sample count), 1 lets subtrees of >= 2^15 samples build their halves concurrently (the default).
void BM_TreeBuild(benchmark::State& state) {
    std::vector<Point3f> points;
    for (const RadianceSample& r : demo_photons().samples) points.push_back(r.position);
    SpatialTreeSettings settings;
    if (state.range(1) == 0) settings.parallel_min_samples = points.size() + 1;
    tbb::task_arena arena(int(state.range(0)));
    int leaves = 0;
    for (auto _ : state) {
        const SpatialTree tree =
            arena_execute(arena, [&] { return SpatialTree::build(guiding_bounds(demo_scene()), points, settings); });
        leaves = tree.leaf_count();
        benchmark::DoNotOptimize(tree);
    }
    state.counters["leaves"] = leaves;
    state.counters["samples"] = double(points.size());
}

template <int Mode>
void BM_Query(benchmark::State& state) {
    const GuidingField& field = demo_field();
    const BBox3f b = field.tree().bounds();
    const PhaseVmm phase = hg_phase_vmm(0.6f);
    std::vector<std::pair<Point3f, Vec3f>> queries;
    for (int i = 0; i < 4096; ++i) {
        Sampler s(5, 0, uint64_t(i));
        const Vec3f e = b.extents();
        queries.push_back({b.lo + Vec3f(e.x * s.next_1d(), e.y * s.next_1d(), e.z * s.next_1d()),
                           warp::square_to_uniform_sphere(s.next_2d())});
    }
    const InscatterCache cache = Mode == 3 ? InscatterCache(field, phase) : InscatterCache();
    size_t i = 0;
    for (auto _ : state) {
        const auto& [x, w] = queries[i++ & 4095];
        Color3 v = Mode == 0   ? field.incident(x, w)
                   : Mode == 1 ? field.inscattered(x, w, phase, InscatterMode::Exact)
                   : Mode == 2 ? field.inscattered(x, w, phase, InscatterMode::A3)
                               : cache.inscattered(x, w);
        benchmark::DoNotOptimize(v);
    }
}

void BM_InscatterCachePrepare(benchmark::State& state) {
    const GuidingField& field = demo_field();
    const PhaseVmm phase = hg_phase_vmm(0.6f);
    size_t bytes = 0;
    for (auto _ : state) {
        InscatterCache cache(field, phase);
        bytes = cache.memory_bytes();
        benchmark::DoNotOptimize(cache);
    }
    state.counters["leaves"] = double(field.leaves().size());
    state.counters["bytes_per_leaf"] = double(bytes) / double(field.leaves().size());
}

// 20 bins of length 0.5, sigma_t = 0.3, albedo 0.8; L_i = 5 in three bins (early: 0-2, late: 17-19),
// 0.01 elsewhere; L consistent with them (exact VRE over the bins), a dim surface at the end.
// `chromatic`: sigma_t = (0.28, 0.3, 0.32) instead (the benchmark scenes' fogs are all chromatic).
std::vector<DistanceBin> distance_bins(bool late, bool chromatic = false) {
    std::vector<DistanceBin> bins(20);
    const Color3 sigma_t = chromatic ? Color3(0.28f, 0.3f, 0.32f) : Color3(0.3f);
    for (int k = 0; k < 20; ++k) {
        const bool lit = late ? k >= 17 : k < 3;
        bins[size_t(k)] = {0.5f * float(k), 0.5f * float(k + 1), sigma_t, 0.8f, lit ? 5.f : 0.01f, 0.f, true};
    }
    float L = 0.05f;
    for (int k = 19; k >= 0; --k) {
        DistanceBin& b = bins[size_t(k)];
        const float T = std::exp(-0.3f * 0.5f);
        L = b.albedo * (1.f - T) * b.inscattered + T * L;
        b.L = L;
    }
    return bins;
}

template <bool Tabulated>
void BM_Distance(benchmark::State& state) {
    const std::vector<DistanceBin> bins = distance_bins(state.range(0) >= 1, state.range(0) == 2);
    const GuidedDistanceSettings settings;
    uint64_t i = 0, steps = 0;
    for (auto _ : state) {
        Sampler rng(3, 0, i++);
        DistanceSample d;
        if constexpr (Tabulated) {
            d = TabulatedDistance(bins, std::nullopt, settings).sample(rng);
        } else {
            size_t next = 0;
            d = sample_incremental_distance(
                [&](DistanceBin& b) {
                    if (next == bins.size()) return false;
                    b = bins[next++];
                    return true;
                },
                rng, settings);
        }
        steps += uint64_t(d.steps);
        benchmark::DoNotOptimize(d);
    }
    state.counters["steps"] = double(steps) / double(std::max<uint64_t>(i, 1));
    state.SetLabel(state.range(0) == 2 ? "late chromatic" : state.range(0) == 1 ? "late" : "early");
}

void BM_DistanceQuery(benchmark::State& state) {
    const GuidingField& field = demo_field();
    const InscatterCache cache(field, hg_phase_vmm(0.f));
    const LeafEstimates estimates(field, cache, 16);
    const std::vector<float> extents = leaf_extents(field.tree());
    const float merge = float(state.range(0)) / 100.f;
    std::optional<LeafGroups> groups;
    if (merge > 0.f) groups.emplace(field.tree(), estimates, extents, merge);
    // The demo's fog: sigma_t 0.1 per unit over a room ~10 units across (a few tenths of an optical depth).
    const HomogeneousMedium medium(Color3(0.1f), std::make_shared<Volume>(VoxelGrid(Color3(0.8f)), Transform()),
                                   std::make_shared<IsotropicPhase>());
    const BBox3f b = field.tree().bounds();
    std::vector<Ray> rays;
    std::vector<float> ends;
    for (int i = 0; i < 4096; ++i) {
        Sampler s(7, 0, uint64_t(i));
        const Vec3f e = b.extents();
        Ray ray(b.lo + Vec3f(e.x * s.next_1d(), e.y * s.next_1d(), e.z * s.next_1d()),
                warp::square_to_uniform_sphere(s.next_2d()));
        float t0, t1;
        b.ray_intersect(ray, t0, t1);
        rays.push_back(ray);
        ends.push_back(t1);
    }
    const GuidedDistanceSettings settings;
    std::vector<ProxySegment> proxies;
    uint64_t i = 0, bins = 0;
    for (auto _ : state) {
        const size_t k = i & 4095;
        Sampler rng(3, 0, i++);
        BinSource source(rays[k], ends[k], medium,
                         BinField{field, &estimates, groups ? &*groups : nullptr, extents, 20.f, 1.f}, proxies);
        const DistanceSample d = sample_incremental_distance(source, rng, settings);
        bins += uint64_t(d.steps);
        benchmark::DoNotOptimize(d);
    }
    state.counters["bins"] = double(bins) / double(std::max<uint64_t>(i, 1));
    state.counters["leaf_groups"] = groups ? double(groups->group_count()) : 0.0;
    state.counters["leaves"] = double(field.tree().leaf_count());
}

void BM_LeafTableLookup(benchmark::State& state) {
    const GuidingField& field = demo_field();
    const InscatterCache cache(field, hg_phase_vmm(0.f));
    const LeafEstimates estimates(field, cache, 16);
    std::vector<std::pair<int, LeafEstimates::Direction>> queries;
    for (int i = 0; i < 4096; ++i) {
        Sampler s(8, 0, uint64_t(i));
        const int leaf = std::min(int(s.next_1d() * float(field.tree().leaf_count())), field.tree().leaf_count() - 1);
        queries.push_back({leaf, estimates.prepare(warp::square_to_uniform_sphere(s.next_2d()))});
    }
    size_t i = 0;
    for (auto _ : state) {
        const auto& [leaf, d] = queries[i++ & 4095];
        Color3 Li, L;
        benchmark::DoNotOptimize(estimates.lookup(leaf, d, Li, L));
        benchmark::DoNotOptimize(Li);
        benchmark::DoNotOptimize(L);
    }
}

// A medium vertex at the ray's origin in `medium` (what the walk begins a GuidedVertex with).
MediumInteraction bench_vertex_at(const Ray& ray, const Medium& medium) {
    MediumInteraction mi;
    mi.p = ray.o;
    mi.wi = -ray.d;
    mi.medium = &medium;
    mi.coeffs = medium.eval(ray.o);
    return mi;
}

// Issue 37: one distance decision in the demo scene's homogeneous fog from a medium vertex whose leaf
// the direction decision found (its GuidedVertex's leaf known, as in the walk; the object's init is
// timed with the decision), along a random direction to the field's bounds: range(0) = 0 the
// medium's free flight, 1 distance="vsp" (GuidedVertex::sample_distance: one table lookup, the segment
// decision), 2 distance="incremental" (the bins, for comparison).
void BM_SegmentDecision(benchmark::State& state) {
    const Scene& scene = demo_scene();
    const GuidingField& field = demo_field();
    const Medium* medium = demo_medium();
    if (!medium || !medium->is_homogeneous()) {
        state.SkipWithError("the demo scene has no homogeneous medium");
        return;
    }
    WalkGuideSettings settings;
    const DistanceGuiding kinds[] = {DistanceGuiding::Vsp, DistanceGuiding::Vsp, DistanceGuiding::Incremental};
    settings.distance = kinds[state.range(0)];
    settings.direction = DirectionGuiding::Product;
    settings.vsp_equiangular = 0.f;  // the demo's lights are directional and an environment: nothing to aim at
    const WalkGuide guide(scene, field, settings);
    const BBox3f b = field.tree().bounds();
    struct Query {
        Ray ray;
        float end;
        int leaf;
    };
    std::vector<Query> queries;
    std::vector<MediumInteraction> vertices;
    for (int i = 0; i < 4096; ++i) {
        Sampler s(7, 0, uint64_t(i));
        const Vec3f e = b.extents();
        const Ray ray(b.lo + Vec3f(e.x * s.next_1d(), e.y * s.next_1d(), e.z * s.next_1d()),
                      warp::square_to_uniform_sphere(s.next_2d()));
        float t0, t1;
        b.ray_intersect(ray, t0, t1);
        queries.push_back({ray, t1, field.tree().leaf_at(ray.o)});
        vertices.push_back(bench_vertex_at(ray, *medium));
    }
    WalkGuideStats counts;
    GuidedVertex origin(guide, counts);
    uint64_t i = 0, scattered = 0;
    for (auto _ : state) {
        const Query& q = queries[i & 4095];
        if (state.range(0) != 0) origin.init(vertices[i & 4095], q.leaf);
        Sampler rng(3, 0, i++);
        const FreeFlightSample f =
            state.range(0) == 0
                ? medium->sample_free_flight(q.ray, q.end, Color3(1.f), rng)
                : origin.sample_distance(DistanceQuery{*medium, q.ray, q.end, Color3(1.f)}, kNoCameraBuffer, rng, nullptr);
        scattered += f.scattered;
        benchmark::DoNotOptimize(f);
    }
    state.counters["scattered"] = double(scattered) / double(std::max<uint64_t>(i, 1));
    const char* labels[] = {"free flight", "vsp", "incremental bins"};
    state.SetLabel(labels[state.range(0)]);
}

Scene& foglamp_scene() {
    static std::unique_ptr<Scene> scene = load_scene(std::string(VOLGUIDE_SOURCE_DIR) + "/bench/scenes/foglamp.xml");
    return *scene;
}

const GuidingField& foglamp_field() {
    static GuidingField f = [] {
        PhotonPassSettings ps;
        ps.photons = kPhotons;
        return GuidingField::build(guiding_bounds(foglamp_scene()),
                                   trace_photons(foglamp_scene(), ps, PreprocessContext{}).samples);
    }();
    return f;
}

// Issue 37, deliverable 5: BM_SegmentDecision's query (a vertex of known leaf, a random direction to
// the field's bounds) in foglamp's fog, whose lamp equiangular sampling can aim at: range(0) = 0 free
// flight, 1 distance="vsp", 2 distance="vsp" with vsp_equiangular 0.5.
void BM_SegmentDecisionEquiangular(benchmark::State& state) {
    const Scene& scene = foglamp_scene();
    const GuidingField& field = foglamp_field();
    const Medium* medium = scene.sensor().medium();
    if (!medium || !medium->is_homogeneous()) {
        state.SkipWithError("foglamp's camera is not in a homogeneous medium");
        return;
    }
    WalkGuideSettings settings;
    settings.distance = DistanceGuiding::Vsp;
    settings.direction = DirectionGuiding::Product;
    settings.vsp_equiangular = state.range(0) == 2 ? 0.5f : 0.f;
    const WalkGuide guide(scene, field, settings);
    // Vertices inside the box (the fog's cube: |x|, |y| < 1, z in (-1, 1)).
    std::vector<std::pair<Ray, int>> queries;
    std::vector<MediumInteraction> vertices;
    for (int i = 0; i < 4096; ++i) {
        Sampler s(7, 0, uint64_t(i));
        const Point3f o(1.9f * s.next_1d() - 0.95f, 1.9f * s.next_1d() - 0.95f, 1.9f * s.next_1d() - 0.95f);
        queries.push_back({Ray(o, warp::square_to_uniform_sphere(s.next_2d())), field.tree().leaf_at(o)});
        vertices.push_back(bench_vertex_at(queries.back().first, *medium));
    }
    const BBox3f b = field.tree().bounds();
    WalkGuideStats st;
    GuidedVertex origin(guide, st);
    uint64_t i = 0, scattered = 0;
    for (auto _ : state) {
        const auto& [ray, leaf] = queries[i & 4095];
        float t0, t1;
        b.ray_intersect(ray, t0, t1);
        if (state.range(0) != 0) origin.init(vertices[i & 4095], leaf);
        Sampler rng(3, 0, i++);
        const FreeFlightSample f =
            state.range(0) == 0 ? medium->sample_free_flight(ray, t1, Color3(1.f), rng)
                                : origin.sample_distance(DistanceQuery{*medium, ray, t1, Color3(1.f)},
                                                         kNoCameraBuffer, rng, nullptr);
        scattered += f.scattered;
        benchmark::DoNotOptimize(f);
    }
    state.counters["scattered"] = double(scattered) / double(std::max<uint64_t>(i, 1));
    state.counters["equiangular"] = st.vsp_scattered ? double(st.vsp_equiangular) / double(st.vsp_scattered) : 0.0;
    state.SetLabel(state.range(0) == 0 ? "free flight" : state.range(0) == 1 ? "vsp" : "vsp, vsp_equiangular 0.5");
}

void BM_RouletteEstimate(benchmark::State& state) {
    const Scene& scene = demo_scene();
    const GuidingField& field = demo_field();
    const Medium* medium = demo_medium();
    if (!medium) {
        state.SkipWithError("the demo scene has no medium");
        return;
    }
    WalkGuideSettings settings;
    settings.distance = DistanceGuiding::Incremental;  // the tables the estimates read
    settings.direction = DirectionGuiding::Product;
    const WalkGuide guide(scene, field, settings);
    const BBox3f b = field.tree().bounds();
    std::vector<std::pair<MediumInteraction, Vec3f>> queries;
    for (int i = 0; i < 4096; ++i) {
        Sampler s(6, 0, uint64_t(i));
        const Vec3f e = b.extents();
        MediumInteraction mi;
        mi.p = b.lo + Vec3f(e.x * s.next_1d(), e.y * s.next_1d(), e.z * s.next_1d());
        mi.medium = medium;
        mi.coeffs = medium->eval(mi.p);
        const Vec3f d = warp::square_to_uniform_sphere(s.next_2d());
        mi.wi = -d;
        queries.push_back({mi, d});
    }
    WalkGuideStats counts;
    GuidedVertex vertex(guide, counts);  // the continuation's estimate is the vertex's
    size_t i = 0;
    for (auto _ : state) {
        const auto& [mi, d] = queries[i++ & 4095];
        vertex.init(mi);  // not known: a descent, as after an unguided distance decision
        benchmark::DoNotOptimize(vertex.estimate(ContinuationStage::Distance, d));
    }
}

// Issue 37 deliverable 2: one medium vertex's GuidedVertex in the demo scene's fog as the walk asks
// it, leaf not handed on (one descent): init, the distance-stage continuation's estimate along the
// arriving ray, the next segment's scatter probability along a second direction; range(0) = 1 also
// builds the direction mixture (the leaf VMM x phase product) between them, as a vertex that
// survives the distance stage does.
void BM_GuidedVertex(benchmark::State& state) {
    const Scene& scene = demo_scene();
    const GuidingField& field = demo_field();
    const Medium* medium = demo_medium();
    if (!medium) {
        state.SkipWithError("the demo scene has no medium");
        return;
    }
    WalkGuideSettings settings;
    settings.distance = DistanceGuiding::Vsp;
    settings.direction = DirectionGuiding::Product;
    const WalkGuide guide(scene, field, settings);
    const BBox3f b = field.tree().bounds();
    struct Query {
        MediumInteraction mi;
        Vec3f w;
    };
    std::vector<Query> queries;
    for (int i = 0; i < 4096; ++i) {
        Sampler s(8, 0, uint64_t(i));
        const Vec3f e = b.extents();
        const Ray ray(b.lo + Vec3f(e.x * s.next_1d(), e.y * s.next_1d(), e.z * s.next_1d()),
                      warp::square_to_uniform_sphere(s.next_2d()));
        queries.push_back({bench_vertex_at(ray, *medium), warp::square_to_uniform_sphere(s.next_2d())});
    }
    const bool direction = state.range(0) == 1;
    WalkGuideStats st;
    GuidedVertex vertex(guide, st);
    size_t i = 0;
    for (auto _ : state) {
        const Query& q = queries[i++ & 4095];
        vertex.init(q.mi);
        benchmark::DoNotOptimize(vertex.estimate(ContinuationStage::Distance, -q.mi.wi));
        if (direction) vertex.prepare_direction();
        benchmark::DoNotOptimize(guide.prepared().scatter_probability(vertex.leaf(), q.mi.medium->phase(), q.w, 0.9f, 0.5f));
    }
    state.counters["descents_per_vertex"] = st.vertices ? double(st.vertex_descents) / double(st.vertices) : 0.0;
    state.counters["products_per_vertex"] = st.vertices ? double(st.vertex_products) / double(st.vertices) : 0.0;
    state.SetLabel(direction ? "init, estimate, direction mixture, scatter probability"
                             : "init, estimate, scatter probability");
}

// Issue 39 deliverable 2: the guided decisions' cost against the field's size. Fields of about
// 1 k, 4 k, 16 k and 64 k leaves over the demo's photons (kSizedPhotons, so that even the smallest
// leaves hold enough samples to be fitted), leaf_samples found by bisection on the tree alone.
constexpr int64_t kSizedPhotons = 4000000;
constexpr size_t kSizedQueries = size_t(1) << 18;  // far more leaves than the caches hold at 64 k

const std::vector<RadianceSample>& sized_photons() {
    static const std::vector<RadianceSample> samples = [] {
        PhotonPassSettings ps;
        ps.photons = kSizedPhotons;
        return trace_photons(demo_scene(), ps, PreprocessContext{}).samples;
    }();
    return samples;
}

// The least leaf_samples whose tree has at most `leaves` leaves (a tree of m samples per leaf has
// between N / m and 2 N / m leaves, and fewer for larger m).
int sized_leaf_samples(std::span<const Point3f> points, const BBox3f& bounds, int leaves) {
    int lo = std::max(1, int(points.size()) / leaves), hi = 2 * lo + 1;
    while (lo < hi) {
        SpatialTreeSettings settings;
        settings.max_samples = lo + (hi - lo) / 2;
        if (SpatialTree::build(bounds, points, settings).leaf_count() <= leaves)
            hi = settings.max_samples;
        else
            lo = settings.max_samples + 1;
    }
    return lo;
}

// One field per leaf count, built once (default settings but leaf_samples and min_samples).
const GuidingField& sized_field(int leaves) {
    static std::map<int, std::unique_ptr<GuidingField>> fields;
    auto& f = fields[leaves];
    if (!f) {
        const auto& samples = sized_photons();
        std::vector<Point3f> points;
        for (const RadianceSample& r : samples) points.push_back(r.position);
        GuidingFieldSettings settings;
        settings.tree.max_samples = sized_leaf_samples(points, guiding_bounds(demo_scene()), leaves);
        // At 64 k leaves a leaf holds a few dozen of the photons' samples: fitted all the same, so
        // that every size guides (nearly) every leaf and the kernels compare the same decisions.
        settings.min_samples = 16;
        f = std::make_unique<GuidingField>(GuidingField::build(guiding_bounds(demo_scene()), samples, settings));
    }
    return *f;
}

// The guide of a sized field for one distance method (direction="product"), built once: a 64 k-leaf
// guide's tables take long to prepare, and Google Benchmark calls a kernel several times.
const WalkGuide& sized_guide(int leaves, DistanceGuiding distance) {
    static std::map<std::pair<int, int>, std::unique_ptr<WalkGuide>> guides;
    auto& g = guides[{leaves, int(distance)}];
    if (!g) {
        WalkGuideSettings settings;
        settings.distance = distance;
        settings.direction = DirectionGuiding::Product;
        settings.vsp_equiangular = 0.f;  // the demo's lights are directional and an environment
        g = std::make_unique<WalkGuide>(demo_scene(), sized_field(leaves), settings);
    }
    return *g;
}

// Random points of the demo's fog (the field's bounds are the medium's) and random directions,
// with the point's leaf and the distance to the bounds along the direction: what a render spreads
// over the field. Many more than the caches hold at 64 k leaves, so that each query reads its leaf
// from memory as a render's random vertices do.
struct SizedQuery {
    Point3f p;
    Vec3f d;
    float end;
    int leaf;
};
const std::vector<SizedQuery>& sized_queries(int leaves) {
    static std::map<int, std::vector<SizedQuery>> queries;
    std::vector<SizedQuery>& q = queries[leaves];
    if (q.empty()) {
        const GuidingField& field = sized_field(leaves);
        const BBox3f b = field.tree().bounds();
        const Vec3f e = b.extents();
        for (size_t i = 0; i < kSizedQueries; ++i) {
            Sampler s(11, 0, uint64_t(i));
            const Ray ray(b.lo + Vec3f(e.x * s.next_1d(), e.y * s.next_1d(), e.z * s.next_1d()),
                          warp::square_to_uniform_sphere(s.next_2d()));
            float t0, t1;
            b.ray_intersect(ray, t0, t1);
            q.push_back({ray.o, ray.d, t1, field.tree().leaf_at(ray.o)});
        }
    }
    return q;
}

void sized_field_counters(benchmark::State& state, const GuidingField& field) {
    size_t valid = 0, lobes = 0;
    for (const GuidingLeaf& l : field.leaves())
        if (l.valid) ++valid, lobes += size_t(l.vmm.size());
    state.counters["leaves"] = double(field.tree().leaf_count());
    state.counters["valid"] = double(valid) / double(field.tree().leaf_count());
    state.counters["lobes"] = valid ? double(lobes) / double(valid) : 0.0;
    state.counters["depth"] = double(field.tree().depth());
}

// One distance decision per segment as the walk makes it from a medium vertex whose leaf the
// direction decision there found (the GuidedVertex's leaf known; its init is timed with the
// decision), along a random direction to the field's bounds: range(0) = 0 distance="vsp" (one table
// lookup), 2 distance="incremental" (the bins: one per leaf crossed, so its cost grows with the field;
// 1 was the retired vsp_product); range(1) the leaf count asked for. Counters: `steps` per decision
// (for the bins, the leaves crossed), `scattered`.
void BM_SizedDistance(benchmark::State& state) {
    const DistanceGuiding kinds[] = {DistanceGuiding::Vsp, DistanceGuiding::Vsp, DistanceGuiding::Incremental};
    const int leaves = int(state.range(1));
    const WalkGuide& guide = sized_guide(leaves, kinds[state.range(0)]);
    const std::vector<SizedQuery>& queries = sized_queries(leaves);
    const Medium* medium = demo_medium();
    if (!medium || !medium->is_homogeneous()) {
        state.SkipWithError("the demo scene has no homogeneous medium");
        return;
    }
    WalkGuideStats counts;
    GuidedVertex origin(guide, counts);
    uint64_t i = 0, scattered = 0;
    for (auto _ : state) {
        const SizedQuery& q = queries[i & (kSizedQueries - 1)];
        const Ray ray(q.p, q.d);
        origin.init(bench_vertex_at(ray, *medium), q.leaf);
        Sampler rng(3, 0, i++);
        const FreeFlightSample f =
            origin.sample_distance(DistanceQuery{*medium, ray, q.end, Color3(1.f)}, kNoCameraBuffer, rng, nullptr);
        scattered += f.scattered;
        benchmark::DoNotOptimize(f);
    }
    sized_field_counters(state, sized_field(leaves));
    state.counters["scattered"] = double(scattered) / double(std::max<uint64_t>(i, 1));
    state.counters["steps"] = double(counts.distance_steps) / double(std::max<uint64_t>(i, 1));
    const char* labels[] = {"vsp", "vsp", "incremental bins"};
    state.SetLabel(labels[state.range(0)]);
}

// One direction decision (direction="product") at a medium vertex as the walk makes it: the vertex
// begun without a handed leaf, its leaf found (a descent unless the last vertex's leaf holds the
// point), the mixture of the leaf VMM x phase product built, one direction sampled; range(0) the
// leaf count asked for. Counters: `descents` per decision, `guided` (the fraction of vertices whose
// mixture is guided).
void BM_SizedDirection(benchmark::State& state) {
    const int leaves = int(state.range(0));
    const WalkGuide& guide = sized_guide(leaves, DistanceGuiding::Vsp);
    const std::vector<SizedQuery>& queries = sized_queries(leaves);
    const Medium* medium = demo_medium();
    if (!medium) {
        state.SkipWithError("the demo scene has no medium");
        return;
    }
    WalkGuideStats after;
    GuidedVertex vertex(guide, after);
    uint64_t i = 0, guided = 0;
    for (auto _ : state) {
        const SizedQuery& q = queries[i & (kSizedQueries - 1)];
        vertex.init(bench_vertex_at(Ray(q.p, q.d), *medium));
        Sampler rng(4, 0, i++);
        vertex.prepare_direction();
        guided += vertex.guided();
        const float u_strategy = rng.next_1d();
        benchmark::DoNotOptimize(vertex.sample_direction(rng.next_2d(), u_strategy));
    }
    sized_field_counters(state, sized_field(leaves));
    const double n = double(std::max<uint64_t>(i, 1));
    state.counters["descents"] = double(after.vertex_descents) / n;
    state.counters["guided"] = double(guided) / n;
}

// The leaf lookup alone (SpatialTree::leaf_at) at the sized queries' points: the tree descent the
// direction decision makes when no leaf was handed on; range(0) the leaf count asked for.
void BM_SizedLeafAt(benchmark::State& state) {
    const int leaves = int(state.range(0));
    const SpatialTree& tree = sized_field(leaves).tree();
    const std::vector<SizedQuery>& queries = sized_queries(leaves);
    uint64_t i = 0;
    for (auto _ : state) benchmark::DoNotOptimize(tree.leaf_at(queries[i++ & (kSizedQueries - 1)].p));
    sized_field_counters(state, sized_field(leaves));
}

// An 8-lobe leaf with concentrations between 1 and 50 in random directions.
GuidingLeaf bench_leaf() {
    GuidingLeaf leaf;
    Sampler s(9, 0, 0);
    for (int k = 0; k < 8; ++k)
        leaf.vmm.add_lobe(0.2f + s.next_1d(), VmfLobe(warp::square_to_uniform_sphere(s.next_2d()),
                                                      std::pow(50.f, s.next_1d())));
    leaf.vmm.normalize_weights();
    leaf.valid = true;
    return leaf;
}

// Per vertex: Construct = build only; Sample = build + one sample (pdf included); Pdf = one pdf
// evaluation of a built sampler (MIS with NEE). The phase VMM is prepared once unless Unprepared.
enum BenchPart { Construct, Sample, Pdf };
template <DirectionGuiding Mode, BenchPart Part, bool Unprepared = false>
void BM_GuidedDirection(benchmark::State& state) {
    const GuidingLeaf leaf = bench_leaf();
    const HGPhase phase(0.6f);
    const PhaseVmm phase_vmm = hg_phase_vmm(phase.g());
    std::vector<Vec3f> dirs;
    for (int i = 0; i < 4096; ++i) {
        Sampler s(5, 0, uint64_t(i));
        dirs.push_back(warp::square_to_uniform_sphere(s.next_2d()));
    }
    const GuidedDirectionSampler fixed(Mode, &leaf, phase, dirs[0], 0.5f, &phase_vmm);
    size_t i = 0;
    for (auto _ : state) {
        const Vec3f& d = dirs[i++ & 4095];
        if constexpr (Part == Pdf) {
            benchmark::DoNotOptimize(fixed.pdf(d));
        } else {
            const GuidedDirectionSampler g(Mode, &leaf, phase, d, 0.5f, Unprepared ? nullptr : &phase_vmm);
            if constexpr (Part == Sample) {
                benchmark::DoNotOptimize(g.sample({d.y * 0.5f + 0.5f, d.z * 0.5f + 0.5f}, d.x * 0.5f + 0.5f));
            } else {
                benchmark::DoNotOptimize(g);
            }
        }
    }
}

}  // namespace

BENCHMARK(BM_Distance<false>)->Name("BM_DistanceIncremental")->Arg(0)->Arg(1)->Arg(2);
BENCHMARK(BM_Distance<true>)->Name("BM_DistanceTabulated")->Arg(0)->Arg(1)->Arg(2);
BENCHMARK(BM_GuidedDirection<DirectionGuiding::Product, Construct>)->Name("BM_GuidedDirectionConstruct/product");
BENCHMARK(BM_GuidedDirection<DirectionGuiding::Product, Construct, true>)
    ->Name("BM_GuidedDirectionConstruct/product/unprepared");
BENCHMARK(BM_GuidedDirection<DirectionGuiding::Incident, Construct>)->Name("BM_GuidedDirectionConstruct/incident");
BENCHMARK(BM_GuidedDirection<DirectionGuiding::Product, Sample>)->Name("BM_GuidedDirectionSample/product");
BENCHMARK(BM_GuidedDirection<DirectionGuiding::Incident, Sample>)->Name("BM_GuidedDirectionSample/incident");
BENCHMARK(BM_GuidedDirection<DirectionGuiding::Phase, Sample>)->Name("BM_GuidedDirectionSample/phase");
BENCHMARK(BM_GuidedDirection<DirectionGuiding::Product, Pdf>)->Name("BM_GuidedDirectionPdf/product");
BENCHMARK(BM_GuidedDirection<DirectionGuiding::Incident, Pdf>)->Name("BM_GuidedDirectionPdf/incident");
BENCHMARK(BM_DistanceQuery)->Arg(0)->Arg(30)->Arg(50);
BENCHMARK(BM_LeafTableLookup);
BENCHMARK(BM_SegmentDecision)->Arg(0)->Arg(1)->Arg(2);
BENCHMARK(BM_SegmentDecisionEquiangular)->Arg(0)->Arg(1)->Arg(2);
BENCHMARK(BM_RouletteEstimate);
BENCHMARK(BM_GuidedVertex)->Arg(0)->Arg(1);
BENCHMARK(BM_SizedDistance)->ArgsProduct({{0, 2}, {1000, 4000, 16000, 64000}});
BENCHMARK(BM_SizedDirection)->Arg(1000)->Arg(4000)->Arg(16000)->Arg(64000);
BENCHMARK(BM_SizedLeafAt)->Arg(1000)->Arg(4000)->Arg(16000)->Arg(64000);
BENCHMARK(BM_LeafWalk<true>)->Name("BM_LeafWalkCursor")->Arg(2000)->Arg(50000);
BENCHMARK(BM_LeafWalk<false>)->Name("BM_LeafWalkTraverse")->Arg(2000)->Arg(50000);
BENCHMARK(BM_PhotonPass)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_FieldBuild)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_TreeBuild)->Args({1, 0})->Args({1, 1})->Args({2, 0})->Args({2, 1})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Query<0>)->Name("BM_Incident");
BENCHMARK(BM_Query<1>)->Name("BM_InscatteredExact");
BENCHMARK(BM_Query<2>)->Name("BM_InscatteredA3");
BENCHMARK(BM_Query<3>)->Name("BM_InscatteredA3Prepared");
BENCHMARK(BM_InscatterCachePrepare)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_MAIN();
