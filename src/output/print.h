// SPDX-License-Identifier: MIT
/// @file print.h
/// printf-style formatting onto a stream, for the writers whose formats are printf formats (the
/// widths and precisions of a table are easiest to read, and to keep, as "%8.2f"). Internal to
/// infocus.
#pragma once

#include <cstdarg>
#include <cstdio>
#include <ostream>
#include <string>

namespace infocus::output {

/// @p format with the arguments @p args as std::vsnprintf writes them, of any length.
inline std::string vformat(const char* format, va_list args) {
    va_list again;
    va_copy(again, args);
    const int n = std::vsnprintf(nullptr, 0, format, args);
    std::string s(n > 0 ? static_cast<size_t>(n) : 0, '\0');
    if (n > 0) std::vsnprintf(s.data(), s.size() + 1, format, again);
    va_end(again);
    return s;
}

/// @p format with its arguments as std::snprintf writes them, of any length.
[[gnu::format(printf, 1, 2)]] inline std::string format(const char* format, ...) {
    va_list args;
    va_start(args, format);
    std::string s = vformat(format, args);
    va_end(args);
    return s;
}

/// Writes @p format with its arguments to @p out, as std::fprintf would to a FILE.
[[gnu::format(printf, 2, 3)]] inline void print(std::ostream& out, const char* format, ...) {
    va_list args;
    va_start(args, format);
    out << vformat(format, args);
    va_end(args);
}

}  // namespace infocus::output
