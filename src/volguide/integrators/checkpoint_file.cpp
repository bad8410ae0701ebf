#include "volguide/integrators/checkpoint_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "volguide/core/bytes.h"
#include "volguide/core/fnv1a.h"

namespace volguide {

namespace {

constexpr char kMagic[8] = {'V', 'G', 'C', 'K', 'P', 'T', 0, 0};

void put_identity(ByteWriter& w, const CheckpointIdentity& id) {
    w.bytes(id.scene);
    w.bytes(id.scene_file);
    w.bytes(id.build);
    w.bytes(id.integrator);
    w.u64(id.options.size());
    for (const auto& [name, value] : id.options) {
        w.bytes(name);
        w.bytes(value);
    }
}

CheckpointIdentity get_identity(ByteReader& r) {
    CheckpointIdentity id;
    id.scene = r.bytes("scene fingerprint");
    id.scene_file = r.bytes("scene file");
    id.build = r.bytes("build identity");
    id.integrator = r.bytes("integrator configuration");
    const uint64_t n = r.u64("option count");
    if (n > r.left() / 16) r.fail("truncated in", "options");  // each option takes two lengths at least
    for (uint64_t i = 0; i < n; ++i) {
        std::string name = r.bytes("option name");
        id.options.emplace_back(std::move(name), r.bytes("option value"));
    }
    return id;
}

uint64_t checksum_of(const std::string& bytes, size_t body_end) {
    return fnv1a64(std::string_view(bytes).substr(sizeof(kMagic), body_end - sizeof(kMagic)));
}

// Writes all of `bytes` to `path` and fsyncs it; "" or the reason.
std::string write_synced(const std::string& path, const std::string& bytes) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) return std::string("cannot create ") + path + ": " + std::strerror(errno);
    size_t done = 0;
    std::string error;
    while (done < bytes.size() && error.empty()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno != EINTR) error = std::string("write failed: ") + std::strerror(errno);
        if (n > 0) done += size_t(n);
    }
    if (error.empty() && ::fsync(fd) != 0) error = std::string("fsync failed: ") + std::strerror(errno);
    if (::close(fd) != 0 && error.empty()) error = std::string("close failed: ") + std::strerror(errno);
    return error;
}

// The rename is durable once the folder's entry is on disk too.
void sync_folder(const std::string& path) {
    std::string dir = std::filesystem::path(path).parent_path().string();
    if (dir.empty()) dir = ".";
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;  // the file is in place; only its durability across a power cut is unknown
    ::fsync(fd);
    ::close(fd);
}

std::string option_mismatch(const CheckpointIdentity& saved, const CheckpointIdentity& current) {
    for (const auto& [name, value] : current.options) {
        std::string was = "(none)";
        for (const auto& [n, v] : saved.options)
            if (n == name) was = v;
        if (was != value) return "written with " + name + " " + was + " (this render: " + value + ")";
    }
    if (saved.options.size() != current.options.size()) return "written with other options";
    return "";
}

}  // namespace

std::string serialize_checkpoint(const Checkpoint& checkpoint) {
    ByteWriter w;
    w.u32(kCheckpointFormatVersion);
    put_identity(w, checkpoint.identity);
    w.bytes(serialize_render_state(checkpoint.state));
    std::string s(kMagic, sizeof(kMagic));
    s += w.str();
    ByteWriter sum;
    sum.u64(checksum_of(s, s.size()));
    return s + sum.str();
}

Checkpoint deserialize_checkpoint(const std::string& bytes) {
    if (bytes.size() < sizeof(kMagic) + 12 || std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0)
        throw CheckpointError("not a volguide checkpoint (bad magic; write one with `volguide render --checkpoint`)");
    const size_t body_end = bytes.size() - 8;
    const std::string checksum = bytes.substr(body_end);  // ByteReader keeps a reference: not a temporary
    ByteReader tail(checksum, "checkpoint");
    if (tail.u64("checksum") != checksum_of(bytes, body_end))
        throw CheckpointError("checkpoint checksum mismatch (corrupt or truncated file)");
    const std::string body = bytes.substr(sizeof(kMagic), body_end - sizeof(kMagic));
    try {
        ByteReader r(body, "checkpoint");
        const uint32_t version = r.u32("version");
        if (version != kCheckpointFormatVersion)
            throw CheckpointError("unsupported checkpoint version " + std::to_string(version) + " (this build reads " +
                                  std::to_string(kCheckpointFormatVersion) + ")");
        Checkpoint c;
        c.identity = get_identity(r);
        c.state = deserialize_render_state(r.bytes("render state"));
        r.finish();
        return c;
    } catch (const CheckpointError&) {
        throw;
    } catch (const std::runtime_error& e) {
        throw CheckpointError(std::string("malformed checkpoint: ") + e.what());
    }
}

void save_checkpoint(const std::string& path, const Checkpoint& checkpoint) {
    const std::string tmp = path + ".tmp";
    const std::string error = write_synced(tmp, serialize_checkpoint(checkpoint));
    if (!error.empty()) {
        std::remove(tmp.c_str());
        throw CheckpointError("cannot write the checkpoint: " + error);
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        const std::string reason = std::strerror(errno);
        std::remove(tmp.c_str());
        throw CheckpointError("cannot write the checkpoint: rename failed: " + reason);
    }
    sync_folder(path);
}

Checkpoint load_checkpoint(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw CheckpointError("cannot open the checkpoint");
    std::ostringstream buf;
    buf << in.rdbuf();
    return deserialize_checkpoint(buf.str());
}

std::string checkpoint_mismatch(const CheckpointIdentity& saved, const CheckpointIdentity& current) {
    if (saved.build != current.build)
        return "written by another build (" + saved.build + "; this one is " + current.build + ")";
    if (saved.integrator != current.integrator)
        return "written with another integrator configuration (" + saved.integrator + "; this scene's is " +
               current.integrator + ")";
    if (saved.scene != current.scene)
        return "written for another scene (" + saved.scene_file + ", fingerprint " + saved.scene + "; this scene's is " +
               current.scene + ")";
    return option_mismatch(saved, current);
}

}  // namespace volguide
