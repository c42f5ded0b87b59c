// SPDX-License-Identifier: MIT
// `python`: bench_python.py, run by the Python the module was built for, times infocus.analyze
// against OpenCV's Laplacian variance per region in a Python loop, and two Python threads
// against one. The script sits beside this module (build tree and installation alike).
#include <nlohmann/json.hpp>

#include <sys/stat.h>
#include <cstdio>
#include <string>

#include "bench/bench.h"
#include "infocus_config.h"
#include "src/core/module_loader.h"

namespace infocus::bench {

namespace {

std::string shellQuoted(const std::string& s) {
    std::string q = "'";
    for (char c : s)
        q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

bool isFile(const std::string& path) {
    struct stat st;
    return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

// Runs @p command and returns its standard output, or nothing when it cannot start or fails.
std::optional<std::string> commandOutput(const std::string& command) {
    FILE* p = ::popen(command.c_str(), "r");
    if (!p) return std::nullopt;
    std::string text;
    char buffer[4096];
    for (size_t n; (n = std::fread(buffer, 1, sizeof buffer, p)) > 0;)
        text.append(buffer, n);
    if (::pclose(p) != 0) return std::nullopt;
    return text;
}

}  // namespace

void benchPython(const BenchOptions& options, const RowSink& sink) {
    BenchRow row{
        "python", 1920,         1080,
        0.0,      std::nullopt, "cv2.Laplacian(region, CV_64F).var() per region in a Python loop",
        ""};
    BenchRow threads{"python_threads",
                     1920,
                     1080,
                     0.0,
                     std::nullopt,
                     "the same frames from one Python thread",
                     ""};
    const auto fail = [&](const std::string& why) {
        row.note = threads.note = why;
        sink(row);
        sink(threads);
    };
    const std::string python = INFOCUS_PYTHON;
    if (python.empty())
        return fail(
            "no Python module in this build (meson feature 'python': pybind11-dev, "
            "python3-dev and python3-numpy)");
    std::string script, pythonPath;
    for (const std::string& dir : moduleSearchPath("bench"))
        if (script.empty() && isFile(dir + "/bench_python.py")) script = dir + "/bench_python.py";
    // The module of the build tree when this is the build tree's executable; an installed one
    // is in Python's own path.
    for (const std::string& dir : moduleSearchPath("src/py"))
        pythonPath += (pythonPath.empty() ? "" : ":") + dir;
    if (script.empty()) return fail("bench_python.py is not beside infocus-bench.so; reinstall");
    const auto text =
        commandOutput("PYTHONPATH=" + shellQuoted(pythonPath) + " " + shellQuoted(python) + " " +
                      shellQuoted(script) + " " + std::to_string(options.secondsPerCase));
    if (!text) return fail(python + " " + script + " failed; run it by hand to see why");
    const auto j = nlohmann::json::parse(*text, nullptr, false);
    if (j.is_discarded() || !j.is_object()) return fail("bench_python.py printed no JSON");
    if (j.contains("error")) return fail(j["error"].get<std::string>());
    const double full = j["full_ms"].get<double>();
    row.ms = j["sharpness_ms"].get<double>();
    if (j["recipe_ms"].is_number()) row.baselineMs = j["recipe_ms"].get<double>();
    char note[240];
    std::snprintf(note, sizeof note,
                  "16x9 regions, infocus.analyze(frame, blur=False) from Python, OpenCV one "
                  "thread%s; with blur %.2f ms; target 10x",
                  row.baselineMs ? "" : " (python3-opencv missing: no baseline)", full);
    row.note = note;
    threads.ms = j["two_threads_ms"].get<double>();
    threads.baselineMs = j["one_thread_ms"].get<double>();
    threads.note =
        "32 frames, infocus.analyze(frame, blur=False) shared by two Python threads, ms a frame "
        "of the whole run: the GIL is released while it measures";
    sink(row);
    sink(threads);
}

}  // namespace infocus::bench
