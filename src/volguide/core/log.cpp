#include "volguide/core/log.h"

#include <cstdio>
#include <mutex>

namespace volguide {

namespace {

std::mutex handler_mutex;
WarningHandler current_handler;

void default_handler(const SourceLocation& loc, const std::string& message) {
    if (loc.file.empty())
        std::fprintf(stderr, "volguide: warning: %s\n", message.c_str());
    else
        std::fprintf(stderr, "volguide: warning: %s: %s\n", loc.str().c_str(), message.c_str());
}

}  // namespace

WarningHandler set_warning_handler(WarningHandler handler) {
    std::lock_guard lock(handler_mutex);
    std::swap(current_handler, handler);
    return handler;
}

void emit_warning(const SourceLocation& loc, const std::string& message) {
    std::lock_guard lock(handler_mutex);
    if (current_handler)
        current_handler(loc, message);
    else
        default_handler(loc, message);
}

}  // namespace volguide
