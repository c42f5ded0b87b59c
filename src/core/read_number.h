// SPDX-License-Identifier: MIT
/// @file read_number.h
/// Whole-value number readers shared by the parsers of the command line, the file sources and
/// the JSON records. Internal to infocus.
#pragma once

#include <charconv>
#include <cstdint>
#include <optional>
#include <string_view>
#include <system_error>

namespace infocus {

/// Whether @p text, all of it, reads as a number into @p value (nothing before or after it).
template <class T>
bool readsWhole(std::string_view text, T& value) {
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    return !text.empty() && ec == std::errc() && end == text.data() + text.size();
}

/// The JSON value @p v (nlohmann::json or ordered_json) as an integer within [@p lo, @p hi];
/// empty for a float, a string or an integer out of range, which a plain get<int>() would cast
/// silently (4294967297 read as 1) or, for a float past the type's range, undefinedly.
template <class Json>
std::optional<int64_t> jsonInteger(const Json& v, int64_t lo, int64_t hi) {
    if (!v.is_number_integer()) return std::nullopt;
    // An unsigned value past INT64_MAX is out of every range an int64_t can ask for.
    if (v.is_number_unsigned() && v.template get<uint64_t>() > static_cast<uint64_t>(INT64_MAX))
        return std::nullopt;
    const auto x = v.template get<int64_t>();
    if (x < lo || x > hi) return std::nullopt;
    return x;
}

}  // namespace infocus
