// SPDX-License-Identifier: MIT
/// @file commands.h
/// The CLI's subcommands. Each adds itself to the app and returns the function that runs it once
/// parsing succeeded; commands.cpp lists them all in one place.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

#include "infocus/analysis.h"
#include "infocus/depth_map.h"
#include "infocus/error.h"
#include "infocus/source.h"

namespace infocus::cli {

/// A registered subcommand and the code that runs it; run() returns the process exit status.
struct Command {
    CLI::App* app = nullptr;
    std::function<int()> run;
};

/// Adds every subcommand to @p app (the single registry of commands).
std::vector<Command> registerCommands(CLI::App& app);

/// Exit status for usage errors (bad options or values).
inline constexpr int kExitUsage = 2;
/// Exit status for runtime failures (device, file, data).
inline constexpr int kExitFailure = 1;

/// Prints "infocus COMMAND: MESSAGE" on stderr and returns the exit status for @p error's kind.
int reportError(const std::string& command, const Error& error);

/// Prints a usage error for @p command on stderr and returns kExitUsage.
int usageError(const std::string& command, const std::string& message);

/// Says once on stderr, as @p command, that frame @p a's edges look sharpened
/// (FrameAnalysis::sharpeningHalo at least kSharpenedHaloFraction), and why it matters;
/// @p warned remembers that it was said.
void warnIfSharpened(const std::string& command, const FrameAnalysis& a, bool& warned);

/// With --transfer auto (@p options.transferFromSource), says once on stderr, as @p command,
/// which transfer function the frames of @p source are decoded by and where it comes from, or
/// that the source names none and its grey levels are measured as they are.
void noteTransfer(const std::string& command, const SourceInfo& source,
                  const AnalysisOptions& options);

/// Checks a --frames value: a whole number ≥ @p least, read before it is converted to an
/// unsigned count (where "-1" would wrap to 2^64 − 1 and never stop).
CLI::Validator frameCount(uint64_t least = 0);

/// Checks a --seconds value: a number above @p lo and at most @p hi, with @p example in the
/// message (CLI11's own range check prints its bounds to the last digit of DBL_MAX).
CLI::Validator secondsIn(double lo, double hi, const std::string& example);

/// Adds --blur-floor and --min-confidence, the options of the depth map (`depth`, `report`),
/// filling @p options.
void addDepthMapOptions(CLI::App* app, DepthMapOptions& options);
/// What to say of depth-map options CLI11 let through (a NaN passes its range check, an
/// infinite floor its type); empty when they are fine.
std::string depthMapOptionsUsage(const DepthMapOptions& options);

// One entry point per command file (src/cli/cmd_NAME.cpp).
Command addAnalyzeCommand(CLI::App& app);
Command addBenchCommand(CLI::App& app);
Command addCheckCommand(CLI::App& app);
Command addDevicesCommand(CLI::App& app);
Command addDofCommand(CLI::App& app);
Command addDepthCommand(CLI::App& app);
Command addLiveCommand(CLI::App& app);
Command addRecordCommand(CLI::App& app);
Command addReportCommand(CLI::App& app);
Command addSweepCommand(CLI::App& app);
Command addStackCommand(CLI::App& app);

}  // namespace infocus::cli
