#pragma once
// Runs the volguide CLI as a user would and captures its exit code and output.
#include <filesystem>
#include <string>
#include <vector>

namespace volguide::test {

struct CliResult {
    int exit_code = -1;
    std::string out, err;
};

// Arguments are shell-quoted; stdin is /dev/null.
CliResult run_cli(const std::vector<std::string>& args);

// A fresh, empty temporary directory, removed by the destructor.
class TempDir {
public:
    explicit TempDir(const std::string& tag);
    ~TempDir();
    const std::filesystem::path& path() const { return path_; }
    std::string file(const std::string& name) const { return (path_ / name).string(); }
    // Writes `text` to name and returns the full path.
    std::string write(const std::string& name, const std::string& text) const;

private:
    std::filesystem::path path_;
};

std::string read_file(const std::string& path);

}  // namespace volguide::test
