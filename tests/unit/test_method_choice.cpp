// The per-tile method choice's decision rule on synthetic tile statistics (integrators/guided/estimates/
// method_choice.h), its map and storage, and the pre-pass deadline (training/preprocess_budget.h).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "volguide/integrators/guided/estimates/method_choice.h"
#include "volguide/integrators/guided/training/preprocess_budget.h"

namespace volguide {
namespace {

// A tile's probe samples of both methods: `pixels` probe pixels of `n` samples each, drawn by `draw`
// (returns the luminance), at a fixed cost per sample.
struct TileSamples {
    std::vector<std::vector<double>> guided, volpath;
};

template <typename DrawG, typename DrawV>
TileSamples make_tile(int pixels, int n, DrawG&& draw_guided, DrawV&& draw_volpath) {
    TileSamples t;
    for (int p = 0; p < pixels; ++p) {
        std::vector<double> g, v;
        for (int k = 0; k < n; ++k) {
            g.push_back(draw_guided());
            v.push_back(draw_volpath());
        }
        t.guided.push_back(g);
        t.volpath.push_back(v);
    }
    return t;
}

// Both methods' evidence, as ChoiceProbes::evidence makes it (the pixel normaliser pools both).
std::pair<TileEvidence, TileEvidence> evidence(const TileSamples& t, double cost_guided, double cost_volpath) {
    TileEvidence g, v;
    for (size_t p = 0; p < t.guided.size(); ++p) {
        double sg = 0, sg2 = 0, sv = 0, sv2 = 0;
        for (double x : t.guided[p]) sg += x, sg2 += x * x;
        for (double x : t.volpath[p]) sv += x, sv2 += x * x;
        const double ng = double(t.guided[p].size()), nv = double(t.volpath[p].size());
        const double pooled = (sg + sv) / (ng + nv);
        g.add_pixel(ng, sg, sg2, ng * cost_guided, ng * cost_guided * cost_guided, pooled);
        v.add_pixel(nv, sv, sv2, nv * cost_volpath, nv * cost_volpath * cost_volpath, pooled);
    }
    return {g, v};
}

TEST(MethodChoice, AClearlyWorseGuidedTileGoesToVolpath) {
    std::mt19937_64 rng(1);
    std::normal_distribution<double> wide(1.0, 0.6), narrow(1.0, 0.3);
    // Guided: 4x the variance at equal cost; 64 probe pixels of 4 samples.
    const TileSamples t = make_tile(64, 4, [&] { return wide(rng); }, [&] { return narrow(rng); });
    const auto [g, v] = evidence(t, 1000, 1000);
    const TileDecision d = decide_tile(g, v);
    EXPECT_EQ(d.method, TileMethod::Volpath) << d.log_ratio << " +- " << d.error;
    EXPECT_NEAR(d.log_ratio, std::log(4.0), 0.4);
    // The same variances, guided 5x cheaper: guided.
    const auto [g2, v2] = evidence(t, 200, 1000);
    EXPECT_EQ(decide_tile(g2, v2).method, TileMethod::Guided);
}

TEST(MethodChoice, TooLittleEvidenceStaysGuided) {
    std::mt19937_64 rng(2);
    std::normal_distribution<double> wide(1.0, 0.6), narrow(1.0, 0.5);
    // 1.44x the variance at equal cost, 16 pixels of 2 samples: not enough to be confident.
    const TileSamples t = make_tile(16, 2, [&] { return wide(rng); }, [&] { return narrow(rng); });
    const auto [g, v] = evidence(t, 1000, 1000);
    EXPECT_EQ(decide_tile(g, v).method, TileMethod::Guided);
    // Volpath far better, but 3 samples per probe pixel: too few to rule out rare bright paths.
    const TileSamples three = make_tile(64, 3, [&] { return 10 * wide(rng); }, [&] { return narrow(rng); });
    const auto [g3, v3] = evidence(three, 1000, 1000);
    EXPECT_EQ(decide_tile(g3, v3).method, TileMethod::Guided);
    const TileSamples four = make_tile(64, 4, [&] { return 10 * wide(rng); }, [&] { return narrow(rng); });
    const auto [g4, v4] = evidence(four, 1000, 1000);
    EXPECT_EQ(decide_tile(g4, v4).method, TileMethod::Volpath);  // (the rule above can fail)
    // Fewer than four probe pixels: no decision at all.
    const TileSamples few = make_tile(3, 8, [&] { return 10 * wide(rng); }, [&] { return narrow(rng); });
    const auto [gf, vf] = evidence(few, 1000, 1000);
    EXPECT_EQ(decide_tile(gf, vf).method, TileMethod::Guided);
}

// Volpath's rare bright paths: the same mean relative variance as a light-tailed volpath tile that
// goes to volpath, but concentrated in a few samples; the variance of the variance estimate (the
// fourth moment) keeps it guided.
TEST(MethodChoice, AHeavyTailedVolpathTileStaysGuided) {
    std::mt19937_64 rng(3);
    std::normal_distribution<double> guided(1.0, 0.5);
    // Light tails: volpath's variance 0.25 / 4 per sample, guided 4x as costly per unit of variance.
    std::normal_distribution<double> light(1.0, 0.25);
    const TileSamples light_tile = make_tile(64, 4, [&] { return guided(rng); }, [&] { return light(rng); });
    const auto [gl, vl] = evidence(light_tile, 1000, 1000);
    EXPECT_EQ(decide_tile(gl, vl).method, TileMethod::Volpath);
    // Heavy tails: 0.9 almost always, 2 bright samples among 256 (each ~ 4 relative-variance units in
    // its pixel); the observed mean relative variance is about volpath's light-tailed one.
    int k = 0;
    const TileSamples heavy = make_tile(64, 4, [&] { return guided(rng); }, [&] { return (++k % 128 == 0) ? 5.0 : 0.97; });
    const auto [gh, vh] = evidence(heavy, 1000, 1000);
    ASSERT_LT(vh.variance(), 2.0 * vl.variance());  // on average, volpath looks as good as the light one...
    ASSERT_GT(vh.variance(), 0.5 * vl.variance());
    const TileDecision d = decide_tile(gh, vh);
    EXPECT_EQ(d.method, TileMethod::Guided) << d.log_ratio << " +- " << d.error;  // ...but the evidence is weak
    EXPECT_GT(d.error, 0.5);
}

TEST(MethodChoice, VolpathThatSawNoVarianceWhereGuidedDidStaysGuided) {
    std::mt19937_64 rng(4);
    std::normal_distribution<double> guided(1.0, 0.5);
    const TileSamples t = make_tile(64, 4, [&] { return guided(rng); }, [] { return 0.0; });
    const auto [g, v] = evidence(t, 5000, 100);
    EXPECT_EQ(decide_tile(g, v).method, TileMethod::Guided);
    // Neither saw any variance (a black background): the cost decides.
    const TileSamples black = make_tile(64, 4, [] { return 0.0; }, [] { return 0.0; });
    const auto [gb, vb] = evidence(black, 5000, 100);
    EXPECT_EQ(decide_tile(gb, vb).method, TileMethod::Volpath);
}

TEST(MethodChoice, ALoneVolpathTileAmongGuidedOnesStaysGuided) {
    std::mt19937_64 rng(5);
    std::normal_distribution<double> wide(1.0, 0.6), narrow(1.0, 0.3), good(1.0, 0.1);
    const TileSamples worse = make_tile(64, 4, [&] { return wide(rng); }, [&] { return narrow(rng); });
    const TileSamples better = make_tile(64, 4, [&] { return good(rng); }, [&] { return narrow(rng); });
    const auto [gw, vw] = evidence(worse, 1000, 1000);
    const auto [gb, vb] = evidence(better, 1000, 1000);
    // 3 x 3 tiles (48 x 48 pixels): guided much better everywhere but in the centre.
    std::vector<TileEvidence> g(9, gb), v(9, vb);
    g[4] = gw;
    v[4] = vw;
    const ChoiceMap lone = decide_map(48, 48, g, v);
    EXPECT_EQ(lone.volpath_share(), 0.0);
    // Guided worse everywhere: every tile volpath's.
    const ChoiceMap all = decide_map(48, 48, std::vector<TileEvidence>(9, gw), std::vector<TileEvidence>(9, vw));
    EXPECT_EQ(all.volpath_share(), 1.0);
}

// Every pixel gets the same spp: a tile twice as efficient with volpath (2x the variance at a quarter of the
// cost) among costly guided tiles stays guided, its saved time too small to pay for its variance.
TEST(MethodChoice, ATileGoesToVolpathOnlyWhenTheWholeImageGains) {
    std::mt19937_64 rng(6);
    std::normal_distribution<double> guided(1.0, 0.4), volpath(1.0, 0.4 * std::sqrt(2.0));
    const TileSamples t = make_tile(64, 16, [&] { return guided(rng); }, [&] { return volpath(rng); });
    const auto [g, v] = evidence(t, 1000, 250);
    ASSERT_EQ(decide_tile(g, v).method, TileMethod::Volpath);  // twice as efficient in itself
    const ChoiceMap alone = decide_map(16, 16, {g}, {v});
    EXPECT_EQ(alone.volpath_share(), 1.0);  // alone in the image: the image gains
    // Among 8 guided tiles of the same variance, each costing 10x: the image loses, it stays guided.
    TileEvidence costly = g;
    costly.cost_sum *= 10;
    costly.cost_sq *= 100;
    std::vector<TileEvidence> gs(9, costly), vs(9, costly);
    for (TileEvidence& e : vs) e.var_sum *= 100;  // volpath hopeless there
    gs[4] = g;
    vs[4] = v;
    const ChoiceMap among = decide_map(48, 48, gs, vs);
    EXPECT_EQ(among.volpath_share(), 0.0);
}

TEST(MethodChoice, MapLooksUpTilesAndRoundTrips) {
    ChoiceMap map{40, 20, {TileMethod::Guided, TileMethod::Volpath, TileMethod::Guided, TileMethod::Volpath,
                           TileMethod::Volpath, TileMethod::Guided}};
    ASSERT_EQ(map.tiles_x(), 3);
    ASSERT_EQ(map.tiles_y(), 2);
    EXPECT_EQ(map.at(Point2f(0.5f / 40, 0.5f / 20)), TileMethod::Guided);
    EXPECT_EQ(map.at(Point2f(17.5f / 40, 0.5f / 20)), TileMethod::Volpath);
    EXPECT_EQ(map.at(Point2f(39.5f / 40, 19.5f / 20)), TileMethod::Guided);
    EXPECT_EQ(map.at(Point2f(-0.1f, 1.2f)), TileMethod::Volpath);  // a filter's border: the nearest tile
    EXPECT_NEAR(map.volpath_share(), 0.5, 1e-12);
    const ChoiceMap back = ChoiceMap::deserialize(map.serialize());
    EXPECT_EQ(back.width, 40);
    EXPECT_EQ(back.tiles, map.tiles);
    const std::string bytes = map.serialize();
    EXPECT_THROW(ChoiceMap::deserialize(bytes.substr(0, bytes.size() - 1)), std::runtime_error);
    std::string version = bytes;
    version[0] = 9;
    EXPECT_THROW(ChoiceMap::deserialize(version), std::runtime_error);
    EXPECT_EQ(ChoiceMap().at(Point2f(0.5f, 0.5f)), TileMethod::Guided);
    const Image img = map.image();
    EXPECT_EQ(img.at(17, 0).r, 1.f);
    EXPECT_LT(img.at(0, 0).r, 0.5f);
}

TEST(PreprocessBudget, StepsStayWithinTheDeadline) {
    const PreprocessBudget none(0, 0.25);
    EXPECT_FALSE(none.limited());
    EXPECT_EQ(none.limit(1.0), 0.0);  // no budget: no limit, nothing depends on the clock
    EXPECT_EQ(none.limit_within(0.5, 0.2), 0.0);
    EXPECT_FALSE(PreprocessBudget::over(0.0, 100.0, 100.0));
    const PreprocessBudget budget(40, 0.25);
    EXPECT_DOUBLE_EQ(budget.total(), 10.0);
    EXPECT_LE(budget.limit(0.5), 5.0);
    EXPECT_GT(budget.limit(0.5), 4.9);
    EXPECT_LE(budget.elapsed() + budget.limit(1.0), 10.0 + 1e-3);
    EXPECT_LE(budget.limit_within(1.0, 0.2), 2.0);  // the first stage's ceiling
    EXPECT_TRUE(PreprocessBudget::over(1.0, 0.8, 0.3));
    EXPECT_FALSE(PreprocessBudget::over(1.0, 0.5, 0.3));
}

}  // namespace
}  // namespace volguide
