// SPDX-License-Identifier: MIT
// A report written whole or not at all (writeFileAtomically, include/infocus/report.h).
#include <filesystem>
#include <fstream>

#include "infocus/report.h"

namespace infocus {

Status writeFileAtomically(const std::string& path, const std::string& text) {
    const std::string tmp = path + ".part";
    {
        std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
        if (!f)
            return makeError(ErrorKind::Io, "cannot write " + tmp +
                                                ": check that the folder exists and is writable");
        f.write(text.data(), static_cast<std::streamsize>(text.size()));
        f.flush();
        if (!f) {
            std::error_code ec;
            std::filesystem::remove(tmp, ec);
            return makeError(ErrorKind::Io, "writing " + tmp + " failed (disk full?); " + path +
                                                " is left as it was");
        }
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        return makeError(ErrorKind::Io, "cannot replace " + path + ": " + ec.message());
    }
    return {};
}

}  // namespace infocus
