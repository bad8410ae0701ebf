#pragma once
// Helpers for the scene loader tests: a scratch directory for small XML files and a fake object
// factory that records what the loader passed to it (no real plugins needed).
#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "volguide/core/error.h"
#include "volguide/scene/loader.h"

namespace volguide::test {

class ScratchDir {
  public:
    ScratchDir() {
        std::string templ = (std::filesystem::temp_directory_path() / "volguide_loader_XXXXXX").string();
        if (!mkdtemp(templ.data())) throw std::runtime_error("mkdtemp failed");
        path_ = templ;
    }
    ~ScratchDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;

    // Writes `content` to `relative` (creating folders) and returns the full path.
    std::string write(const std::string& relative, const std::string& content) const {
        std::filesystem::path p = path_ / relative;
        std::filesystem::create_directories(p.parent_path());
        std::ofstream(p) << content;
        return p.string();
    }
    std::string path(const std::string& relative = "") const { return (path_ / relative).string(); }

  private:
    std::filesystem::path path_;
};

// Records its tag and a copy of the Properties it was built from.
struct FakeObject : Object {
    std::string tag;
    Properties props;
    FakeObject(std::string t, Properties p) : tag(std::move(t)), props(std::move(p)) {}
};

// Accepts everything: marks all parameters used. A plugin type named "strict" reads nothing, so
// the loader's unused-parameter check fires.
inline ObjectPtr fake_factory(const std::string& tag, const Properties& props) {
    if (props.type() != "strict")
        for (const auto& e : props.entries()) e.used = true;
    return std::make_shared<FakeObject>(tag, props);
}

inline Properties load_fake(const std::string& path, const LoadOptions& options = {}) {
    return load_scene_properties(path, options, fake_factory);
}

// The n-th child object of `category` in `props`, as a FakeObject.
inline std::shared_ptr<FakeObject> child(const Properties& props, const std::string& category, size_t n = 0) {
    auto kids = props.children(category);
    if (n >= kids.size()) return nullptr;
    return std::dynamic_pointer_cast<FakeObject>(std::get<ObjectPtr>(kids[n]->value));
}

// Runs `f`, expecting an InputError at file:line whose message contains `needle`.
template <typename F>
void expect_input_error(F&& f, const std::string& file, int line, const std::string& needle) {
    try {
        f();
        ADD_FAILURE() << "expected InputError at " << file << ":" << line << " containing \"" << needle
                      << "\"";
    } catch (const InputError& e) {
        EXPECT_EQ(e.location().file, file) << e.what();
        EXPECT_EQ(e.location().line, line) << e.what();
        EXPECT_NE(e.message().find(needle), std::string::npos) << "message: " << e.what();
    }
}

inline std::string scene(const std::string& body) {
    return "<scene version=\"3.0.0\">\n" + body + "</scene>\n";
}

}  // namespace volguide::test
