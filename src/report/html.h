// SPDX-License-Identifier: MIT
// Internal: text helpers of the HTML report: printf-style formatting, escaping and base64.
#pragma once

#include <cstddef>
#include <string>

#include "infocus/analysis.h"

namespace infocus::report_detail {

/// printf into a string of any length.
std::string fmt(const char* f, ...) __attribute__((format(printf, 1, 2)));
/// @p s with the characters HTML gives a meaning (& < > ") escaped.
std::string escapeHtml(const std::string& s);
/// The @p n bytes @p data in base64 (RFC 4648, padded), for data URIs.
std::string base64(const unsigned char* data, size_t n);
/// A region as the report names it: "(column, row)" in the grid.
std::string regionName(const RegionResult& r);

}  // namespace infocus::report_detail
