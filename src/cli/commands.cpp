// SPDX-License-Identifier: MIT
#include "commands.h"

#include <charconv>
#include <cstdint>
#include <iostream>

namespace infocus::cli {

std::vector<Command> registerCommands(CLI::App& app) {
    // Order here is the order of `infocus --help`.
    return {
        addDevicesCommand(app), addAnalyzeCommand(app), addDofCommand(app),
        addDepthCommand(app),   addRecordCommand(app),  addBenchCommand(app),
    };
}

int reportError(const std::string& command, const Error& error) {
    std::cerr << "infocus " << command << ": " << error.message << "\n";
    return error.kind == ErrorKind::Usage ? kExitUsage : kExitFailure;
}

int usageError(const std::string& command, const std::string& message) {
    std::cerr << "infocus " << command << ": " << message << "\n"
              << "Run 'infocus " << command << " --help' for the options.\n";
    return kExitUsage;
}

CLI::Validator frameCount() {
    return CLI::Validator(
        [](const std::string& text) {
            uint64_t n = 0;
            const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
            if (text.empty() || ec != std::errc() || end != text.data() + text.size())
                return "'" + text + "' is not a frame count; give a whole number ≥ 0, e.g. 100";
            return std::string();
        },
        "N");
}

}  // namespace infocus::cli
