#pragma once
// Warnings from library code (e.g. "sampler 'stratified' is sampled independently"). The library
// never writes to the terminal itself: warnings go to a handler the application may replace. The
// default handler prints `volguide: warning: FILE:LINE: message` to stderr.
#include <fmt/format.h>

#include <functional>
#include <string>

#include "volguide/core/error.h"

namespace volguide {

using WarningHandler = std::function<void(const SourceLocation& loc, const std::string& message)>;

// Replaces the handler (thread-safe); returns the previous one. An empty handler restores the default.
WarningHandler set_warning_handler(WarningHandler handler);
void emit_warning(const SourceLocation& loc, const std::string& message);

template <typename... Args>
void warn(const SourceLocation& loc, fmt::format_string<Args...> f, Args&&... args) {
    emit_warning(loc, fmt::format(f, std::forward<Args>(args)...));
}

}  // namespace volguide
