// The training file container (integrators/guided/prepass/training_file.h) and the integrator configuration text.
#include <gtest/gtest.h>

#include <string>

#include "volguide/integrators/integrator_configuration.h"
#include "volguide/integrators/guided/prepass/training_file.h"

namespace volguide {
namespace {

TrainingFile example() {
    TrainingFile f;
    f.scene = "0123456789abcdef";
    f.scene_file = "scenes/fog.xml";
    f.integrator = "guided_volpath{photons=1000}";
    f.seed = 42;
    f.prepass = std::string("\0field bytes\xff", 13);
    return f;
}

TEST(TrainingFile, RoundTripIsExact) {
    const TrainingFile f = example();
    const TrainingFile g = deserialize_training(serialize_training(f));
    EXPECT_EQ(g.scene, f.scene);
    EXPECT_EQ(g.scene_file, f.scene_file);
    EXPECT_EQ(g.integrator, f.integrator);
    EXPECT_EQ(g.seed, f.seed);
    EXPECT_EQ(g.prepass, f.prepass);
}

TEST(TrainingFile, EveryFlippedByteAndEveryTruncationIsRejected) {
    const std::string bytes = serialize_training(example());
    for (size_t i = 0; i < bytes.size(); ++i) {
        std::string bad = bytes;
        bad[i] ^= 0x10;
        EXPECT_THROW(deserialize_training(bad), TrainingFileError) << "byte " << i;
    }
    for (size_t n = 0; n < bytes.size(); ++n)
        EXPECT_THROW(deserialize_training(bytes.substr(0, n)), TrainingFileError) << "length " << n;
}

TEST(TrainingFile, MismatchNamesTheConfigurationOrTheScene) {
    const TrainingFile f = example();
    EXPECT_EQ(training_mismatch(f, f.scene, f.integrator), "");
    EXPECT_EQ(training_mismatch(f, "other", f.integrator).rfind("trained for another scene", 0), 0u);
    EXPECT_EQ(training_mismatch(f, f.scene, "guided_volpath{photons=2}").rfind(
                  "trained with another integrator configuration", 0),
              0u);
}

TEST(IntegratorConfiguration, SortedParametersWithoutOutputFiles) {
    Properties p("integrator", "guided_volpath", SourceLocation{"s.xml", 3});
    p.set("photons", "integer", int64_t(1000), {});
    p.set("distance", "string", std::string("incremental"), {});
    p.set("save_field", "string", std::string("f.bin"), {});
    p.set("training_fraction", "float", 0.25, {});
    EXPECT_EQ(integrator_configuration(p),
              "guided_volpath{distance=\"incremental\", photons=1000, training_fraction=0.25}");
}

}  // namespace
}  // namespace volguide
