// SPDX-License-Identifier: MIT
// A fresh directory for a test's files, removed with everything in it when the test is done, so
// that test runs leave nothing behind in the temporary directory.
#pragma once
#include <stdlib.h>

#include <filesystem>
#include <stdexcept>
#include <string>

namespace infocus::test {

/// A new directory under the system's temporary directory, named @p prefix and six random
/// characters; removed, with its contents, on destruction.
class ScratchDir {
public:
    explicit ScratchDir(const std::string& prefix) {
        std::string tmpl = (std::filesystem::temp_directory_path() / (prefix + "XXXXXX")).string();
        if (::mkdtemp(tmpl.data()) == nullptr)
            throw std::runtime_error("cannot create a scratch directory from " + tmpl);
        path_ = tmpl;
    }
    ~ScratchDir() {
        std::error_code ignored;  // a failed clean-up must not fail the test that ran
        std::filesystem::remove_all(path_, ignored);
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;

    /// The directory.
    const std::string& path() const { return path_; }
    /// The path of @p name inside it.
    std::string file(const std::string& name) const { return path_ + "/" + name; }

private:
    std::string path_;
};

}  // namespace infocus::test
