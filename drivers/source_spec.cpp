// SPDX-License-Identifier: MIT
#include <sys/stat.h>

#include "infocus/source.h"

namespace infocus {

namespace {

bool exists(const std::string& path) {
    struct stat st;
    return ::stat(path.c_str(), &st) == 0;
}

std::vector<std::string> split(std::string_view s, char sep) {
    std::vector<std::string> out;
    size_t start = 0;
    while (true) {
        const size_t pos = s.find(sep, start);
        out.emplace_back(s.substr(start, pos == std::string_view::npos ? s.npos : pos - start));
        if (pos == std::string_view::npos) break;
        start = pos + 1;
    }
    return out;
}

}  // namespace

Result<SourceSpec> parseSourceSpec(std::string_view text) {
    SourceSpec spec;
    spec.text = std::string(text);
    if (text.empty())
        return makeError(ErrorKind::Usage,
                         "empty source; give a camera (v4l2:/dev/video0, libcamera:0), sim:, or a "
                         "path to a recording, video or image(s)");

    std::string_view rest = text;
    static constexpr std::string_view kKinds[] = {"v4l2", "libcamera", "sim"};
    for (std::string_view k : kKinds) {
        if (rest.size() > k.size() && rest.substr(0, k.size()) == k && rest[k.size()] == ':') {
            spec.kind = std::string(k);
            rest.remove_prefix(k.size() + 1);
            break;
        }
        if (rest == k && k == "sim") {
            spec.kind = "sim";
            rest = {};
            break;
        }
    }
    if (spec.kind.empty()) {
        // A path that exists as written is taken whole, commas and all.
        if (exists(spec.text)) {
            spec.kind = spec.text.rfind("/dev/video", 0) == 0 ? "v4l2" : "path";
            spec.target = spec.text;
            return spec;
        }
        spec.kind = rest.substr(0, 10) == "/dev/video" ? "v4l2" : "path";
    }

    auto parts = split(rest, ',');
    size_t first = 0;
    if (!parts.empty() && parts[0].find('=') == std::string::npos) {
        spec.target = parts[0];
        first = 1;
    }
    for (size_t i = first; i < parts.size(); ++i) {
        const std::string& p = parts[i];
        if (p.empty()) continue;
        const size_t eq = p.find('=');
        if (eq == std::string::npos || eq == 0)
            return makeError(ErrorKind::Usage, "source '" + spec.text + "': option '" + p +
                                                   "' is not of the form key=value");
        const std::string key = p.substr(0, eq);
        if (spec.options.count(key))
            return makeError(ErrorKind::Usage,
                             "source '" + spec.text + "': option '" + key + "' given twice");
        spec.options[key] = p.substr(eq + 1);
    }
    if (spec.kind == "sim" && !spec.target.empty())
        return makeError(ErrorKind::Usage, "source '" + spec.text +
                                               "': sim: takes only key=value options, e.g. "
                                               "sim:scene=tilted,focus=1.2m");
    if (spec.kind == "path" && spec.target.empty())
        return makeError(ErrorKind::Usage, "source '" + spec.text +
                                               "' names no file; give a path, or prefix a "
                                               "camera with v4l2: or libcamera:");
    return spec;
}

}  // namespace infocus
