// SPDX-License-Identifier: MIT
#include "parse.h"

#include <vector>

#include "infocus/analysis.h"

namespace infocus::cli {

namespace {

// Splits @p text at @p sep into non-negative integers; nullopt if any part is not one.
std::optional<std::vector<int>> integers(std::string_view text, char sep) {
    std::vector<int> out;
    while (true) {
        const size_t pos = text.find(sep);
        const std::string_view part = text.substr(0, pos);
        int v = 0;
        if (!readsWhole(part, v) || v < 0) return std::nullopt;
        out.push_back(v);
        if (pos == std::string_view::npos) return out;
        text.remove_prefix(pos + 1);
    }
}

}  // namespace

std::optional<std::pair<int, int>> parseGrid(std::string_view text) {
    auto v = integers(text, 'x');
    if (!v || v->size() != 2 || (*v)[0] < 1 || (*v)[1] < 1 || (*v)[0] > kMaxGridSide ||
        (*v)[1] > kMaxGridSide)
        return std::nullopt;
    return std::pair{(*v)[0], (*v)[1]};
}

std::optional<Rect> parseRoi(std::string_view text) {
    auto v = integers(text, ',');
    if (!v || v->size() != 4) return std::nullopt;
    return Rect{(*v)[0], (*v)[1], (*v)[2], (*v)[3]};
}

bool parseTransfer(std::string_view text, AnalysisOptions& options) {
    options.transferFromSource = text == "auto";
    if (options.transferFromSource) {
        options.transfer = TransferFunction::Linear;
        return true;
    }
    const auto tf = transferFunctionFromName(text);
    if (tf) options.transfer = *tf;
    return tf.has_value();
}

std::string gridUsage(std::string_view text) {
    return "--grid " + std::string(text) + ": give columns x rows; " + gridLimitText();
}

std::string transferUsage(std::string_view text) {
    return "--transfer " + std::string(text) +
           ": use linear, srgb, rec709 (JPEG files and most webcams: srgb) or auto (the camera's "
           "or file's own)";
}

}  // namespace infocus::cli
