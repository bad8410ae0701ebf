#pragma once
// Strict parsing of the numbers and lists found in scene attribute values.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace volguide {

// Splits on commas and whitespace, dropping empty pieces ("1, 2 3" → {"1", "2", "3"}).
std::vector<std::string_view> tokenize_list(std::string_view text);
// Splits on one separator character, keeping empty pieces ("400:" → {"400", ""}).
std::vector<std::string_view> split_on(std::string_view text, char separator);

std::string_view trim(std::string_view text);

// The whole (trimmed) text must be a number: "1.0x", "", "1 2" are rejected. NaN is always
// rejected; ±infinity only when allow_infinity.
std::optional<double> parse_double(std::string_view text, bool allow_infinity = false);
std::optional<int64_t> parse_int64(std::string_view text);
// "true" / "false", case-insensitive (as Mitsuba).
std::optional<bool> parse_bool(std::string_view text);

// The piecewise-linear spectra of <spectrum>: wavelength:value pairs ("400:0.1, 500:0.5") and .spd
// files (one "wavelength value" pair per line, '#' comments). Each appends what it reads and returns
// the error message (empty when all is well), which the caller reports at the element's line; the
// last checks that there are two pairs or more and that the wavelengths increase strictly.
std::string parse_spectrum_pairs(std::string_view text, std::vector<double>& wavelengths,
                                 std::vector<double>& values);
std::string read_spd_file(const std::string& path, std::vector<double>& wavelengths, std::vector<double>& values);
std::string check_spectrum_wavelengths(const std::vector<double>& wavelengths);

}  // namespace volguide
