#pragma once
// Scene parameters: <default name value> declarations, -D overrides and `$name` substitution in
// attribute values.
#include <map>
#include <string>
#include <string_view>

#include "volguide/core/error.h"

namespace volguide {

class SceneParameters {
  public:
    explicit SceneParameters(std::map<std::string, std::string> overrides = {})
        : overrides_(std::move(overrides)) {}

    // The first declaration of a name wins (later ones, e.g. in included files, are ignored, as in
    // Mitsuba); an override replaces the declared value.
    void declare(const std::string& name, const std::string& value, const SourceLocation& loc);
    bool is_declared(const std::string& name) const { return declared_.count(name) != 0; }
    // Every override must name a declared default; `scene` locates the error.
    void check_overrides(const SourceLocation& scene) const;

    // Replaces each `$name` by its value; the longest declared name matching after the '$' wins.
    // `\$` stands for a literal '$'. Any other '$' is an error at `loc`.
    // A value containing `$other` is expanded in turn.
    std::string substitute(std::string_view text, const SourceLocation& loc, int depth = 0) const;

  private:
    std::map<std::string, std::string> overrides_;
    std::map<std::string, std::string> declared_;  // name → effective value
};

}  // namespace volguide
