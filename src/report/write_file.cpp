// SPDX-License-Identifier: MIT
// A report written whole or not at all (writeFileAtomically, include/infocus/report.h).
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "infocus/report.h"

namespace infocus {

namespace fs = std::filesystem;

namespace {

// The file a path names once its symbolic links are followed (the path itself when it is no
// link), so that a link is written through and stays a link; empty past 40 links (a loop).
fs::path followLinks(fs::path p) {
    for (int hops = 0; hops < 40; ++hops) {
        std::error_code ec;
        if (!fs::is_symlink(fs::symlink_status(p, ec))) return p;
        const fs::path target = fs::read_symlink(p, ec);
        if (ec) return p;
        p = target.is_absolute() ? target : p.parent_path() / target;
    }
    return {};
}

// Writes @p text to a device, a FIFO or a socket as it is: a rename would replace the node
// with a regular file (as root, -o /dev/full would destroy the device).
Status writeDirectly(const std::string& path, const std::string& text) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0)
        return makeError(ErrorKind::Io, "cannot write " + path + ": " + std::strerror(errno));
    size_t done = 0;
    int err = 0;
    while (done < text.size()) {
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            err = n < 0 ? errno : EIO;
            break;
        }
        done += static_cast<size_t>(n);
    }
    if (::close(fd) != 0 && err == 0 && errno != EINTR) err = errno;
    if (err)
        return makeError(ErrorKind::Io, "writing " + path + " failed: " + std::strerror(err) +
                                            "; write the report to a file instead");
    return {};
}

}  // namespace

Status writeFileAtomically(const std::string& path, const std::string& text) {
    const fs::path target = followLinks(path);
    if (target.empty())
        return makeError(ErrorKind::Io, "cannot write " + path +
                                            ": too many symbolic links (a loop?); give a file");
    std::error_code ec;
    const fs::file_status status = fs::status(target, ec);
    if (fs::is_directory(status))
        return makeError(ErrorKind::Io, "cannot write " + path +
                                            ": it is a directory; give a "
                                            "file name, e.g. report.html");
    if (fs::exists(status) && !fs::is_regular_file(status)) return writeDirectly(path, text);

    const std::string file = target.string();
    const std::string tmp = file + ".part";
    {
        std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
        if (!f)
            return makeError(ErrorKind::Io, "cannot write " + tmp +
                                                ": check that the folder exists and is writable");
        f.write(text.data(), static_cast<std::streamsize>(text.size()));
        f.flush();
        if (!f) {
            fs::remove(tmp, ec);
            return makeError(ErrorKind::Io, "writing " + tmp + " failed (disk full?); " + path +
                                                " is left as it was");
        }
    }
    fs::rename(tmp, file, ec);
    if (ec) {
        const std::string why = ec.message();
        fs::remove(tmp, ec);
        return makeError(ErrorKind::Io, "cannot replace " + path + ": " + why);
    }
    return {};
}

}  // namespace infocus
