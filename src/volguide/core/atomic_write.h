#pragma once
// Writes a file through `<path>.tmp-<pid>` and renames it into place, so readers (and an
// interrupted run) never see a partial file.
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>

namespace volguide {

// write(tmp_path) produces the whole file (throwing on failure). Returns "" on success, otherwise
// the reason; the temporary file is removed then and `path` is left untouched.
template <typename WriteFn>
std::string write_atomically(const std::string& path, WriteFn&& write) {
    const std::string tmp = path + ".tmp-" + std::to_string(::getpid());
    std::string error;
    try {
        write(tmp);
    } catch (const std::exception& e) {
        error = e.what();
    }
    if (error.empty() && std::rename(tmp.c_str(), path.c_str()) != 0)
        error = std::string("rename failed: ") + std::strerror(errno);
    if (!error.empty()) std::remove(tmp.c_str());
    return error;
}

}  // namespace volguide
