#include "volguide/integrators/guided/prepass/training_file.h"

#include <cstring>
#include <fstream>
#include <sstream>

#include "volguide/core/atomic_write.h"
#include "volguide/core/fingerprint.h"

namespace volguide {

namespace {

constexpr char kMagic[8] = {'V', 'G', 'T', 'R', 'A', 'I', 'N', 0};

void put_uint(std::string& s, uint64_t v, int bytes) {
    for (int i = 0; i < bytes; ++i) s.push_back(char(uint8_t(v >> (8 * i))));
}
void put_string(std::string& s, const std::string& v) {
    put_uint(s, v.size(), 4);
    s += v;
}

struct TrainingFileReader {
    const std::string& bytes;
    size_t pos, end;
    void need(uint64_t n, const char* what) const {
        if (end - pos < n) throw TrainingFileError(std::string("truncated training file (in ") + what + ")");
    }
    uint64_t uint(int n, const char* what) {
        need(uint64_t(n), what);
        uint64_t v = 0;
        for (int i = 0; i < n; ++i) v |= uint64_t(uint8_t(bytes[pos + i])) << (8 * i);
        pos += size_t(n);
        return v;
    }
    std::string string(int length_bytes, const char* what) {
        const uint64_t n = uint(length_bytes, what);
        need(n, what);
        std::string s = bytes.substr(pos, n);
        pos += n;
        return s;
    }
};

}  // namespace

std::string serialize_training(const TrainingFile& file) {
    std::string s(kMagic, sizeof(kMagic));
    put_uint(s, kTrainingFormatVersion, 4);
    put_string(s, file.scene);
    put_string(s, file.scene_file);
    put_string(s, file.integrator);
    put_uint(s, file.seed, 8);
    put_uint(s, file.prepass.size(), 8);
    s += file.prepass;
    put_uint(s, fnv1a64(std::string_view(s).substr(sizeof(kMagic))), 8);
    return s;
}

TrainingFile deserialize_training(const std::string& bytes) {
    if (bytes.size() < sizeof(kMagic) + 12 || std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0)
        throw TrainingFileError("not a volguide training file (bad magic; write one with `volguide train`)");
    const size_t body_end = bytes.size() - 8;
    TrainingFileReader tail{bytes, body_end, bytes.size()};
    if (tail.uint(8, "checksum") != fnv1a64(std::string_view(bytes).substr(sizeof(kMagic), body_end - sizeof(kMagic))))
        throw TrainingFileError("training file checksum mismatch (corrupt or truncated file)");
    TrainingFileReader r{bytes, sizeof(kMagic), body_end};
    const uint64_t version = r.uint(4, "header");
    if (version != kTrainingFormatVersion)
        throw TrainingFileError("unsupported training file version " + std::to_string(version) + " (this build reads " +
                                std::to_string(kTrainingFormatVersion) + ")");
    TrainingFile file;
    file.scene = r.string(4, "scene fingerprint");
    file.scene_file = r.string(4, "scene file");
    file.integrator = r.string(4, "integrator configuration");
    file.seed = r.uint(8, "seed");
    file.prepass = r.string(8, "pre-pass");
    if (r.pos != r.end) throw TrainingFileError("training file has trailing data");
    return file;
}

void save_training(const std::string& path, const TrainingFile& file) {
    const std::string bytes = serialize_training(file);
    const std::string error = write_atomically(path, [&](const std::string& tmp) {
        std::ofstream out(tmp, std::ios::binary);
        out.write(bytes.data(), std::streamsize(bytes.size()));
        out.close();
        if (!out) throw std::runtime_error("write failed");
    });
    if (!error.empty()) throw TrainingFileError("cannot write the training file: " + error);
}

TrainingFile load_training(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw TrainingFileError("cannot open the training file");
    std::ostringstream buf;
    buf << in.rdbuf();
    return deserialize_training(buf.str());
}

std::string prepass_fingerprint(const std::string& prepass) { return fingerprint(prepass); }

std::string training_mismatch(const TrainingFile& file, const std::string& scene_fingerprint,
                              const std::string& integrator_configuration) {
    // The configuration first: the scene's fingerprint covers its file, the integrator included.
    if (file.integrator != integrator_configuration)
        return "trained with another integrator configuration (" + file.integrator + "; this scene's is " +
               integrator_configuration + ")";
    if (file.scene != scene_fingerprint)
        return "trained for another scene (" + file.scene_file + ", fingerprint " + file.scene +
               "; this scene's is " + scene_fingerprint + ")";
    return "";
}

}  // namespace volguide
