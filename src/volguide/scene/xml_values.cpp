#include "volguide/scene/xml_values.h"

#include <fmt/format.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>

namespace volguide {

namespace {
bool is_space(char c) {
    return std::isspace(static_cast<unsigned char>(c)) != 0;
}
}  // namespace

std::vector<std::string_view> tokenize_list(std::string_view text) {
    std::vector<std::string_view> out;
    size_t i = 0;
    while (i < text.size()) {
        while (i < text.size() && (is_space(text[i]) || text[i] == ',')) ++i;
        size_t start = i;
        while (i < text.size() && !is_space(text[i]) && text[i] != ',') ++i;
        if (i > start) out.push_back(text.substr(start, i - start));
    }
    return out;
}

std::vector<std::string_view> split_on(std::string_view text, char separator) {
    std::vector<std::string_view> out;
    size_t start = 0;
    for (size_t i = 0; i <= text.size(); ++i)
        if (i == text.size() || text[i] == separator) {
            out.push_back(text.substr(start, i - start));
            start = i + 1;
        }
    return out;
}

std::string_view trim(std::string_view text) {
    while (!text.empty() && is_space(text.front())) text.remove_prefix(1);
    while (!text.empty() && is_space(text.back())) text.remove_suffix(1);
    return text;
}

std::optional<double> parse_double(std::string_view text, bool allow_infinity) {
    text = trim(text);
    // from_chars rejects a leading '+', which Mitsuba (strtod) accepts.
    if (text.size() > 1 && text.front() == '+' && text[1] != '-' && text[1] != '+') text.remove_prefix(1);
    if (text.empty()) return std::nullopt;
    double value = 0.0;
    auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || ptr != text.data() + text.size()) return std::nullopt;
    if (std::isnan(value)) return std::nullopt;
    if (std::isinf(value) && !allow_infinity) return std::nullopt;
    return value;
}

std::optional<int64_t> parse_int64(std::string_view text) {
    text = trim(text);
    if (text.size() > 1 && text.front() == '+' && text[1] != '-' && text[1] != '+') text.remove_prefix(1);
    if (text.empty()) return std::nullopt;
    int64_t value = 0;
    auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || ptr != text.data() + text.size()) return std::nullopt;
    return value;
}

std::optional<bool> parse_bool(std::string_view text) {
    std::string lower;
    for (char c : trim(text)) lower += char(std::tolower(static_cast<unsigned char>(c)));
    if (lower == "true") return true;
    if (lower == "false") return false;
    return std::nullopt;
}

namespace {

// One number of a spectrum; false with `error` set when it is not a finite number.
bool spectrum_number(std::string_view text, const char* what, double& out, std::string& error) {
    auto v = parse_double(text);
    if (!v) {
        error = fmt::format("<spectrum>: could not parse {} \"{}\" as a finite number", what, text);
        return false;
    }
    out = *v;
    return true;
}

}  // namespace

std::string parse_spectrum_pairs(std::string_view text, std::vector<double>& wavelengths,
                                 std::vector<double>& values) {
    std::string error;
    for (std::string_view token : tokenize_list(text)) {
        auto pair = split_on(token, ':');
        if (pair.size() != 2) return fmt::format("<spectrum>: \"{}\" is not a wavelength:value pair", token);
        double wl = 0, v = 0;
        if (!spectrum_number(pair[0], "wavelength", wl, error) || !spectrum_number(pair[1], "spectrum value", v, error))
            return error;
        wavelengths.push_back(wl);
        values.push_back(v);
    }
    return {};
}

std::string read_spd_file(const std::string& path, std::vector<double>& wavelengths, std::vector<double>& values) {
    std::ifstream in(path);
    if (!in) return fmt::format("<spectrum>: cannot read '{}'", path);
    std::string line, error;
    int n = 0;
    while (std::getline(in, line)) {
        ++n;
        std::string_view text = trim(line);
        if (text.empty() || text.front() == '#') continue;
        auto parts = tokenize_list(text);
        if (parts.size() != 2) return fmt::format("<spectrum>: '{}' line {}: expected \"wavelength value\"", path, n);
        double wl = 0, v = 0;
        if (!spectrum_number(parts[0], "wavelength", wl, error) || !spectrum_number(parts[1], "spectrum value", v, error))
            return error;
        wavelengths.push_back(wl);
        values.push_back(v);
    }
    return {};
}

std::string check_spectrum_wavelengths(const std::vector<double>& wavelengths) {
    if (wavelengths.size() < 2) return "<spectrum> needs at least two wavelength:value pairs";
    for (size_t i = 1; i < wavelengths.size(); ++i)
        if (!(wavelengths[i] > wavelengths[i - 1])) return "<spectrum>: wavelengths must be strictly increasing";
    return {};
}

}  // namespace volguide
