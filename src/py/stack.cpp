// SPDX-License-Identifier: MIT
// infocus.stack: `infocus stack --json` as Python objects, with the focus map, the composite and
// the regions' curves as NumPy arrays.
#include <pybind11/stl.h>

#include <cmath>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "infocus/output.h"
#include "infocus/stack.h"
#include "py_infocus.h"

namespace infocus::py {

void registerStack(pb::module_& m) {
    m.def(
        "stack",
        [](const std::string& source, std::pair<int, int> grid,
           const std::variant<std::monostate, std::string, std::vector<LensPosition>>& positions,
           const std::string& metric, bool maps, int step, int threads,
           const pb::object& progress) {
            StackOptions options;
            options.cols = grid.first;
            options.rows = grid.second;
            options.metric = metric;
            options.maps = maps;
            options.mapStepPx = step;
            options.threads =
                threads > 0 ? threads : static_cast<int>(std::thread::hardware_concurrency());
            if (const auto* path = std::get_if<std::string>(&positions))
                options.positions = take(readPositionsCsv(*path));
            else if (const auto* list = std::get_if<std::vector<LensPosition>>(&positions))
                options.positions = *list;
            Progress report(progress);
            if (!report.empty())
                options.progress = [&](uint64_t done, uint64_t total) { report(done, total); };
            std::optional<Result<StackResult>> r;
            {
                pb::gil_scoped_release release;
                r = analyzeStack(source, options);
            }
            report.rethrow();
            const StackResult s = take(std::move(*r));

            // The same object `infocus stack --json` prints, read by Python's own json module.
            pb::dict out = pb::module_::import("json").attr("loads")(stackJson(s));
            const size_t frames = s.frames.size();
            int cols = 0, rows = 0;
            for (const StackRegion& g : s.regions)
                cols = std::max(cols, g.col + 1), rows = std::max(rows, g.row + 1);
            pb::array_t<double> sharp({rows, cols, static_cast<int>(frames)});
            pb::array_t<double> blur({rows, cols, static_cast<int>(frames)});
            auto sm = sharp.mutable_unchecked<3>();
            auto bm = blur.mutable_unchecked<3>();
            for (const StackRegion& g : s.regions)
                for (size_t i = 0; i < frames; ++i) {
                    sm(g.row, g.col, i) =
                        g.usable[i] ? g.sharpness[i] : std::numeric_limits<double>::quiet_NaN();
                    bm(g.row, g.col, i) = g.usable[i] ? orNan(g.blurWidth[i])
                                                      : std::numeric_limits<double>::quiet_NaN();
                }
            out["sharpness_curves"] = sharp;
            out["blur_width_curves"] = blur;
            out["axis"] =
                pb::array_t<double>(static_cast<pb::ssize_t>(s.axis.size()), s.axis.data());
            if (s.map.cols > 0) {
                pb::array_t<float> map({s.map.rows, s.map.cols});
                std::copy(s.map.peakFrame.begin(), s.map.peakFrame.end(), map.mutable_data());
                pb::array_t<uint8_t> composite({s.height, s.width});
                std::copy(s.composite.begin(), s.composite.end(), composite.mutable_data());
                out["focus_map_array"] = map;
                out["composite"] = composite;
            } else {
                out["focus_map_array"] = pb::none();
                out["composite"] = pb::none();
            }
            return out;
        },
        pb::arg("source"), pb::arg("grid") = std::pair<int, int>{8, 6},
        pb::arg("positions") = pb::none(), pb::arg("metric") = "", pb::arg("maps") = true,
        pb::arg("step") = 16, pb::arg("threads") = 0, pb::arg("progress") = pb::none(),
        "Where each region of a focus stack is sharpest: the dict `infocus stack --json` prints, "
        "plus NumPy arrays sharpness_curves and blur_width_curves (rows, cols, frames; NaN "
        "where unmeasured), axis (frames), focus_map_array (peak frame per map cell, NaN "
        "without texture) and composite (all-in-focus luma). positions: a CSV path or a list "
        "of LensPosition, one per frame. threads 0: the machine's cores.");
}

}  // namespace infocus::py
