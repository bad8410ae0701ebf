#pragma once
// Input errors carry the file and line they came from. The CLI prints them as one line
// `volguide: FILE:LINE: message` and exits 1; library code never exits.
#include <fmt/format.h>

#include <stdexcept>
#include <string>

namespace volguide {

struct SourceLocation {
    std::string file;  // as given by the user (or resolved path)
    int line = 0;      // 1-based; 0 = unknown
    std::string str() const { return line > 0 ? fmt::format("{}:{}", file, line) : file; }
};

class InputError : public std::runtime_error {
public:
    InputError(SourceLocation loc, const std::string& msg)
        : std::runtime_error(loc.file.empty() ? msg : loc.str() + ": " + msg), loc_(std::move(loc)), msg_(msg) {}
    const SourceLocation& location() const { return loc_; }
    const std::string& message() const { return msg_; }

private:
    SourceLocation loc_;
    std::string msg_;
};

template <typename... Args>
[[noreturn]] void fail(const SourceLocation& loc, fmt::format_string<Args...> f, Args&&... args) {
    throw InputError(loc, fmt::format(f, std::forward<Args>(args)...));
}

// An error about a whole file (no line: a binary file or one read by a library).
[[noreturn]] inline void fail_file(const std::string& path, const std::string& what) {
    throw InputError(SourceLocation{path, 0}, what);
}

}  // namespace volguide
