#pragma once
// Where relative file names in a scene are looked up: the directory of the file that mentions
// them, then the <path> directories (most recently declared first), then the main scene's
// directory. Each directory is kept twice: the real one and the spelling used in messages.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace volguide {

struct ResolvedFile {
    std::filesystem::path path;  // absolute and lexically normal
    std::string display;         // as the user would recognise it (relative to how the scene was named)
};

class FileResolver {
  public:
    struct Dir {
        std::filesystem::path real;
        std::string display;
    };

    explicit FileResolver(Dir main_dir) : main_(std::move(main_dir)) {}
    void add_search_dir(Dir dir) { search_.insert(search_.begin(), std::move(dir)); }

    // `current` is the directory of the file containing the reference. nullopt when not found.
    std::optional<ResolvedFile> resolve(const std::string& name, const Dir& current,
                                        bool want_directory = false) const;

    static std::string join_display(const std::string& dir, const std::string& name);

  private:
    Dir main_;
    std::vector<Dir> search_;
};

}  // namespace volguide
