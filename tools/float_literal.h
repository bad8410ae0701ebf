#pragma once
// A C++ float literal for a value, valid for every value ("0.f", "1.5f", "1e-05f"), with the given
// significant digits (9 read back as the same float). Shared by the table generators.
#include <cstdio>
#include <string>

inline std::string float_literal(double x, int significant_digits) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "%.*g", significant_digits, x);
    std::string s = buf;
    if (s.find_first_of(".e") == std::string::npos) s += ".";
    return s + "f";
}
