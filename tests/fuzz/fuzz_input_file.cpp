#include "fuzz_input_file.h"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace volguide::fuzz {

namespace {

// Removed at exit so that millions of runs leave nothing behind.
const std::filesystem::path& private_dir() {
    static const std::filesystem::path dir = [] {
        std::filesystem::path d =
            std::filesystem::temp_directory_path() / ("volguide-fuzz-" + std::to_string(getpid()));
        std::filesystem::create_directories(d);
        return d;
    }();
    static const bool cleanup_registered = [] {
        std::atexit([] {
            std::error_code ec;
            std::filesystem::remove_all(private_dir(), ec);
        });
        return true;
    }();
    (void)cleanup_registered;
    return dir;
}

}  // namespace

std::string write_fuzz_input(const uint8_t* data, size_t size, const std::string& extension) {
    const std::filesystem::path path = private_dir() / ("input" + extension);
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    out.close();
    // A harness that cannot write its input would report nothing for every run: stop loudly instead.
    if (!out) throw std::runtime_error("cannot write the fuzz input " + path.string());
    return path.string();
}

}  // namespace volguide::fuzz
