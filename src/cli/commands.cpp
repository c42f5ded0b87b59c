// SPDX-License-Identifier: MIT
#include "commands.h"

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

}  // namespace infocus::cli
