// SPDX-License-Identifier: MIT
// Positions files (frame,position,unit rows): `stack --positions`, `check` and focus brackets.
#include "replay/positions_csv.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include "infocus/stack.h"
#include "src/core/read_number.h"

namespace infocus {

namespace replay {

namespace {

std::string trim(std::string s) {
    const auto notSpace = [](unsigned char c) { return !std::isspace(c); };
    s.erase(s.begin(), std::find_if(s.begin(), s.end(), notSpace));
    s.erase(std::find_if(s.rbegin(), s.rend(), notSpace).base(), s.end());
    return s;
}

}  // namespace

Result<std::vector<PositionRow>> readPositionRows(const std::string& path) {
    std::ifstream in(path);
    if (!in) {
        const int err = errno;
        return makeError(ErrorKind::NotFound, "cannot read the positions file '" + path +
                                                  "': " + std::strerror(err) +
                                                  "; give a CSV of frame,position,unit rows");
    }
    std::map<long, PositionRow> rows;
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        const std::string where = path + " line " + std::to_string(number) + ": ";
        line = trim(line);
        if (line.empty() || line[0] == '#') continue;
        std::vector<std::string> cells;
        std::stringstream ss(line);
        for (std::string c; std::getline(ss, c, ',');)
            cells.push_back(trim(c));
        if (cells.size() == 3 && cells[0] == "frame" && cells[1] == "position") continue;
        if (cells.size() != 3)
            return makeError(ErrorKind::Usage,
                             where + "'" + line + "' is not frame,position,unit (e.g. 0,1.25,dpt)");
        long frame = 0;
        if (!readsWhole(cells[0], frame) || frame < 0)
            return makeError(ErrorKind::Usage,
                             where + "frame '" + cells[0] + "' is not a frame number from 0");
        LensPosition p;
        const std::string& unit = cells[2];
        if (unit == "m" && cells[1] == "inf") {
            p.value = HUGE_VAL;
        } else if (const std::string_view v = std::string_view(cells[1]).substr(
                       cells[1].starts_with('+') ? 1 : 0);  // "+20": a stage's Z as printed
                   !readsWhole(v, p.value) || !std::isfinite(p.value)) {
            return makeError(ErrorKind::Usage,
                             where + "position '" + cells[1] + "' is not a finite number");
        }
        if (unit.empty() || unit.find_first_of(" \"") != std::string::npos)
            return makeError(ErrorKind::Usage,
                             where + "give a unit: dpt, m, or the axis's own (mm, um, steps)");
        if (unit == "dpt" || unit == "dioptre") {
            if (p.value < 0)
                return makeError(ErrorKind::Usage, where + "a lens focus of " + cells[1] +
                                                       " dpt lies beyond infinity");
            p.unit = "dioptre";
            p.dioptres = p.value;
        } else if (unit == "m") {
            if (!(p.value > 0))
                return makeError(ErrorKind::Usage,
                                 where + "a focused distance must be above 0 m (or inf)");
            p.unit = "m";
            p.dioptres = 1.0 / p.value;
        } else {
            p.unit = unit;
        }
        if (!rows.emplace(frame, PositionRow{p, number}).second)
            return makeError(ErrorKind::Usage,
                             where + "frame " + cells[0] + " is given a second time");
    }
    std::vector<PositionRow> out;
    for (const auto& [frame, p] : rows) {
        if (frame != static_cast<long>(out.size()))
            return makeError(ErrorKind::Usage, path + ": frame " + std::to_string(out.size()) +
                                                   " has no row (frames count from 0, each once)");
        out.push_back(p);
    }
    if (out.empty()) return makeError(ErrorKind::Usage, path + " holds no frame,position,unit row");
    return out;
}

}  // namespace replay

Result<std::vector<LensPosition>> readPositionsCsv(const std::string& path) {
    auto rows = replay::readPositionRows(path);
    if (!rows) return rows.error();
    std::vector<LensPosition> out;
    out.reserve(rows->size());
    for (const replay::PositionRow& r : *rows)
        out.push_back(r.position);
    return out;
}

}  // namespace infocus
