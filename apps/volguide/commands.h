#pragma once
// The `volguide` commands. Each returns the process exit code; input and I/O errors are
// thrown (volguide::InputError or std::exception) and usage errors as UsageError, and main()
// turns them into one stderr line and exit code 1 or 2.
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace volguide::cli {

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// An error about one file without a line number: printed as `volguide: FILE: message`.
struct FileError : std::runtime_error {
    FileError(std::string file, const std::string& message)
        : std::runtime_error(message), file(std::move(file)) {}
    std::string file;
};

struct RenderArgs {
    std::string scene;
    // Empty: <scene stem>.exr in the current directory. Several outputs (e.g. EXR + PNG preview) are
    // written from one render; the variance image follows the first one.
    std::vector<std::string> outputs;
    std::vector<std::string> defines;  // name=value
    std::optional<int> spp;
    std::optional<double> time;
    std::optional<uint64_t> seed;
    std::optional<int> threads;
    std::string stats;  // JSON file, empty for none
    // --reference: compare with this image during the render (convergence curve in the stats) and
    // after it (printed); empty for none.
    std::string reference;
    bool quiet = false;
    bool variance = false;  // also write the per-sample variance image (as the moment integrator does)
    std::string field;      // --field: a training file of `volguide train`; the render trains nothing
    std::string samples;    // --samples FIRST:COUNT: only these sample indices of every pixel
    // --checkpoint FILE: the render's state, written atomically every checkpoint_every seconds (at the
    // end of a pass) and when it stops; --resume FILE: go on from such a checkpoint (render_checkpoints.h).
    std::string checkpoint;
    double checkpoint_every = 60;
    std::string resume;
};
int run_render(const RenderArgs& args);

struct TrainArgs {
    std::string scene, output;
    std::vector<std::string> defines;
    std::optional<double> time;
    std::optional<int> spp;  // the frame's samples per pixel
    std::optional<uint64_t> seed;
    std::optional<int> threads;
    bool quiet = false;
};
int run_train(const TrainArgs& args);

struct MergeArgs {
    std::vector<std::string> parts;
    std::string output;
};
int run_merge(const MergeArgs& args);

struct DiffArgs {
    std::string image, reference, error_image;
    bool json = false;
    std::optional<double> min_reference;  // compare only pixels whose reference mean exceeds it
};
int run_diff(const DiffArgs& args);

struct ConvertArgs {
    std::string input, output;
    double exposure = 0;  // stops: the image is scaled by 2^exposure
};
int run_convert(const ConvertArgs& args);

// volguide upgrade IN.xml -o OUT.xml [-D name=value]...: a Mitsuba 0.x scene in Mitsuba 3's form.
struct UpgradeArgs {
    std::string scene, output;
    std::vector<std::string> defines;
};
int run_upgrade(const UpgradeArgs& args);

struct InfoArgs {
    std::string scene;
    std::vector<std::string> defines;
    std::string field;  // --field: summarise a saved guiding field instead of a scene
};
int run_info(const InfoArgs& args);

}  // namespace volguide::cli
