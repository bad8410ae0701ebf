// Replays every seed (tests/fuzz/corpus/<target>/) and every input a fuzzer once broke volguide with
// (tests/fuzz/regression/<target>/) through the same entry points as the fuzzers, in the normal build.
// A reader that crashes, hangs or throws anything but its documented error fails the test.
#include <gtest/gtest.h>

#include <stdlib.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "fuzz_targets.h"

namespace fs = std::filesystem;
using volguide::fuzz::FuzzTarget;

namespace {

std::vector<fs::path> inputs_of(const std::string& target) {
    std::vector<fs::path> files;
    for (const char* kind : {"corpus", "regression"}) {
        const fs::path dir = fs::path(VOLGUIDE_FUZZ_DIR) / kind / target;
        if (!fs::is_directory(dir)) continue;
        for (const auto& e : fs::directory_iterator(dir))
            if (e.is_regular_file()) files.push_back(e.path());
    }
    std::sort(files.begin(), files.end());
    return files;
}

std::string read_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

class FuzzRegression : public testing::TestWithParam<FuzzTarget> {
  protected:
    // The budget the fuzzers run with (scripts/fuzz.sh): inputs whose sizes are refused there must
    // be refused here too, not allocated (one kept input densifies to 7.5 GB within a 23 GB machine).
    void SetUp() override { setenv("VOLGUIDE_MEMORY_LIMIT_MB", "1024", 1); }
    void TearDown() override { unsetenv("VOLGUIDE_MEMORY_LIMIT_MB"); }
};

TEST_P(FuzzRegression, EveryKeptInputIsHandled) {
    const FuzzTarget& target = GetParam();
    const std::vector<fs::path> files = inputs_of(target.name);
    // Every target has seeds: an empty folder would make this test pass without testing anything.
    ASSERT_FALSE(files.empty()) << "no inputs for fuzz target " << target.name;
    for (const fs::path& file : files) {
        SCOPED_TRACE(file.string());
        const std::string bytes = read_bytes(file);
        EXPECT_NO_THROW(target.entry(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()));
    }
}

INSTANTIATE_TEST_SUITE_P(Readers, FuzzRegression, testing::ValuesIn(volguide::fuzz::fuzz_targets()),
                         [](const testing::TestParamInfo<FuzzTarget>& info) { return std::string(info.param.name); });

}  // namespace
