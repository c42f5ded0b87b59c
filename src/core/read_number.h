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
#include <utility>

namespace infocus {

/// Whether @p text, all of it, reads as a number into @p value (nothing before or after it).
template <class T>
bool readsWhole(std::string_view text, T& value) {
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    return !text.empty() && ec == std::errc() && end == text.data() + text.size();
}

/// Metres per length unit @p unit, as people write lengths everywhere in infocus (options and
/// source strings alike): m, cm, mm, um or µm, nm. nullopt for any other unit.
inline std::optional<double> metresPerUnit(std::string_view unit) {
    constexpr std::pair<std::string_view, double> kUnits[] = {
        {"m", 1.0}, {"cm", 1e-2}, {"mm", 1e-3}, {"um", 1e-6}, {"µm", 1e-6}, {"nm", 1e-9}};
    for (const auto& [name, scale] : kUnits)
        if (unit == name) return scale;
    return std::nullopt;
}

/// The units metresPerUnit knows, for messages.
inline constexpr std::string_view kLengthUnitNames = "m, cm, mm, um (or µm), nm";

/// @p text, a number followed by a unit metresPerUnit knows ("1.4um", "50 mm"), in metres;
/// nullopt for anything else (no number, no unit, another unit, trailing text).
inline std::optional<double> readLength(std::string_view text) {
    double v = 0.0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || end == text.data()) return std::nullopt;
    std::string_view unit(end, static_cast<size_t>(text.data() + text.size() - end));
    while (!unit.empty() && unit.front() == ' ')
        unit.remove_prefix(1);
    const auto scale = metresPerUnit(unit);
    if (!scale) return std::nullopt;
    return v * *scale;
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
